//! Lateral bending modes of a guide bar, clamped at its root and free at its tip, for the
//! separation model's floating-frame (modal) bar. The separation module samples the shapes at
//! stations along the bar and interpolates between them.
//!
//! TEMPORARY: closed-form Euler-Bernoulli cantilever modes (βL roots). To be replaced by the FE
//! beam model of this module once the FE core lands; the signature stays.

use crate::error::FemError;
use crate::spec::Material;

/// Mass-normalised lateral modes of one bending plane (a circular bar has the same modes in x
/// and y).
#[derive(Debug, Clone)]
pub struct BarModes {
    /// Stations along the bar from the root, m (first = 0, last = length).
    pub stations_m: Vec<f64>,
    pub frequencies_hz: Vec<f64>,
    /// `shapes[mode][station]`: lateral deflection for a unit modal coordinate (unit modal
    /// mass), m per √kg.
    pub shapes: Vec<Vec<f64>>,
    /// Mass per unit length, kg/m.
    pub mass_per_length_kg_m: f64,
    pub length_m: f64,
}

/// Modes of a solid circular bar of `diameter_m` and `length_m`, clamped at z = 0.
pub fn cantilever_bar_modes(
    length_m: f64,
    diameter_m: f64,
    material: &Material,
    elements: usize,
    n_modes: usize,
) -> Result<BarModes, FemError> {
    if !(length_m > 0.0 && diameter_m > 0.0) || elements == 0 {
        return Err(FemError::Invalid("bar length, diameter and elements must be positive".into()));
    }
    let roots = [1.875104068711961, 4.694091132974175, 7.854757438237613, 10.995540734875467, 14.137168391046471];
    let area = std::f64::consts::PI * diameter_m.powi(2) / 4.0;
    let i = std::f64::consts::PI * diameter_m.powi(4) / 64.0;
    let mu = material.density_kg_m3 * area;
    let e = material.youngs_modulus_pa;
    let stations: Vec<f64> = (0..=elements).map(|k| length_m * k as f64 / elements as f64).collect();
    let mut freqs = Vec::new();
    let mut shapes = Vec::new();
    for (m, &bl) in roots.iter().enumerate().take(n_modes) {
        let _ = m;
        let beta = bl / length_m;
        let w = beta * beta * (e * i / mu).sqrt();
        freqs.push(w / (2.0 * std::f64::consts::PI));
        let s = (bl.sin() - bl.sinh()) / (bl.cos() + bl.cosh());
        let phi = |x: f64| {
            let bx = beta * x;
            (bx.cosh() - bx.cos()) + s * (bx.sinh() - bx.sin())
        };
        // ∫φ² dx = L for this normalisation of the clamped-free shape; unit modal mass
        // divides by √(μL).
        let scale = 1.0 / (mu * length_m).sqrt();
        shapes.push(stations.iter().map(|&x| phi(x) * scale).collect());
    }
    Ok(BarModes { stations_m: stations, frequencies_hz: freqs, shapes, mass_per_length_kg_m: mu, length_m })
}
