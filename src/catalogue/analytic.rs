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
