//! Event location within an accepted step: the crossing of each live event on the dense
//! output (Illinois false position), contacts hidden inside a step (a cubic Hermite test on
//! δ and δ̇), the earliest crossing, the re-take of the step to it, and the set of events
//! that happen at that instant.

use super::super::contact::ContactState;
use super::super::integrator::Dopri5;
use super::Sim;
use super::stepping::Stepper;
use crate::error::SeparationError;

/// Events located within this time of the earliest one in a step are processed together, s.
/// At the 0.01 m/s impact speeds of the reference scene an edge moves 1e-10 m in that time.
const SIMULTANEOUS_S: f64 = 1e-8;

impl Sim<'_> {
    /// Evaluates the events at the step end, locates the earliest crossing, re-takes the step
    /// to it and returns the events that happen there (empty when none crossed).
    pub(super) fn resolve_events(
        &mut self,
        st: &mut Stepper,
    ) -> Result<Vec<usize>, SeparationError> {
        self.events(&st.ig.y, &mut st.g1, &mut st.gd1);
        let t1 = st.ig.t;
        let Some((t_event, first)) = self.earliest_crossing(st) else {
            return Ok(Vec::new());
        };
        if t_event < t1 {
            let this = &*self;
            let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
            st.ig.retake(&mut f, t_event);
            if let Some(e) = self.non_finite(st.ig.t, &st.ig.y) {
                return Err(e);
            }
            self.events(&st.ig.y, &mut st.g1, &mut st.gd1);
        }
        Ok(self.events_at(st, t_event, first))
    }

    /// The earliest located crossing in the step (time, event), every located one kept in
    /// `st.located`.
    fn earliest_crossing(&mut self, st: &mut Stepper) -> Option<(f64, usize)> {
        let (t0, t1) = (st.ig.t_prev(), st.ig.t);
        let mut t_event = f64::INFINITY;
        let mut first = usize::MAX;
        st.located.clear();
        for idx in 0..self.n_events() {
            if self.left_the_bar(idx) {
                continue;
            }
            let (ga, gb) = (st.g0[idx], st.g1[idx]);
            let te = if self.crossed(idx, ga, gb) {
                Some(self.locate(&st.ig, idx, t0, t1, ga, gb, &mut st.ybuf))
            } else if self.may_hide_contact(idx, ga, gb) {
                let te = self.hidden_onset(st, idx, t0, t1);
                if te.is_some() {
                    self.transitions.hidden_onsets += 1;
                }
                te
            } else {
                None
            };
            if let Some(te) = te {
                st.located.push((idx, te));
                if te < t_event {
                    t_event = te;
                    first = idx;
                }
            }
        }
        t_event.is_finite().then_some((t_event, first))
    }

    /// Whether event `idx` belongs to an edge past the bar tip: it is never live (`crossed`,
    /// `may_hide_contact`), and the edges of the satellites that have left make up most of
    /// the events late in a run, so the loops skip them first.
    #[inline(always)]
    fn left_the_bar(&self, idx: usize) -> bool {
        // No `idx % n8`: an integer division per event and step costs more than the test.
        let n8 = 8 * self.n;
        let ei = if idx < n8 { idx } else { idx.wrapping_sub(n8) };
        idx < 2 * n8 && self.edges[ei].past_tip
    }

    /// Whether event `idx` is the δ of a free edge, apart at both ends of the step: a short
    /// pulse can open and close between two step ends (a free-flight step is far longer than
    /// a contact), so such an edge is looked at inside the step.
    fn may_hide_contact(&self, idx: usize, ga: f64, gb: f64) -> bool {
        idx < 8 * self.n
            && ga < 0.0
            && gb < 0.0
            && !self.edges[idx].past_tip
            && !matches!(
                self.edges[idx].state,
                ContactState::Collision | ContactState::Contact
            )
    }

    /// The onset of a contact hidden inside the step (t0, t1] of edge `idx`, when the Hermite
    /// interpolant's maximum is positive and the dense output confirms δ ≥ 0 there.
    fn hidden_onset(&self, st: &mut Stepper, idx: usize, t0: f64, t1: f64) -> Option<f64> {
        let (g0, g1) = (st.g0[idx], st.g1[idx]);
        let th = hidden_contact(g0, st.gd0[idx], g1, st.gd1[idx], t1 - t0)?;
        let tm = t0 + th * (t1 - t0);
        for part in self.event_state_parts(idx) {
            st.ig.dense_part(tm, &mut st.ybuf, part);
        }
        let gm = self.event_value_at(&st.ybuf, idx);
        (gm >= 0.0).then(|| self.locate(&st.ig, idx, t0, tm, g0, gm, &mut st.ybuf))
    }

    /// Every event whose sign has crossed at the event point, and every event located within
    /// `SIMULTANEOUS_S` of the earliest one: symmetric edges that touch at the same instant
    /// must be latched at the same state, not one after another with slivers of steps in
    /// between (which breaks the symmetry the physics has).
    fn events_at(&self, st: &Stepper, t_event: f64, first: usize) -> Vec<usize> {
        let mut events_at_t: Vec<usize> = Vec::new();
        for idx in 0..self.n_events() {
            if self.left_the_bar(idx) {
                continue;
            }
            let near = st
                .located
                .iter()
                .any(|&(i, te)| i == idx && te <= t_event + SIMULTANEOUS_S);
            if near || self.crossed(idx, st.g0[idx], st.g1[idx]) {
                events_at_t.push(idx);
            }
        }
        if events_at_t.is_empty() {
            events_at_t.push(first);
        }
        events_at_t
    }

    /// Root of event `idx` in (t0, t1] on the dense output (Illinois false position); returns
    /// the end of the final bracket on the crossed side.
    #[allow(clippy::too_many_arguments)]
    fn locate(
        &self,
        ig: &Dopri5,
        idx: usize,
        t0: f64,
        t1: f64,
        g0: f64,
        g1: f64,
        buf: &mut [f64],
    ) -> f64 {
        let (mut a, mut b, mut ga, mut gb) = (t0, t1, g0, g1);
        let tol = 1e-13 * t1.abs().max(1.0);
        let mut side = 0i32;
        for _ in 0..200 {
            if b - a <= tol {
                break;
            }
            let mut t = (a * gb - b * ga) / (gb - ga);
            if !(t > a && t < b) {
                t = 0.5 * (a + b);
            }
            for part in self.event_state_parts(idx) {
                ig.dense_part(t, buf, part);
            }
            let g = self.event_value_at(buf, idx);
            let crossed_here = if g0 < 0.0 { g >= 0.0 } else { g <= 0.0 };
            if crossed_here {
                b = t;
                gb = g;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            } else {
                a = t;
                ga = g;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            }
        }
        b
    }
}

