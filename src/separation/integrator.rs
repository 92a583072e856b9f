//! Adaptive Dormand–Prince 5(4) (Hairer–Nørsett–Wanner, "DOPRI5") with FSAL, PI step-size
//! control, the 4th-order continuous extension (dense output) and an exact "retake" of the last
//! step to a located event time.
//!
//! Why hand-written: the separation model changes discrete state at events (an impact speed is
//! latched at contact onset, a spring reaches its end stop, a bore edge leaves the bar tip), and
//! each change must land exactly on the event, with the right-hand side smooth inside every
//! step. That needs the step loop in our hands: accept a step, locate the root of an event
//! function on the dense output, re-take the step to that time, change the discrete state,
//! refresh the FSAL stage. `ode_solvers::Dopri5` has dense output but no event location or
//! state change hook; `diffsol` targets implicit (BDF/SDIRK) solvers for large stiff systems.
//! The tableau is the published one (Hairer, Nørsett & Wanner, Solving ODE I, Table 5.2;
//! dense-output coefficients from their `dopri5.f`).
//!
//! Inputs: a right-hand side closure `f(t, y, dy)`, relative tolerance and an absolute
//! tolerance per component (the caller knows the physical scales), and a largest step.

use std::ops::Range;

const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Work counters of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Stats {
    pub steps: usize,
    pub rejected: usize,
    pub rhs_evals: usize,
}

/// Why a step could not be taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepFailure {
    /// The step underflowed the round-off floor at time t with step h.
    TooSmall { t: f64, h: f64 },
    /// Every trial step from t, down to the round-off floor, produced a non-finite stage;
    /// `index` is the first state component that went non-finite.
    NonFinite { t: f64, index: usize },
}

pub struct Dopri5 {
    pub rtol: f64,
    pub atol: Vec<f64>,
    pub h_max: f64,
    pub t: f64,
    pub y: Vec<f64>,
    /// f(t, y): the FSAL stage.
    f0: Vec<f64>,
    /// Proposed next step.
    h: f64,
    t_prev: f64,
    y_prev: Vec<f64>,
    k: [Vec<f64>; 7],
    /// Dense-output coefficients of the last step.
    rcont: [Vec<f64>; 5],
    h_last: f64,
    facold: f64,
    ytmp: Vec<f64>,
    /// Squared weighted errors of the last attempt, per component.
    err_sq: Vec<f64>,
    /// The components the stage, error and dense-output loops run over, ascending (all by
    /// default; see [`Dopri5::set_active`]).
    active: Vec<Range<usize>>,
    pub stats: Stats,
}

impl Dopri5 {
    /// Starts at (t, y) and evaluates f there.
    pub fn new<F: FnMut(f64, &[f64], &mut [f64])>(
        f: &mut F,
        t: f64,
        y: Vec<f64>,
        rtol: f64,
        atol: Vec<f64>,
        h_max: f64,
    ) -> Dopri5 {
        let n = y.len();
        let z = || vec![0.0; n];
        let mut s = Dopri5 {
            rtol,
            atol,
            h_max,
            t,
            y_prev: y.clone(),
            y,
            f0: z(),
            h: 0.0,
            t_prev: t,
            k: [z(), z(), z(), z(), z(), z(), z()],
            rcont: [z(), z(), z(), z(), z()],
            h_last: 0.0,
            facold: 1e-4,
            ytmp: z(),
            err_sq: z(),
            active: std::iter::once(0..n).collect(),
            stats: Stats::default(),
        };
        s.refresh(f);
        s.h = s.initial_step(f);
        s
    }

    /// Re-evaluates the FSAL stage after a change of discrete state (or of `y` by the caller).
    pub fn refresh<F: FnMut(f64, &[f64], &mut [f64])>(&mut self, f: &mut F) {
        f(self.t, &self.y, &mut self.f0);
        self.stats.rhs_evals += 1;
    }

