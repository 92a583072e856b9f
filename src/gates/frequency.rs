//! Stiffness gates: the first lateral (x, y) and axial (z) resonances against the launcher's
//! minimum frequencies, and the buckling factor of the preloaded stack.

use super::verdict::{Verdict, at_least};
use crate::modal::ModalResult;
use crate::spec::GatesSpec;

const LATERAL_SOURCE: &str =
    "launcher lateral minimum (Falcon 9 User's Guide), [gates] min_lateral_frequency_hz";
const AXIAL_SOURCE: &str =
    "launcher axial minimum (Falcon 9 User's Guide), [gates] min_axial_frequency_hz";

/// Smallest effective-mass fraction that makes a mode "the" resonance along a direction.
const MIN_EFFECTIVE_MASS_FRACTION: f64 = 0.1;
/// Modes below this are rigid-body modes of a free structure, not resonances.
const RIGID_BODY_HZ: f64 = 1e-3;

/// The first mode with ≥ 10% effective mass along direction `dir` (0 = x, 1 = y, 2 = z):
/// (mode index, frequency in Hz).
pub fn first_mode(r: &ModalResult, dir: usize) -> Option<(usize, f64)> {
    r.modes
        .iter()
        .find(|m| {
            m.frequency_hz > RIGID_BODY_HZ
                && m.effective_mass_fraction.to_array()[dir] >= MIN_EFFECTIVE_MASS_FRACTION
        })
        .map(|m| (m.index, m.frequency_hz))
}

/// One gate per direction that has a first mode: lateral x and y, axial z.
/// Margin: f/f_min − 1.
pub fn first_frequencies(first: [Option<(usize, f64)>; 3], limits: &GatesSpec) -> Vec<Verdict> {
    let rules = [
        (
            "lateral frequency x",
            limits.min_lateral_frequency_hz,
            LATERAL_SOURCE,
        ),
        (
            "lateral frequency y",
            limits.min_lateral_frequency_hz,
            LATERAL_SOURCE,
        ),
        (
            "axial frequency z",
            limits.min_axial_frequency_hz,
            AXIAL_SOURCE,
        ),
    ];
    first
        .iter()
        .zip(rules)
        .filter_map(|(mode, (what, limit, source))| {
            mode.map(|(i, f)| at_least(format!("first {what} (mode {i}) [Hz]"), f, limit, source))
        })
        .collect()
}

/// The buckling factor λ of the preload, when the scene has one. Margin: λ/λ_min − 1.
pub fn buckling(factor: Option<f64>, limits: &GatesSpec) -> Option<Verdict> {
    factor.map(|l| {
        at_least(
            "stack buckling factor under the preload",
            l,
            limits.min_buckling_factor,
            "linear buckling (K + λ·K_G)φ = 0, [gates] min_buckling_factor",
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed against the [gates] defaults (10 Hz lateral, 25 Hz axial, λ ≥ 1):
    /// 12/10 − 1 = 0.2, 20/25 − 1 = −0.2, 1.5/1 − 1 = 0.5.
    #[test]
    fn frequency_and_buckling_margins_are_relative_to_the_minimum() {
        let limits = GatesSpec::default();
        let v = first_frequencies([Some((1, 12.0)), None, Some((3, 20.0))], &limits);
        assert_eq!(v.len(), 2);
        assert_eq!(v[0].name, "first lateral frequency x (mode 1) [Hz]");
        assert!(v[0].pass && (v[0].margin - 0.2).abs() < 1e-12);
        assert_eq!(v[1].name, "first axial frequency z (mode 3) [Hz]");
        assert!(!v[1].pass && (v[1].margin + 0.2).abs() < 1e-12);
        let b = buckling(Some(1.5), &limits).unwrap();
        assert!(b.pass && (b.margin - 0.5).abs() < 1e-12);
        assert!(buckling(None, &limits).is_none());
    }
}