/// A contact hidden inside a step: δ < 0 at both ends, but the cubic Hermite interpolant of
/// δ (values and rates at both ends) rises above zero in between. Returns the θ ∈ (0, 1)
/// of the interpolant's maximum when it is positive.
fn hidden_contact(g0: f64, d0: f64, g1: f64, d1: f64, h: f64) -> Option<f64> {
    if stays_below_zero(g0, d0, g1, d1, h) {
        return None;
    }
    let a = 2.0 * g0 + h * d0 - 2.0 * g1 + h * d1;
    let b = -3.0 * g0 - 2.0 * h * d0 + 3.0 * g1 - h * d1;
    let c = h * d0;
    let p = |t: f64| ((a * t + b) * t + c) * t + g0;
    // Roots of p' = 3a θ² + 2b θ + c.
    let mut cands = [f64::NAN; 2];
    if a.abs() < 1e-300 {
        if b.abs() > 1e-300 {
            cands[0] = -c / (2.0 * b);
        }
    } else {
        let disc = 4.0 * b * b - 12.0 * a * c;
        if disc >= 0.0 {
            let sq = disc.sqrt();
            cands[0] = (-2.0 * b + sq) / (6.0 * a);
            cands[1] = (-2.0 * b - sq) / (6.0 * a);
        }
    }
    cands
        .into_iter()
        .filter(|t| *t > 0.0 && *t < 1.0 && p(*t) > 0.0)
        .reduce(f64::min)
}

