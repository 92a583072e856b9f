//! Guide bars as flexible cantilevers in modal coordinates (paper §3.2, floating frame with the
//! frame fixed at the clamped root, so no rigid motion): the lateral deflection in x and in y at
//! height z is u(z) = Σ φ_j(z)·q_j. Shapes and frequencies come from
//! `fem::cantilever_bar_modes` (mass-normalised, sampled at stations); a natural cubic spline
//! through the stations gives φ and φ' continuously, so the right-hand side stays smooth while a
//! bore edge slides along the bar (a piecewise-linear shape would put a kink into every step).

use crate::error::SeparationError;
use crate::fem::{BarModes, cantilever_bar_modes};
use crate::spec::Material;

/// One sampled function on uniform stations with its natural cubic spline moments.
#[derive(Debug, Clone)]
pub struct Spline {
    h: f64,
    y: Vec<f64>,
    /// Second derivatives at the stations.
    m: Vec<f64>,
}

impl Spline {
    /// Natural cubic spline on the uniform grid `0, h, 2h, …` (stations of `BarModes`).
    pub fn new(h: f64, y: Vec<f64>) -> Spline {
        let n = y.len();
        let mut m = vec![0.0; n];
        if n > 2 {
            // Tridiagonal system h/6·M[i-1] + 2h/3·M[i] + h/6·M[i+1] = Δ²y/h, M[0] = M[n-1] = 0.
            let k = n - 2;
            let mut c = vec![0.0; k];
            let mut d = vec![0.0; k];
            for i in 0..k {
                let rhs = (y[i + 2] - 2.0 * y[i + 1] + y[i]) / h * 6.0 / h;
                // Normalised: M[i-1] + 4 M[i] + M[i+1] = rhs.
                let (a, b) = (if i > 0 { 1.0 } else { 0.0 }, 4.0);
                let denom = b - a * if i > 0 { c[i - 1] } else { 0.0 };
                c[i] = 1.0 / denom;
                d[i] = (rhs - a * if i > 0 { d[i - 1] } else { 0.0 }) / denom;
            }
            for i in (0..k).rev() {
                let next = if i + 1 < k { m[i + 2] } else { 0.0 };
                m[i + 1] = d[i] - c[i] * next;
            }
        }
        Spline { h, y, m }
    }

    /// Value and slope at `x` (clamped to the sampled range).
    #[inline]
    pub fn eval(&self, x: f64) -> (f64, f64) {
        let n = self.y.len();
        let xmax = self.h * (n - 1) as f64;
        let x = x.clamp(0.0, xmax);
        let i = ((x / self.h) as usize).min(n - 2);
        let t = x - i as f64 * self.h;
        let h = self.h;
        let a = (h - t) / h;
        let b = t / h;
        let (m0, m1, y0, y1) = (self.m[i], self.m[i + 1], self.y[i], self.y[i + 1]);
        let v = a * y0 + b * y1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
        let d = (y1 - y0) / h + ((1.0 - 3.0 * a * a) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
        (v, d)
    }
}

/// The modal model of one guide bar (the same in x and y: a solid circular section).
#[derive(Debug, Clone)]
pub struct ModalBar {
    pub length_m: f64,
    /// Circular frequencies, rad/s.
    pub omega: Vec<f64>,
    pub damping_ratio: f64,
    pub shapes: Vec<Spline>,
    pub frequencies_hz: Vec<f64>,
    /// Station values and spline moments interleaved by mode, `[station * n_modes + mode]`,
    /// so one interval search serves every mode.
    y: Vec<f64>,
    m: Vec<f64>,
    h: f64,
    /// Bound of |φ_j| on each of `BINS` equal segments of the bar, `[mode * BINS + bin]`.
    bin_max: Vec<f64>,
}

/// Segments of the bar for the per-height deflection bound.
const BINS: usize = 32;

impl ModalBar {
    pub fn new(
        length_m: f64,
        diameter_m: f64,
        material: &Material,
        elements: usize,
        n_modes: usize,
        damping_ratio: f64,
    ) -> Result<ModalBar, SeparationError> {
        let modes: BarModes =
            cantilever_bar_modes(length_m, diameter_m, material, elements, n_modes)
                .map_err(|e| SeparationError::Invalid(format!("guide-bar modes: {e}")))?;
        if modes.shapes.len() < n_modes {
            return Err(SeparationError::Invalid(format!(
                "guide-bar modes: asked for {n_modes} modes, the bar model gave {}",
                modes.shapes.len()
            )));
        }
        let st = &modes.stations_m;
        let h = st[1] - st[0];
        // The spline assumes uniform stations; check rather than trust.
        for w in st.windows(2) {
            if ((w[1] - w[0]) - h).abs() > 1e-9 * length_m {
                return Err(SeparationError::Invalid(
                    "guide-bar modes: stations are not uniform".into(),
                ));
            }
        }
        let shapes: Vec<Spline> = modes
            .shapes
            .iter()
            .take(n_modes)
            .map(|s| Spline::new(h, s.clone()))
            .collect();
        let ns = st.len();
        let mut y = vec![0.0; ns * n_modes];
        let mut m = vec![0.0; ns * n_modes];
        for (j, sp) in shapes.iter().enumerate() {
            for k in 0..ns {
                y[k * n_modes + j] = sp.y[k];
                m[k * n_modes + j] = sp.m[k];
            }
        }
        // Per-segment bound of |φ|: sample the spline densely, then add 10% for what the
        // samples miss between them.
        let mut bin_max = vec![0.0; n_modes * BINS];
        for (j, sp) in shapes.iter().enumerate() {
            for b in 0..BINS {
                let (z0, z1) = (
                    length_m * b as f64 / BINS as f64,
                    length_m * (b + 1) as f64 / BINS as f64,
                );
                let mut mx = 0.0f64;
                for k in 0..=16 {
                    mx = mx.max(sp.eval(z0 + (z1 - z0) * k as f64 / 16.0).0.abs());
                }
                bin_max[j * BINS + b] = 1.1 * mx;
            }
        }
        Ok(ModalBar {
            length_m,
            omega: modes
                .frequencies_hz
                .iter()
                .take(n_modes)
                .map(|f| 2.0 * std::f64::consts::PI * f)
                .collect(),
            damping_ratio,
            shapes,
            frequencies_hz: modes.frequencies_hz.iter().take(n_modes).copied().collect(),
            y,
            m,
            h,
            bin_max,
        })
    }

