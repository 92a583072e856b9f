//! Test-data gates: the random control against its profile (GSFC-STD-7000 tolerances), a
//! shock record's SRS against the shock specification (NASA-STD-7003A, MIL-STD-810H 516), and
//! the pre/post-test signatures mode by mode.

use super::verdict::{Group, Verdict, at_most};
use crate::signal::srs::SpecCheck;
use crate::signal::{SignatureReport, ToleranceReport};
use crate::spec::GatesSpec;

/// The control of random log `log`: no line beyond the abort band (value: % of lines outside,
/// margin: minus the fraction outside, so 0 at best), and the Grms within its tolerance
/// (margin 1 − |ΔGrms|/tolerance).
pub fn random_control(log: &str, rep: &ToleranceReport, limits: &GatesSpec) -> [Verdict; 2] {
    let outside = rep.fraction_outside_abort;
    [
        Verdict::gate(
            format!(
                "{log}: control lines beyond ±{} dB abort [%]",
                limits.abort_db
            ),
            outside * 100.0,
            0.0,
            -outside,
            outside == 0.0,
            "GSFC-STD-7000 random test tolerance, [gates] abort_db",
        )
        .in_group(Group::TestData)
        .with_unit("%"),
        at_most(
            format!("{log}: control Grms departure from the profile [%]"),
            rep.grms_error_pct.abs(),
            limits.grms_tolerance_pct,
            "GSFC-STD-7000 Grms tolerance, [gates] grms_tolerance_pct",
        )
        .in_group(Group::TestData)
        .with_unit("%"),
    ]
}

const SHOCK_SOURCE: &str = "NASA-STD-7003A / MIL-STD-810H Method 516 SRS tolerance, [shock] upper_db, lower_db, allowed_fraction";

/// Channel `channel` of shock log `log`: the share of SRS points above the upper and below the
/// lower limit, each at most `[shock] allowed_fraction` (margin: allowed − share, so 0 at best
/// with none allowed). With no SRS point inside the specification's band, nothing was shown
/// to meet it: one failed gate says so.
pub fn shock_spec(log: &str, channel: &str, check: &SpecCheck) -> Vec<Verdict> {
    let name = format!("{log}: {channel} SRS");
    if check.points.is_empty() {
        let v = Verdict::gate(
            format!("{name}: points within the specification's band"),
            0.0,
            1.0,
            -1.0,
            false,
            SHOCK_SOURCE,
        );
        return vec![v.in_group(Group::TestData)];
    }
    let tol = check.tolerance;
    let share = |label: String, fraction: f64| {
        Verdict::gate(
            label,
            100.0 * fraction,
            100.0 * tol.allowed_fraction,
            tol.allowed_fraction - fraction,
            fraction <= tol.allowed_fraction,
            SHOCK_SOURCE,
        )
        .in_group(Group::TestData)
        .with_unit("%")
    };
    vec![
        share(
            format!("{name}: points above +{} dB of the spec [%]", tol.upper_db),
            check.fraction_above_upper,
        ),
        share(
            format!("{name}: points below −{} dB of the spec [%]", tol.lower_db),
            check.fraction_below_lower,
        ),
    ]
}

/// Per mode of the before-signature: frequency shift and amplitude change within their
/// limits (margin 1 − |change|/limit), or a failed gate when the mode was not found after.
pub fn signature(rep: &SignatureReport, limits: &GatesSpec) -> Vec<Verdict> {
    let mut out = Vec::new();
    for m in &rep.modes {
        let name = format!("signature mode {} ({:.2} Hz)", m.mode, m.before_hz);
        match (m.shift_pct, m.amplitude_change_pct) {
            (Some(shift), Some(amp)) => out.extend(mode_changes(&name, shift, amp, limits)),
            _ => out.push(
                Verdict::gate(
                    format!("{name}: found after the test"),
                    f64::NAN,
                    0.0,
                    -1.0,
                    false,
                    m.reason.clone(),
                )
                .in_group(Group::TestData),
            ),
        }
    }
    out
}

/// The two gates of a mode found before and after the test.
pub fn mode_changes(name: &str, shift_pct: f64, amp_pct: f64, limits: &GatesSpec) -> [Verdict; 2] {
    [
        at_most(
            format!("{name}: frequency shift [%]"),
            shift_pct.abs(),
            limits.max_frequency_shift_pct,
            "GSFC-STD-7000 practice, [gates] max_frequency_shift_pct",
        )
        .in_group(Group::TestData)
        .with_unit("%"),
        at_most(
            format!("{name}: amplitude change [%]"),
            amp_pct.abs(),
            limits.max_amplitude_change_pct,
            "GSFC-STD-7000 practice, [gates] max_amplitude_change_pct",
        )
        .in_group(Group::TestData)
        .with_unit("%"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed against the [gates] defaults (5% shift, 20% amplitude):
    /// 1 − 3/5 = 0.4 for a −3% shift; 1 − 30/20 = −0.5 for a +30% amplitude change.
    #[test]
    fn mode_change_margins_use_the_magnitude_of_the_change() {
        let [shift, amp] = mode_changes("mode 1", -3.0, 30.0, &GatesSpec::default());
        assert!(shift.pass && (shift.margin - 0.4).abs() < 1e-12 && shift.value == 3.0);
        assert!(!amp.pass && (amp.margin + 0.5).abs() < 1e-12);
        assert_eq!(shift.name, "mode 1: frequency shift [%]");
    }
}