/// Whether the Hermite cubic of [`hidden_contact`] certainly stays below zero on [0, 1], by
/// a bound that needs no root: in the Hermite basis p = H00 g0 + H01 g1 + H10 h d0 + H11 h d1
/// with H00 + H01 = 1 (both ≥ 0), 0 ≤ H10 ≤ 4/27 and −4/27 ≤ H11 ≤ 0, so
/// p ≤ max(g0, g1) + 4/27 h (max(d0, 0) + max(−d1, 0)). Most free edges recede or drift
/// slowly: the bound settles them without the square root. The margin (1e-12 of the terms'
/// size, far above the roundings of the cubic's evaluation) keeps every edge whose cubic the
/// full test could find positive.
#[inline(always)]
fn stays_below_zero(g0: f64, d0: f64, g1: f64, d1: f64, h: f64) -> bool {
    let rise = 4.0 / 27.0 * h * (d0.max(0.0) + (-d1).max(0.0));
    let size = g0.abs() + g1.abs() + h * (d0.abs() + d1.abs());
    g0.max(g1) + rise + 1e-12 * size < 0.0
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// δ(θ) = −0.1 + θ(1 − θ) over a unit step: values −0.1 at both ends, rates +1 and −1;
    /// its maximum 0.15 sits at θ = ½ (by hand), and a parabola is its own Hermite cubic.
    #[test]
    fn a_pulse_between_two_negative_ends_is_found_at_its_peak() {
        let th = hidden_contact(-0.1, 1.0, -0.1, -1.0, 1.0).expect("the pulse rises above 0");
        assert!((th - 0.5).abs() < 1e-15, "{th}");
        // A pulse that stays below zero (peak −0.05) is no contact.
        assert_eq!(hidden_contact(-0.3, 1.0, -0.3, -1.0, 1.0), None);
    }

    /// The root-free bound never settles a cubic that rises above zero: over a grid of end
    /// values and rates, whenever it says 'below', the cubic sampled finely stays below (the
    /// bound is 4/27 h per unit rate: a pulse of peak −0.05 above passes, one of peak +0.15
    /// does not).
    #[test]
    fn the_root_free_bound_only_settles_cubics_below_zero() {
        assert!(stays_below_zero(-0.3, 1.0, -0.3, -1.0, 1.0) == (-0.3 + 8.0 / 27.0 < 0.0));
        assert!(!stays_below_zero(-0.1, 1.0, -0.1, -1.0, 1.0));
        let vals = [-1.0, -0.3, -0.1, -1e-3, -1e-9];
        let rates = [-5.0, -1.0, -0.1, 0.0, 0.1, 1.0, 5.0];
        for &g0 in &vals {
            for &g1 in &vals {
                for &d0 in &rates {
                    for &d1 in &rates {
                        if !stays_below_zero(g0, d0, g1, d1, 1.0) {
                            continue;
                        }
                        let (a, b, c) = (
                            2.0 * g0 + d0 - 2.0 * g1 + d1,
                            -3.0 * g0 - 2.0 * d0 + 3.0 * g1 - d1,
                            d0,
                        );
                        let max = (0..=1000)
                            .map(|i| {
                                let t = i as f64 / 1000.0;
                                ((a * t + b) * t + c) * t + g0
                            })
                            .fold(f64::NEG_INFINITY, f64::max);
                        assert!(max < 0.0, "{g0} {d0} {g1} {d1}: {max}");
                        assert_eq!(hidden_contact(g0, d0, g1, d1, 1.0), None);
                    }
                }
            }
        }
    }

    /// Satellite 1 free, rising at 0.2 m/s with nothing acting on it: its top edges pass the
    /// bar tip at t = (1.5 − 1.2) / 0.2 = 1.5 s, by hand. The located time must match to the
    /// locator's bracket (1e-13 s) plus the dense output's error on a straight line (exact up
    /// to roundings).
    #[test]
    fn a_tip_crossing_is_located_at_its_closed_form_time() {
        let mut m = fixture::two_satellites();
        m.satellites[0].initial_velocity_m_s = [0.0, 0.0, 0.2];
        m.max_step_s = 2.0;
        let mut sim = Sim::new(&m);
        let mut st = sim.start();
        // Step until the step that passes the tip, the event values kept at each step start.
        loop {
            let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| sim.rhs(y, dy);
            st.ig.step(&mut f, 10.0).expect("free flight steps");
            if st.ig.t > 1.5 {
                break;
            }
            sim.events(&st.ig.y, &mut st.g0, &mut st.gd0);
        }
        let events = sim.resolve_events(&mut st).expect("finite");
        // All four top edges (odd edges of satellite 1) at once.
        assert_eq!(events, vec![16 + 1, 16 + 3, 16 + 5, 16 + 7]);
        assert!((st.ig.t - 1.5).abs() < 1e-12, "{}", st.ig.t);
    }
}
