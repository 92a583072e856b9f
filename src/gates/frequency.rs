//! Stiffness gates: the first lateral (x, y) and axial (z) resonances against the launcher's
//! minimum frequencies, and the buckling factor of the preloaded stack.
//!
//! A direction is never silently ungated: a rigid-body mode along it is a first frequency of
//! 0 Hz (the model is not supported there); no mode along it within the extracted band passes
//! only when the band's last mode is itself above the minimum (the first mode is above it), and
//! fails as "not evaluated" otherwise. Only a direction in which no free DOF carries mass
//! (fully supported) has no gate.

use super::verdict::{Group, Verdict, at_least};
use crate::modal::ModalResult;
use crate::spec::GatesSpec;

const LATERAL_SOURCE: &str =
    "launcher lateral minimum (Falcon 9 User's Guide), [gates] min_lateral_frequency_hz";
const AXIAL_SOURCE: &str =
    "launcher axial minimum (Falcon 9 User's Guide), [gates] min_axial_frequency_hz";

/// Smallest effective-mass fraction that makes a mode "the" resonance along a direction.
const MIN_EFFECTIVE_MASS_FRACTION: f64 = 0.1;
/// Share of the total mass (or inertia) the free DOFs must carry along a direction for it to
/// need a frequency gate: below it the direction is supported everywhere.
const FREE_MASS_FRACTION: f64 = 1e-9;

/// The first mode with ≥ 10% effective mass along direction `dir` (0 = x, 1 = y, 2 = z),
/// rigid-body modes (0 Hz) included: (mode index, frequency in Hz).
pub fn first_mode(r: &ModalResult, dir: usize) -> Option<(usize, f64)> {
    r.modes
        .iter()
        .find(|m| m.effective_mass_fraction.to_array()[dir] >= MIN_EFFECTIVE_MASS_FRACTION)
        .map(|m| (m.index, m.frequency_hz))
}

/// What the extracted band says about the directions without a first mode: the last mode's
/// frequency (a lower bound of theirs), and which directions are free at all.
#[derive(Debug, Clone, Copy)]
pub struct Band {
    pub top_hz: Option<f64>,
    pub free: [bool; 3],
}

impl Band {
    pub fn of(r: &ModalResult) -> Band {
        let free_mass = r.rigid_body_mass.to_array();
        let total = r.total_rigid_body_mass.to_array();
        Band {
            top_hz: r.modes.last().map(|m| m.frequency_hz),
            free: std::array::from_fn(|d| free_mass[d] > FREE_MASS_FRACTION * total[d]),
        }
    }
}

/// One gate per free direction: lateral x and y, axial z. Margin: f/f_min − 1.
pub fn first_frequencies(
    first: [Option<(usize, f64)>; 3],
    band: Band,
    limits: &GatesSpec,
) -> Vec<Verdict> {
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
        .zip(band.free)
        .filter_map(|((mode, (what, limit, source)), free)| match mode {
            Some((i, f)) if *f == 0.0 => Some(at_least(
                format!(
                    "first {what} (mode {i}, rigid-body: the model is not supported along it) [Hz]"
                ),
                0.0,
                limit,
                source,
            )),
            Some((i, f)) => Some(at_least(
                format!("first {what} (mode {i}) [Hz]"),
                *f,
                limit,
                source,
            )),
            None if free => Some(beyond_band(what, band.top_hz, limit, source)),
            None => None,
        })
        .map(|v| v.in_group(Group::Frequency).with_unit("Hz"))
        .collect()
}

/// A free direction with no mode in the band: the band's top is a lower bound of its first
/// frequency, which passes when it already meets the minimum and cannot be evaluated otherwise.
fn beyond_band(what: &str, top_hz: Option<f64>, limit: f64, source: &str) -> Verdict {
    match top_hz {
        Some(top) if top >= limit => at_least(
            format!("first {what} (above the last extracted mode) [Hz]"),
            top,
            limit,
            source,
        ),
        _ => {
            let top = top_hz.unwrap_or(0.0);
            let found = match top_hz {
                Some(t) => format!("no mode with ≥ 10% effective mass up to {t:.4} Hz"),
                None => "no mode was extracted".to_string(),
            };
            let name = format!(
                "first {what} [Hz]: not evaluated, {found}; extract more modes ([modal] fmax_hz or modes)"
            );
            Verdict::gate(name, top, limit, -1.0, false, source)
        }
    }
}

/// The verdict of a qualification in which no gate could be evaluated: a failure, since a
/// PASS must rest on at least one criterion.
pub fn nothing_evaluated() -> Verdict {
    Verdict::gate(
        "no gate evaluated: nothing in the scene could be checked",
        0.0,
        1.0,
        -1.0,
        false,
        "satqual: a qualification passes only on criteria that were evaluated",
    )
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
        .in_group(Group::Buckling)
        .with_unit("")
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
        let band = Band {
            top_hz: Some(30.0),
            free: [true, false, true],
        };
        let v = first_frequencies([Some((1, 12.0)), None, Some((3, 20.0))], band, &limits);
        assert_eq!(v.len(), 2);
        assert_eq!(v[0].name, "first lateral frequency x (mode 1) [Hz]");
        assert!(v[0].pass && (v[0].margin - 0.2).abs() < 1e-12);
        assert_eq!(v[1].name, "first axial frequency z (mode 3) [Hz]");
        assert!(!v[1].pass && (v[1].margin + 0.2).abs() < 1e-12);
        let b = buckling(Some(1.5), &limits).unwrap();
        assert!(b.pass && (b.margin - 0.5).abs() < 1e-12);
        assert!(buckling(None, &limits).is_none());
    }

    /// A rigid-body mode is a 0 Hz first frequency (margin 0/10 − 1 = −1); a free direction
    /// without a mode passes on the band's top (30/10 − 1 = 2 lateral, 30/25 − 1 = 0.2 axial)
    /// and fails as not evaluated when the top is below the minimum (8 < 10 Hz).
    #[test]
    fn rigid_body_and_missing_directions_are_gated_not_dropped() {
        let limits = GatesSpec::default();
        let free = [true; 3];
        let v = first_frequencies(
            [Some((1, 0.0)), None, None],
            Band {
                top_hz: Some(30.0),
                free,
            },
            &limits,
        );
        assert_eq!(v.len(), 3);
        assert!(!v[0].pass && v[0].margin == -1.0 && v[0].name.contains("rigid-body"));
        assert!(v[1].pass && (v[1].margin - 2.0).abs() < 1e-12);
        assert!(v[2].pass && (v[2].margin - 0.2).abs() < 1e-12);
        let low = first_frequencies(
            [None, None, None],
            Band {
                top_hz: Some(8.0),
                free,
            },
            &limits,
        );
        assert!(low.iter().all(|g| !g.pass));
        assert!(low[0].name.contains("up to 8.0000 Hz"), "{}", low[0].name);
        // No mode extracted at all: said so, not "up to 0 Hz".
        let none = first_frequencies([None, None, None], Band { top_hz: None, free }, &limits);
        assert!(
            none.iter()
                .all(|g| !g.pass && g.name.contains("no mode was extracted"))
        );
        assert!(!nothing_evaluated().pass);
    }
}
