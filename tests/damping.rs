//! `[damping]`: per-mode ratios over the base, and the table's interpolation, against the
//! analytic single-DOF peak; bad keys are located errors.

use crate::common::{parse, scene_error};
use satqual::response::{Prepared, SineOptions};

const SDOF: &str = "test-specs/verification/sdof-base.toml";

fn sdof_with(damping: &str) -> satqual::spec::Scene {
    let text = std::fs::read_to_string(SDOF).unwrap();
    parse(&text.replace("[damping]\nq = 10.0", damping))
}

fn sine_peak_g(scene: &satqual::spec::Scene) -> f64 {
    let (model, sys) = satqual::pipeline::modal(scene, None, None).unwrap();
    let prep = Prepared::new(scene, &model, &sys).unwrap();
    let spec = scene.file.sine.clone().unwrap();
    let r = satqual::response::sine::run(&prep, &spec, 0, &SineOptions::default()).unwrap();
    r.peaks[0].acceleration_g
}

/// The exact maximum of the absolute-acceleration transmissibility of a base-driven SDOF
/// (Harris' Shock and Vibration Handbook, ch. 2): at r² = (√(1 + 8ζ²) − 1)/(4ζ²).
fn sdof_max(zeta: f64) -> f64 {
    let r2 = ((1.0 + 8.0 * zeta * zeta).sqrt() - 1.0) / (4.0 * zeta * zeta);
    let c = 4.0 * zeta * zeta * r2;
    ((1.0 + c) / ((1.0 - r2).powi(2) + c)).sqrt()
}

#[test]
fn damping_mode_entry_overrides_the_base() {
    // Base Q = 10 (ζ 5 %) but mode 1 given ζ = 2 %: the peak is the ζ = 2 % one (about 25),
    // within the sine analysis's 0.5 % acceptance.
    let peak = sine_peak_g(&sdof_with(
        "[damping]\nq = 10.0\nmodes = [{ mode = 1, zeta = 0.02 }]",
    ));
    let exact = sdof_max(0.02);
    assert!((peak - exact).abs() / exact < 0.005, "{peak} vs {exact}");
    // A mode entry for a mode the model does not have changes nothing: the base applies.
    let peak = sine_peak_g(&sdof_with(
        "[damping]\nq = 10.0\nmodes = [{ mode = 2, zeta = 0.02 }]",
    ));
    let exact = sdof_max(0.05);
    assert!((peak - exact).abs() / exact < 0.005, "{peak} vs {exact}");
}

#[test]
fn damping_table_log_interpolation_at_the_mode() {
    // Table 4 % at 50 Hz, 1 % at 200 Hz, read at fn = 100 Hz (reference: the interpolation
    // formulas). Linear in f: 4 % − (50/150)·3 % = 3 %. Log-log: 4 % · (1/4)^(ln 2/ln 4) = 2 %
    // (the table is ζ ∝ 1/f exactly). Peaks against the exact SDOF maximum, 0.5 %.
    let table = "table = [[50.0, 0.04], [200.0, 0.01]]";
    let lin = sine_peak_g(&sdof_with(&format!("[damping]\n{table}")));
    let log = sine_peak_g(&sdof_with(&format!(
        "[damping]\n{table}\ninterpolation = \"log\""
    )));
    for (got, zeta) in [(lin, 0.03), (log, 0.02)] {
        let exact = sdof_max(zeta);
        assert!(
            (got - exact).abs() / exact < 0.005,
            "{got} vs {exact} (ζ {zeta})"
        );
    }
}

#[test]
fn damping_bad_mode_keys_are_located() {
    let base = std::fs::read_to_string(SDOF).unwrap();
    let cases = [
        (
            "q = 10.0",
            "q = 10.0\nmodes = [{ mode = 0, zeta = 0.02 }]",
            "damping.modes[0].mode",
        ),
        (
            "q = 10.0",
            "q = 10.0\nmodes = [{ mode = 1, zeta = 0.02 }, { mode = 1, zeta = 0.03 }]",
            "damping.modes[1].mode",
        ),
        (
            "q = 10.0",
            "q = 10.0\nmodes = [{ mode = 1, zeta = 1.5 }]",
            "damping.modes[0].zeta",
        ),
        (
            "q = 10.0",
            "q = 10.0\ninterpolation = \"log\"",
            "damping.interpolation",
        ),
        ("q = 10.0", "modes = [{ mode = 1, zeta = 0.02 }]", "damping"),
    ];
    for (from, to, key) in cases {
        let msg = scene_error(&base, from, to);
        assert!(msg.contains(key), "{to}: {msg}");
    }
}