    /// Restricts the stage, error and dense-output loops to the components in `active`
    /// (ascending, disjoint). The caller guarantees that every other component has a zero
    /// derivative from now until the next call (a body that does not move): then a step
    /// leaves it exactly as it is, its error term is zero and its dense output its value,
    /// which is what the loops would compute, so skipping it changes no bit. Its value is
    /// set in every buffer the steps rotate, and its dense output to that constant.
    pub fn set_active(&mut self, active: Vec<Range<usize>>) {
        let mut next = 0;
        for r in active
            .iter()
            .chain(std::iter::once(&(self.y.len()..self.y.len())))
        {
            for i in next..r.start {
                let v = self.y[i];
                (self.y_prev[i], self.ytmp[i], self.err_sq[i]) = (v, v, 0.0);
                self.rcont[0][i] = v;
                for c in &mut self.rcont[1..] {
                    c[i] = 0.0;
                }
            }
            next = r.end;
        }
        self.active = active;
    }

    /// Previous accepted time (start of the last step).
    pub fn t_prev(&self) -> f64 {
        self.t_prev
    }

    /// The FSAL derivative f(t, y) at the current point.
    pub fn derivative(&self) -> &[f64] {
        &self.f0
    }

    fn wnorm(&self, v: &[f64], ya: &[f64], yb: &[f64]) -> f64 {
        let mut s = 0.0;
        for i in 0..v.len() {
            let sc = self.atol[i] + self.rtol * ya[i].abs().max(yb[i].abs());
            let r = v[i] / sc;
            s += r * r;
        }
        (s / v.len() as f64).sqrt()
    }

    /// Hairer's starting-step heuristic (dopri5.f `HINIT`).
    fn initial_step<F: FnMut(f64, &[f64], &mut [f64])>(&mut self, f: &mut F) -> f64 {
        let d0 = self.wnorm(&self.y, &self.y, &self.y);
        let d1 = self.wnorm(&self.f0, &self.y, &self.y);
        let mut h = if d0 < 1e-10 || d1 < 1e-10 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        h = h.min(self.h_max);
        for i in 0..self.y.len() {
            self.ytmp[i] = self.y[i] + h * self.f0[i];
        }
        let mut f1 = vec![0.0; self.y.len()];
        f(self.t + h, &self.ytmp, &mut f1);
        self.stats.rhs_evals += 1;
        for (a, b) in f1.iter_mut().zip(&self.f0) {
            *a -= b;
        }
        let d2 = self.wnorm(&f1, &self.y, &self.y) / h;
        let dm = d1.max(d2);
        let h1 = if dm <= 1e-15 {
            (h * 1e-3).max(1e-6)
        } else {
            (0.01 / dm).powf(0.2)
        };
        (100.0 * h).min(h1).min(self.h_max)
    }

