//! Guide bars as flexible cantilevers in modal coordinates (paper §3.2, floating frame with the
//! frame fixed at the clamped root, so no rigid motion): the lateral deflection in x and in y at
//! height z is u(z) = Σ φ_j(z)·q_j. Shapes and frequencies come from
//! [`super::bar_modes::cantilever_bar_modes`] (mass-normalised, sampled at stations); a natural cubic spline
//! through the stations gives φ and φ' continuously, so the right-hand side stays smooth while a
//! bore edge slides along the bar (a piecewise-linear shape would put a kink into every step).

use super::bar_modes::{BarModes, cantilever_bar_modes};
use crate::error::{Error, SeparationError};
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
    /// The spline as a cubic in the local coordinate t ∈ [0, h) of each interval, the
    /// coefficients of every mode side by side: `coef[(interval * 4 + power) * n_modes + mode]`.
    /// One index computation and three fused multiply-adds per mode, no search, no division.
    coef: Vec<f64>,
    h: f64,
    inv_h: f64,
    /// Stations − 1.
    intervals: usize,
    /// h · intervals: the sampled length.
    z_max: f64,
}

impl ModalBar {
    pub fn new(
        length_m: f64,
        diameter_m: f64,
        material: &Material,
        elements: usize,
        n_modes: usize,
        damping_ratio: f64,
    ) -> Result<ModalBar, Error> {
        // The FE and modal errors stay typed: they already name the node, DOF or pivot.
        let modes: BarModes =
            cantilever_bar_modes(length_m, diameter_m, material, elements, n_modes)?;
        if modes.shapes.len() < n_modes {
            return Err(SeparationError::Invalid(format!(
                "guide-bar modes: asked for {n_modes} modes, the bar model gave {}",
                modes.shapes.len()
            ))
            .into());
        }
        let st = &modes.stations_m;
        let h = st[1] - st[0];
        // The spline assumes uniform stations; check rather than trust.
        for w in st.windows(2) {
            if ((w[1] - w[0]) - h).abs() > 1e-9 * length_m {
                return Err(SeparationError::Invalid(
                    "guide-bar modes: stations are not uniform".into(),
                )
                .into());
            }
        }
        let shapes: Vec<Spline> = modes
            .shapes
            .iter()
            .take(n_modes)
            .map(|s| Spline::new(h, s.clone()))
            .collect();
        let intervals = st.len() - 1;
        let mut coef = vec![0.0; intervals * 4 * n_modes];
        for (j, sp) in shapes.iter().enumerate() {
            for i in 0..intervals {
                let (y0, y1, m0, m1) = (sp.y[i], sp.y[i + 1], sp.m[i], sp.m[i + 1]);
                let c = [
                    y0,
                    (y1 - y0) / h - h * (2.0 * m0 + m1) / 6.0,
                    0.5 * m0,
                    (m1 - m0) / (6.0 * h),
                ];
                for (p, cp) in c.iter().enumerate() {
                    coef[(i * 4 + p) * n_modes + j] = *cp;
                }
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
            coef,
            h,
            inv_h: 1.0 / h,
            intervals,
            z_max: h * intervals as f64,
        })
    }

    pub fn n_modes(&self) -> usize {
        self.omega.len()
    }

    /// φ_j(z) and φ_j'(z) of every mode into `phi`, `dphi`.
    #[inline]
    pub fn eval_all(&self, z: f64, phi: &mut [f64], dphi: &mut [f64]) {
        self.eval_phi(z, phi);
        self.eval_dphi(z, dphi);
    }

    /// The interval of height z (clamped to the bar) and the local coordinate in it.
    #[inline]
    fn interval(&self, z: f64) -> (usize, f64) {
        // `clamp` by hand: the same result for every z (NaN included), without its assertion
        // and the product, in the innermost call of the right-hand side.
        let x = if z < 0.0 {
            0.0
        } else if z > self.z_max {
            self.z_max
        } else {
            z
        };
        let i = ((x * self.inv_h) as usize).min(self.intervals - 1);
        (i, x - i as f64 * self.h)
    }

    /// φ_j(z) of every mode (the penetration needs no slope).
    #[inline]
    pub fn eval_phi(&self, z: f64, phi: &mut [f64]) {
        let nm = self.omega.len();
        let (i, t) = self.interval(z);
        let c = &self.coef[i * 4 * nm..(i + 1) * 4 * nm];
        let (c0, c) = c.split_at(nm);
        let (c1, c) = c.split_at(nm);
        let (c2, c3) = c.split_at(nm);
        for j in 0..nm {
            phi[j] = ((c3[j] * t + c2[j]) * t + c1[j]) * t + c0[j];
        }
    }

    /// φ_j'(z) of every mode.
    #[inline]
    pub fn eval_dphi(&self, z: f64, dphi: &mut [f64]) {
        let nm = self.omega.len();
        let (i, t) = self.interval(z);
        let c = &self.coef[(i * 4 + 1) * nm..(i + 1) * 4 * nm];
        let (c1, c) = c.split_at(nm);
        let (c2, c3) = c.split_at(nm);
        for j in 0..nm {
            dphi[j] = (3.0 * c3[j] * t + 2.0 * c2[j]) * t + c1[j];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial pieces of `ModalBar` are the spline of each mode, value and slope.
    #[test]
    fn modal_bar_pieces_match_the_spline() {
        let steel = Material {
            name: "steel".into(),
            youngs_modulus_pa: 200e9,
            poisson_ratio: 0.29,
            density_kg_m3: 7850.0,
            yield_strength_pa: None,
            ultimate_strength_pa: None,
        };
        let bar = ModalBar::new(3.85, 0.02, &steel, 12, 3, 0.01).unwrap();
        let (mut phi, mut dphi) = ([0.0; 3], [0.0; 3]);
        for k in 0..=700 {
            let z = -0.1 + 4.05 * k as f64 / 700.0;
            bar.eval_all(z, &mut phi, &mut dphi);
            for (j, sp) in bar.shapes.iter().enumerate() {
                let (v, d) = sp.eval(z);
                // Reference: the spline's own evaluation; round-off only (|φ| ≲ 1, |φ'| ≲ 10).
                assert!(
                    (phi[j] - v).abs() < 1e-12,
                    "z {z} mode {j}: {} vs {v}",
                    phi[j]
                );
                assert!(
                    (dphi[j] - d).abs() < 1e-11,
                    "z {z} mode {j}: {} vs {d}",
                    dphi[j]
                );
            }
        }
    }

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
