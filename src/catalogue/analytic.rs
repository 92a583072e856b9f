//! Analytic and published answers to the catalogue's problems, each with its source.

use std::f64::consts::PI;

/// βL of the first four bending modes of a clamped-free Euler-Bernoulli beam (roots of
/// cos βL · cosh βL = −1; e.g. Blevins, *Formulas for Natural Frequency and Mode Shape*,
/// table 8-1).
pub const CANTILEVER_BETA_L: [f64; 4] = [
    1.875104068711961,
    4.694091132974175,
    7.854757438237613,
    10.995540734875467,
];

/// The first four bending frequencies of the [`CANTILEVER`](super::CANTILEVER) scene (steel,
/// 20×20 mm, 1 m): f = (βL)²/(2πL²)·√(EI/ρA), about 16.710, 104.722, 293.224 and 574.602 Hz.
/// Each comes twice in the FE model, once per bending plane.
pub fn cantilever_frequencies_hz() -> [f64; 4] {
    let (e, rho, a, i) = (210e9, 7850.0, 4e-4, 0.02f64.powi(4) / 12.0);
    CANTILEVER_BETA_L.map(|bl| bl * bl / (2.0 * PI) * (e * i / (rho * a)).sqrt())
}

/// NAFEMS R0015 test FV5 (deep simply supported beam) targets of the first nine modes,
/// Timoshenko theory. The flexural modes come in pairs, one per bending plane.
pub const NAFEMS_FV5_HZ: [f64; 9] = [
    42.65, 42.65, 71.20, 125.00, 148.15, 148.15, 213.61, 283.47, 283.47,
];

/// Natural frequency of the [`SDOF_BASE`](super::SDOF_BASE) oscillator.
pub const SDOF_NATURAL_HZ: f64 = 100.0;
/// Viscous damping ratio of the [`SDOF_BASE`](super::SDOF_BASE) oscillator.
pub const SDOF_DAMPING_RATIO: f64 = 0.05;

/// |T|² of the absolute acceleration of the base-driven SDOF at `f` Hz (e.g. Harris' Shock
/// and Vibration Handbook, ch. 2, eq. 2.30).
pub fn sdof_transmissibility_squared(f: f64) -> f64 {
    let r = f / SDOF_NATURAL_HZ;
    let c = 2.0 * SDOF_DAMPING_RATIO * r;
    (1.0 + c * c) / ((1.0 - r * r).powi(2) + c * c)
}

/// A 3-DOF chain for the modal-identification checks: masses 2, 1, 1.5 kg; springs
/// ground–1 2e5 N/m, 1–2 1e5 N/m, 2–3 1.5e5 N/m; modal (proportional) damping 1 %, 2 %,
/// 1.5 %; force at mass 1, acceleration of the three masses. Its accelerance is exact:
/// H_o(ω) = −ω² Σ_r φ_o,r φ_1,r / (ω_r² − ω² + 2jζ_r ω_r ω), φ mass-normalised.
pub struct ThreeDof {
    /// Undamped natural frequencies, Hz, ascending.
    pub frequencies_hz: [f64; 3],
    pub damping: [f64; 3],
    /// `shapes[r][o]`: mass-normalised mode r at mass o.
    pub shapes: [[f64; 3]; 3],
}

pub fn three_dof() -> ThreeDof {
    let m = [2.0, 1.0, 1.5];
    let (k1, k2, k3) = (2e5, 1e5, 1.5e5);
    let k = nalgebra::Matrix3::new(k1 + k2, -k2, 0.0, -k2, k2 + k3, -k3, 0.0, -k3, k3);
    // Symmetric form M^-1/2 K M^-1/2, then φ = M^-1/2 v.
    let s = nalgebra::Vector3::from_fn(|i, _| 1.0 / f64::sqrt(m[i]));
    let a = nalgebra::Matrix3::from_fn(|i, j| s[i] * k[(i, j)] * s[j]);
    let eig = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..3).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let frequencies_hz: Vec<f64> = order
        .iter()
        .map(|&r| eig.eigenvalues[r].sqrt() / (2.0 * PI))
        .collect();
    let shapes: Vec<[f64; 3]> = order
        .iter()
        .map(|&r| [0, 1, 2].map(|o| s[o] * eig.eigenvectors[(o, r)]))
        .collect();
    ThreeDof {
        frequencies_hz: [frequencies_hz[0], frequencies_hz[1], frequencies_hz[2]],
        damping: [0.01, 0.02, 0.015],
        shapes: [shapes[0], shapes[1], shapes[2]],
    }
}

impl ThreeDof {
    /// The accelerances on 0–200 Hz at 0.25 Hz lines as an EMA input, each line with a complex
    /// error of up to `noise`·|H| per part (seed 7), shared by the EMA tests and bench.
    pub fn frf_set(&self, noise: f64) -> crate::signal::ema::FrfSet {
        use rand::{RngExt, SeedableRng};
        use realfft::num_complex::Complex64;
        let freqs: Vec<f64> = (0..=800).map(|k| k as f64 * 0.25).collect();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let h = self
            .accelerance(&freqs)
            .into_iter()
            .map(|ho| {
                ho.into_iter()
                    .map(|(re, im)| {
                        let z = Complex64::new(re, im);
                        let n =
                            Complex64::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
                        z + z.norm() * noise * 2.0 * n
                    })
                    .collect()
            })
            .collect();
        crate::signal::ema::FrfSet {
            freqs,
            channels: vec!["m1".into(), "m2".into(), "m3".into()],
            h,
        }
    }

    /// Accelerance (m/s² per N) of masses 1..3 to a force at mass 1: `[o][k]` as (re, im).
    pub fn accelerance(&self, freqs: &[f64]) -> Vec<Vec<(f64, f64)>> {
        (0..3)
            .map(|o| {
                freqs
                    .iter()
                    .map(|&f| {
                        let w = 2.0 * PI * f;
                        let (mut re, mut im) = (0.0, 0.0);
                        for r in 0..3 {
                            let wr = 2.0 * PI * self.frequencies_hz[r];
                            let g = self.shapes[r][o] * self.shapes[r][0];
                            let (dr, di) = (wr * wr - w * w, 2.0 * self.damping[r] * wr * w);
                            let d2 = dr * dr + di * di;
                            // −ω² g / (dr + j di)
                            re += -w * w * g * dr / d2;
                            im += w * w * g * di / d2;
                        }
                        (re, im)
                    })
                    .collect()
            })
            .collect()
    }
}