    /// Computes the stages of a step of size `h` from (t, y) into `k` and the 5th-order result
    /// into `ytmp`; returns the weighted error estimate. The loops run over the active
    /// components only (see [`Self::set_active`]).
    fn attempt<F: FnMut(f64, &[f64], &mut [f64])>(&mut self, f: &mut F, h: f64) -> f64 {
        let n = self.y.len();
        let t = self.t;
        self.k[0].copy_from_slice(&self.f0);
        let y = &self.y[..n];
        let mut yt = std::mem::take(&mut self.ytmp);
        let active = &self.active;
        let [k0, k1, k2, k3, k4, k5, k6] = &mut self.k;
        // Every slice cut to the range so that the loops compile without bounds checks (and
        // vectorise); each element is the same expression as in dopri5.f.
        for r in active {
            let (yt, y, k0) = (&mut yt[r.clone()], &y[r.clone()], &k0[r.clone()]);
            for i in 0..yt.len() {
                yt[i] = y[i] + h * A21 * k0[i];
            }
        }
        f(t + C2 * h, &yt, k1);
        for r in active {
            let (yt, y, k0, k1) = (
                &mut yt[r.clone()],
                &y[r.clone()],
                &k0[r.clone()],
                &k1[r.clone()],
            );
            for i in 0..yt.len() {
                yt[i] = y[i] + h * (A31 * k0[i] + A32 * k1[i]);
            }
        }
        f(t + C3 * h, &yt, k2);
        for r in active {
            let (yt, y) = (&mut yt[r.clone()], &y[r.clone()]);
            let (k0, k1, k2) = (&k0[r.clone()], &k1[r.clone()], &k2[r.clone()]);
            for i in 0..yt.len() {
                yt[i] = y[i] + h * (A41 * k0[i] + A42 * k1[i] + A43 * k2[i]);
            }
        }
        f(t + C4 * h, &yt, k3);
        for r in active {
            let (yt, y) = (&mut yt[r.clone()], &y[r.clone()]);
            let (k0, k1, k2, k3) = (
                &k0[r.clone()],
                &k1[r.clone()],
                &k2[r.clone()],
                &k3[r.clone()],
            );
            for i in 0..yt.len() {
                yt[i] = y[i] + h * (A51 * k0[i] + A52 * k1[i] + A53 * k2[i] + A54 * k3[i]);
            }
        }
        f(t + C5 * h, &yt, k4);
        for r in active {
            let (yt, y) = (&mut yt[r.clone()], &y[r.clone()]);
            let (k0, k1, k2) = (&k0[r.clone()], &k1[r.clone()], &k2[r.clone()]);
            let (k3, k4) = (&k3[r.clone()], &k4[r.clone()]);
            for i in 0..yt.len() {
                yt[i] = y[i]
                    + h * (A61 * k0[i] + A62 * k1[i] + A63 * k2[i] + A64 * k3[i] + A65 * k4[i]);
            }
        }
        f(t + h, &yt, k5);
        for r in active {
            let (yt, y) = (&mut yt[r.clone()], &y[r.clone()]);
            let (k0, k2, k3) = (&k0[r.clone()], &k2[r.clone()], &k3[r.clone()]);
            let (k4, k5) = (&k4[r.clone()], &k5[r.clone()]);
            for i in 0..yt.len() {
                yt[i] = y[i]
                    + h * (A71 * k0[i] + A73 * k2[i] + A74 * k3[i] + A75 * k4[i] + A76 * k5[i]);
            }
        }
        f(t + h, &yt, k6);
        self.stats.rhs_evals += 6;
        // The squares first (a loop without a carried dependency, so the divisions
        // vectorise), then their sum in the same order as before: the inactive components'
        // squares are zero, and adding +0 to a sum of squares changes no bit.
        let mut s = 0.0;
        for r in active {
            let (yt, y, atol) = (&yt[r.clone()], &y[r.clone()], &self.atol[r.clone()]);
            let (k0, k2, k3) = (&k0[r.clone()], &k2[r.clone()], &k3[r.clone()]);
            let (k4, k5, k6) = (&k4[r.clone()], &k5[r.clone()], &k6[r.clone()]);
            let sq = &mut self.err_sq[r.clone()];
            for i in 0..sq.len() {
                let e = h
                    * (E1 * k0[i] + E3 * k2[i] + E4 * k3[i] + E5 * k4[i] + E6 * k5[i] + E7 * k6[i]);
                let sc = atol[i] + self.rtol * y[i].abs().max(yt[i].abs());
                let r = e / sc;
                sq[i] = r * r;
            }
            for v in sq.iter() {
                s += v;
            }
        }
        self.ytmp = yt;
        (s / n as f64).sqrt()
    }