    pub fn n_modes(&self) -> usize {
        self.omega.len()
    }

    /// φ_j(z) and φ_j'(z) of every mode into `phi`, `dphi` (one interval search for all).
    #[inline]
    pub fn eval_all(&self, z: f64, phi: &mut [f64], dphi: &mut [f64]) {
        let nm = self.omega.len();
        let ns = self.y.len() / nm;
        let h = self.h;
        let x = z.clamp(0.0, h * (ns - 1) as f64);
        let i = ((x / h) as usize).min(ns - 2);
        let t = x - i as f64 * h;
        let a = (h - t) / h;
        let b = t / h;
        let ca = (a * a * a - a) * h * h / 6.0;
        let cb = (b * b * b - b) * h * h / 6.0;
        let da = (1.0 - 3.0 * a * a) * h / 6.0;
        let db = (3.0 * b * b - 1.0) * h / 6.0;
        let (y0, y1) = (
            &self.y[i * nm..i * nm + nm],
            &self.y[(i + 1) * nm..(i + 1) * nm + nm],
        );
        let (m0, m1) = (
            &self.m[i * nm..i * nm + nm],
            &self.m[(i + 1) * nm..(i + 1) * nm + nm],
        );
        for j in 0..nm {
            phi[j] = a * y0[j] + b * y1[j] + ca * m0[j] + cb * m1[j];
            dphi[j] = (y1[j] - y0[j]) / h + da * m0[j] + db * m1[j];
        }
    }

    /// Bound of |φ_j| at height z, for every mode (cheap test that an edge cannot touch).
    #[inline]
    pub fn bound_at(&self, z: f64, out: &mut [f64]) {
        let b = ((z / self.length_m * BINS as f64).max(0.0) as usize).min(BINS - 1);
        for (j, o) in out.iter_mut().enumerate().take(self.omega.len()) {
            *o = self.bin_max[j * BINS + b];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spline_reproduces_a_cubic_interior_and_its_slope() {
        // A natural spline is exact for a straight line; for sin it converges as h².
        let h = 0.05;
        let y: Vec<f64> = (0..=40).map(|i| 3.0 * (i as f64 * h) - 1.0).collect();
        let s = Spline::new(h, y);
        let (v, d) = s.eval(1.234);
        assert!((v - (3.0 * 1.234 - 1.0)).abs() < 1e-12 && (d - 3.0).abs() < 1e-12);
        let y: Vec<f64> = (0..=40).map(|i| (i as f64 * h).sin()).collect();
        let s = Spline::new(h, y);
        let (v, d) = s.eval(1.0);
        assert!(
            (v - 1f64.sin()).abs() < 1e-5 && (d - 1f64.cos()).abs() < 1e-4,
            "{v} {d}"
        );
    }
}
