//! Damping identified by `satqual update` from the test modes' measured sine peaks
//! (`peak` in `[[test_modes.mode]]`).

use crate::common::{load, parse};
use satqual::pipeline::workflows::update;
use satqual::spec::Scene;

/// Peak absolute-acceleration transmissibility of a base-driven single-DOF oscillator,
/// max over r of √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)) (the closed form of
/// test-specs/verification/sdof-base.toml), maximised by golden section to 1e-14 in r.
fn sdof_peak_transmissibility(zeta: f64) -> f64 {
    let t = |r: f64| {
        let d = (1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2);
        ((1.0 + (2.0 * zeta * r).powi(2)) / d).sqrt()
    };
    let (mut a, mut b) = (0.5, 1.0);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    while b - a > 1e-14 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if t(c) > t(d) {
            b = d;
        } else {
            a = c;
        }
    }
    t(0.5 * (a + b))
}

/// The SDOF verification scene at Q = 10, its mass a test point measured with `peak_g`.
fn sdof_with_peak(peak_g: f64) -> Scene {
    let base = std::fs::read_to_string("test-specs/verification/sdof-base.toml").unwrap();
    parse(&format!(
        "{base}
[[test_point]]
channel = \"mass x\"
node = 2
direction = \"+x\"

[test_modes]
[[test_modes.mode]]
frequency_hz = 100.0
peak = {{ channel = \"mass x\", g = {peak_g} }}

[update]
[[update.parameter]]
path = \"spring.0.stiffness.0\"
lower = 1e5
upper = 1e6
"
    ))
}

#[test]
fn a_single_dof_peak_gives_back_the_damping_that_made_it() {
    // Reference: the closed-form transmissibility above. The measured peak is that of
    // ζ = 0.02 under the scene's 1 g sine; the scene starts at ζ = 0.05 (Q = 10). Tolerance
    // 1e-4 relative on ζ: the identification stops at a 1e-6 peak mismatch, and the sine
    // peak is refined on the transfer function (golden section).
    let truth = 0.02;
    let u = update::run(&sdof_with_peak(sdof_peak_transmissibility(truth))).unwrap();
    assert_eq!(u.damping.len(), 1);
    let d = &u.damping[0];
    assert!((d.zeta_start - 0.05).abs() < 1e-12, "{}", d.zeta_start);
    assert!(
        (d.zeta - truth).abs() < 1e-4 * truth,
        "{} vs {truth}",
        d.zeta
    );
    assert!(
        u.updated_text
            .contains("{ mode = 1, zeta = 0.02, direction = \"x\" }"),
        "{}",
        u.updated_text
    );
}

#[test]
fn the_shaker_scene_reproduces_the_measured_sine_peaks_with_its_identified_damping() {
    // Source: paper §5.1.1, Fig. 17a: 4.53 g (x), 4.29 g (y), 0.68 g (z) under 0.3 g. The
    // issue's acceptance is 10 %; the scene's ratios are the identified ones rounded to six
    // decimals, so the match is to 1e-3 (the peaks are matched by construction: the test is
    // that the scene holds what `update` identifies and that the sine response uses it).
    let scene = load("test-specs/shaker-2sat.toml");
    let u = update::run(&scene).unwrap();
    let written = scene.file.damping.clone().unwrap().modes.unwrap();
    for d in &u.damping {
        let w = written
            .iter()
            .find(|m| m.mode == d.fe_mode)
            .expect("written");
        assert!(
            (w.zeta - d.zeta).abs() < 1e-6,
            "mode {}: {} vs {}",
            d.fe_mode,
            w.zeta,
            d.zeta
        );
    }
    let (model, sys) = satqual::pipeline::modal(&scene, None, None).unwrap();
    let prep = satqual::response::Prepared::new(&scene, &model, &sys).unwrap();
    let spec = scene.file.sine.clone().unwrap();
    for (axis, measured) in [(0, 4.53), (1, 4.29), (2, 0.68)] {
        let run = satqual::response::sine::run(&prep, &spec, axis, &Default::default()).unwrap();
        let sat1 = run.peaks.iter().find(|p| p.name == "sat 1").unwrap();
        let err = (sat1.acceleration_g - measured) / measured;
        assert!(
            err.abs() < 1e-3,
            "axis {axis}: {} g vs {measured} g",
            sat1.acceleration_g
        );
    }
    // Satellite 1 moves more than a single-DOF oscillator (modal factor ≈ 1.16), so the
    // model needs more damping than the single-DOF reading of the lateral peaks.
    for d in &u.damping[..2] {
        let sdof = scene.file.test_modes.as_ref().unwrap().mode[d.test_mode - 1]
            .damping_ratio
            .unwrap();
        assert!(
            d.zeta > sdof,
            "test mode {}: {} vs {sdof}",
            d.test_mode,
            d.zeta
        );
    }
}

#[test]
fn a_peak_on_an_unknown_channel_or_without_a_sine_input_is_a_located_error() {
    let base = sdof_with_peak(5.0);
    let bad = base
        .text
        .replacen("channel = \"mass x\", g", "channel = \"mass y\", g", 1);
    let e = Scene::parse(&base.path, &bad).unwrap_err().to_string();
    assert!(
        e.contains("test_modes.mode[0].peak.channel") && e.contains("mass y"),
        "{e}"
    );
    let start = base.text.find("\n[sine]").unwrap();
    let end = base.text.find("\n[random]").unwrap();
    let no_sine = format!("{}{}", &base.text[..start], &base.text[end..]);
    let e = Scene::parse(&base.path, &no_sine).unwrap_err().to_string();
    assert!(e.contains("peak") && e.contains("[sine]"), "{e}");
}

#[test]
fn correlate_writes_the_measured_damping_of_the_paired_modes() {
    // The shaker scene's test modes carry measured ratios (the single-DOF readings of the
    // paper's peaks); each lands on its paired FE mode (1, 2, 12), exactly as written, and
    // every comment of the scene survives. The input is never the output.
    let dir = crate::common::temp_dir("correlate-write-damping");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("shaker-damped.toml");
    let (code, _, err) = crate::common::run_text(
        &[
            "correlate",
            "test-specs/shaker-2sat.toml",
            "--write-damping",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let original = std::fs::read_to_string("test-specs/shaker-2sat.toml").unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    for line in original
        .lines()
        .filter(|l| l.trim_start().starts_with("# ASSUMPTION"))
    {
        assert!(written.contains(line), "lost {line:?}");
    }
    let scene = Scene::parse(&out, &written).unwrap();
    let modes = scene.file.damping.unwrap().modes.unwrap();
    // Each entry names its mode's family (the direction of its largest effective mass), so
    // that a later model that renumbers its modes is refused rather than damping another one.
    let families = [(1, 0.03319, "x"), (2, 0.03505, "y"), (12, 0.2458, "z")];
    for (mode, zeta, direction) in families {
        let m = modes.iter().find(|m| m.mode == mode).expect("entry");
        assert_eq!(m.zeta, zeta, "mode {mode}");
        assert_eq!(m.direction.as_deref(), Some(direction), "mode {mode}");
    }
    let (code, _, err) = crate::common::run_text(
        &[
            "correlate",
            "test-specs/shaker-2sat.toml",
            "--write-damping",
            "test-specs/shaker-2sat.toml",
        ],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("never overwrites its input"), "{err}");
}