    /// Moves to the end of an attempted step of size h and builds the dense output (of the
    /// active components: the others keep their constant one).
    fn commit(&mut self, h: f64) {
        for r in &self.active {
            let (y, yt) = (&self.y[r.clone()], &self.ytmp[r.clone()]);
            let [k0, _, k2, k3, k4, k5, k6] = &self.k;
            let (k0, k2, k3) = (&k0[r.clone()], &k2[r.clone()], &k3[r.clone()]);
            let (k4, k5, k6) = (&k4[r.clone()], &k5[r.clone()], &k6[r.clone()]);
            let [r0, r1, r2, r3, r4] = &mut self.rcont;
            let (r0, r1, r2) = (&mut r0[r.clone()], &mut r1[r.clone()], &mut r2[r.clone()]);
            let (r3, r4) = (&mut r3[r.clone()], &mut r4[r.clone()]);
            for i in 0..y.len() {
                let y0 = y[i];
                let y1 = yt[i];
                let dy = y1 - y0;
                let bspl = h * k0[i] - dy;
                r0[i] = y0;
                r1[i] = dy;
                r2[i] = bspl;
                r3[i] = dy - h * k6[i] - bspl;
                r4[i] = h
                    * (D1 * k0[i] + D3 * k2[i] + D4 * k3[i] + D5 * k4[i] + D6 * k5[i] + D7 * k6[i]);
            }
        }
        // Buffer swaps, not copies: `ytmp` and stage 6 are scratch until the next attempt.
        std::mem::swap(&mut self.y_prev, &mut self.y);
        self.t_prev = self.t;
        std::mem::swap(&mut self.y, &mut self.ytmp);
        std::mem::swap(&mut self.f0, &mut self.k[6]);
        self.t += h;
        self.h_last = h;
        self.stats.steps += 1;
    }

    /// Takes one accepted step, never past `t_limit`.
    pub fn step<F: FnMut(f64, &[f64], &mut [f64])>(
        &mut self,
        f: &mut F,
        t_limit: f64,
    ) -> Result<(), StepFailure> {
        const SAFE: f64 = 0.9;
        const BETA: f64 = 0.04;
        const EXPO1: f64 = 0.2 - BETA * 0.75;
        let mut h = self.h.min(self.h_max);
        let mut last = false;
        if self.t + h >= t_limit - 1e-12 * t_limit.abs().max(1.0) {
            h = t_limit - self.t;
            last = true;
        }
        let mut rejected_once = false;
        loop {
            if h.abs() <= 1e-14 * self.t.abs().max(1.0) {
                if let Some(index) = self.non_finite_stage() {
                    return Err(StepFailure::NonFinite { t: self.t, index });
                }
                return Err(StepFailure::TooSmall { t: self.t, h });
            }
            let err = self.attempt(f, h);
            let fac11 = err.powf(EXPO1);
            if err <= 1.0 && err.is_finite() {
                // PI control (Gustafsson, as in dopri5.f).
                let mut fac = fac11 / self.facold.powf(BETA);
                fac = (fac / SAFE).clamp(1.0 / 10.0, 1.0 / 0.2);
                let mut hnew = h / fac;
                if rejected_once {
                    hnew = hnew.min(h);
                }
                self.facold = err.max(1e-4);
                self.commit(h);
                if last {
                    self.t = t_limit;
                }
                // Keep the proposal of the free step even when this one was cut at a limit.
                if !last || hnew > self.h {
                    self.h = hnew.min(self.h_max);
                }
                return Ok(());
            }
            self.stats.rejected += 1;
            rejected_once = true;
            last = false;
            // dopri5.f: h / min(1/fac1, fac11/safe) with fac1 = 0.2; a non-finite error
            // (an overshoot into a stiff contact) shrinks by the largest factor.
            let shrink = if err.is_finite() {
                (fac11 / SAFE).min(5.0)
            } else {
                5.0
            };
            h /= shrink;
        }
    }

    /// Caps the next proposed step (the caller knows a scale the error estimate misjudges).
    pub fn limit_next_step(&mut self, h: f64) {
        self.h = self.h.min(h);
    }

    /// The first component that is non-finite in the last trial's stages or result.
    fn non_finite_stage(&self) -> Option<usize> {
        (0..self.y.len())
            .find(|&i| !self.ytmp[i].is_finite() || self.k.iter().any(|k| !k[i].is_finite()))
    }

    /// The dense output at `t` in the last step [t_prev, t].
    pub fn dense(&self, t: f64, out: &mut [f64]) {
        let h = self.h_last;
        if h == 0.0 {
            out.copy_from_slice(&self.y);
            return;
        }
        let th = (t - self.t_prev) / h;
        let th1 = 1.0 - th;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.rcont[0][i]
                + th * (self.rcont[1][i]
                    + th1 * (self.rcont[2][i] + th * (self.rcont[3][i] + th1 * self.rcont[4][i])));
        }
    }

    /// The dense output at `t` of the components in `range` only (an event that reads a few
    /// bodies needs no more); each component is the same expression as in [`Self::dense`].
    pub fn dense_part(&self, t: f64, out: &mut [f64], range: std::ops::Range<usize>) {
        let h = self.h_last;
        if h == 0.0 {
            out[range.clone()].copy_from_slice(&self.y[range]);
            return;
        }
        let th = (t - self.t_prev) / h;
        let th1 = 1.0 - th;
        let [r0, r1, r2, r3, r4] = &self.rcont;
        let (r0, r1, r2, r3, r4) = (
            &r0[range.clone()],
            &r1[range.clone()],
            &r2[range.clone()],
            &r3[range.clone()],
            &r4[range.clone()],
        );
        for (i, o) in out[range].iter_mut().enumerate() {
            *o = r0[i] + th * (r1[i] + th1 * (r2[i] + th * (r3[i] + th1 * r4[i])));
        }
    }

    /// Replaces the last accepted step by an exact step from its start to `t_target`
    /// (t_prev < t_target ≤ t): the 5th-order solution at an event, not the interpolant.
    pub fn retake<F: FnMut(f64, &[f64], &mut [f64])>(&mut self, f: &mut F, t_target: f64) {
        let h = t_target - self.t_prev;
        self.t = self.t_prev;
        self.y.copy_from_slice(&self.y_prev);
        self.f0.copy_from_slice(&self.k[0]);
        self.stats.steps -= 1;
        let _ = self.attempt(f, h);
        self.commit(h);
        self.t = t_target;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = -y, y(0) = 1 → e^{-t}; and the harmonic oscillator's energy.
    #[test]
    fn exponential_decay_to_tolerance_and_dense_output() {
        let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| dy[0] = -y[0];
        let mut s = Dopri5::new(&mut f, 0.0, vec![1.0], 1e-10, vec![1e-12], 1.0);
        while s.t < 2.0 {
            s.step(&mut f, 2.0).unwrap();
            let mut o = [0.0];
            let tm = 0.5 * (s.t_prev() + s.t);
            s.dense(tm, &mut o);
            assert!((o[0] - (-tm).exp()).abs() < 1e-8, "dense at {tm}");
        }
        assert_eq!(s.t, 2.0);
        assert!((s.y[0] - (-2.0f64).exp()).abs() < 1e-9);
        // Retake to an interior time gives the exact-step value there.
        let t_mid = 0.5 * (s.t_prev() + 2.0);
        s.retake(&mut f, t_mid);
        assert!((s.y[0] - (-t_mid).exp()).abs() < 1e-9);
    }

    /// A component with a zero derivative left out of the loops (`set_active`): the others
    /// step bit for bit as with every component active, it keeps its value, and its dense
    /// output is that value.
    #[test]
    fn an_inactive_component_changes_no_bit_of_the_others() {
        let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[2];
            dy[1] = 0.0;
            dy[2] = -y[0];
        };
        let y0 = vec![1.0, 0.7, 0.0];
        let mut all = Dopri5::new(&mut f, 0.0, y0.clone(), 1e-8, vec![1e-10; 3], 0.1);
        let mut part = Dopri5::new(&mut f, 0.0, y0, 1e-8, vec![1e-10; 3], 0.1);
        part.set_active(vec![0..1, 2..3]);
        while all.t < 3.0 {
            all.step(&mut f, 3.0).unwrap();
            part.step(&mut f, 3.0).unwrap();
            assert_eq!((all.t, &all.y), (part.t, &part.y));
            let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
            let tm = 0.3 * all.t_prev() + 0.7 * all.t;
            all.dense(tm, &mut a);
            part.dense(tm, &mut b);
            assert_eq!(a, b);
        }
        assert_eq!(part.y[1], 0.7);
    }
}
