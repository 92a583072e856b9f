//! The shaker fixture modelled apart from the stack (`[stack.fixture]`), the test model
//! calibrated with it, and the flight scene's calibration record (`[calibration]`).

use satqual::modal::ModalSystem;
use satqual::pipeline::workflows::calibration;
use satqual::spec::Scene;

use crate::common::load;

fn solve(scene: &Scene) -> ModalSystem {
    satqual::pipeline::modal(scene, None, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .1
}

/// The shaker scene with its `[stack.fixture]` table rewritten by `edit`.
fn with_fixture(edit: impl Fn(&str) -> String) -> Scene {
    let base = load("test-specs/shaker-2sat.toml");
    let start = base.text.find("\n[stack.fixture]\n").expect("a fixture");
    let end = start
        + base.text[start..]
            .find("\n[modal]")
            .expect("[modal] follows");
    let text = format!(
        "{}{}{}",
        &base.text[..start],
        edit(&base.text[start..end]),
        &base.text[end..]
    );
    Scene::parse(&base.path, &text).unwrap_or_else(|e| panic!("{e}"))
}

fn frequencies(sys: &ModalSystem, n: usize) -> Vec<f64> {
    sys.result.modes[..n]
        .iter()
        .map(|m| m.frequency_hz)
        .collect()
}

#[test]
fn a_fixture_much_stiffer_than_the_joints_leaves_the_clamped_modes() {
    // Source: springs in series, 1/k = 1/k_joint + 1/k_fixture, tends to the clamped base as
    // k_fixture → ∞. At 1e4 × the estimate (a 20 kHz fixture under a 29-78 Hz article) the
    // fixture's share of the compliance is ~(78/20000)² ≈ 2e-5; tolerance 1e-4 relative on the
    // first twelve modes.
    let stiff = solve(&with_fixture(|t| {
        t.replace("= 4.3e8", "= 4.3e12")
            .replace("= 2.3e8", "= 2.3e12")
            .replace("= 1.7e8", "= 1.7e12")
    }));
    let clamped = solve(&with_fixture(|_| String::new()));
    for (a, b) in frequencies(&stiff, 12)
        .iter()
        .zip(frequencies(&clamped, 12))
    {
        assert!(
            (a - b).abs() / b < 1e-4,
            "{a} Hz on the stiff fixture vs {b} Hz clamped"
        );
    }
}

#[test]
fn the_fixture_lowers_every_stack_mode_and_its_plate_is_not_article_mass() {
    // Source: Rayleigh's monotonicity — adding compliance (and the plate's mass) can only lower
    // every eigenvalue of the clamped system; strict for the three measured ones.
    let with = load("test-specs/shaker-2sat.toml");
    let clamped = solve(&with_fixture(|_| String::new()));
    let on_fixture = solve(&with);
    for (a, b) in frequencies(&on_fixture, 3)
        .iter()
        .zip(frequencies(&clamped, 3))
    {
        assert!(a < &b, "{a} Hz on the fixture, {b} Hz clamped");
    }
    // The model carries the 60 kg plate; the test article is the rest (GEVS weight reduction).
    let total = on_fixture.result.total_mass_kg;
    let article = clamped.result.total_mass_kg;
    assert!((total - article - 60.0).abs() < 1e-9, "{total} - {article}");
    assert_eq!(with.file.fixture_mass_kg(), 60.0);
}

#[test]
fn the_shaker_scene_holds_the_joint_values_its_update_gives() {
    // Source: `satqual update` on the scene itself (fixture in the model, least squares on the
    // three measured frequencies, paper §5.1.1). The scene's values are the update's rounded to
    // five digits, so re-updating moves them by less than 1e-4 relative, and the paired
    // frequencies stay within the ECSS-E-ST-32-11C ±3 %.
    let u = satqual::pipeline::workflows::update::run(&load("test-specs/shaker-2sat.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    for p in &u.parameters {
        assert!(
            (p.value - p.start).abs() / p.start < 1e-4,
            "{}: {} -> {}",
            p.path,
            p.start,
            p.value
        );
    }
    for t in &u.targets {
        assert!(
            t.error_after_pct.abs() < 3.0,
            "test mode {}: {:+.3} %",
            t.test_mode,
            t.error_after_pct
        );
    }
}

#[test]
fn the_flight_scene_follows_the_fixture_range_as_series_compliance_predicts() {
    // Source: springs in series again. A softer fixture (× 0.25) takes more of the measured
    // compliance, so the recalibrated joints are stiffer and the flight stack, which has no
    // fixture, stiffer too; a stiffer fixture (× 4) the reverse. The nominal case is the
    // flight scene as written, whose values are the test scene's.
    let flight = load("test-specs/paper-stack.toml");
    let spec = flight.file.calibration.clone().expect("[calibration]");
    let c = calibration::run(&flight, &spec).unwrap_or_else(|e| panic!("{e}"));
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    for p in &c.parameters {
        assert_eq!(p.flight, p.test, "{}", p.path);
    }
    let [nominal, soft, stiff] = [&c.cases[0], &c.cases[1], &c.cases[2]];
    assert_eq!((soft.fixture_factor, stiff.fixture_factor), (0.25, 4.0));
    for (i, p) in c.parameters.iter().enumerate() {
        if p.path.starts_with("stack.interface.") {
            assert!(soft.values[i] > nominal.values[i] && nominal.values[i] > stiff.values[i]);
        } else {
            // The damping ratios are identified after the frequency fit, at the nominal
            // fixture, and held across the range.
            assert!(soft.values[i] == nominal.values[i] && stiff.values[i] == nominal.values[i]);
        }
    }
    for d in 0..3 {
        let f = |case: &satqual::results::FixtureCase| case.first_hz[d].expect("a first mode");
        assert!(f(soft) > f(nominal) && f(nominal) > f(stiff), "axis {d}");
    }
}

#[test]
fn a_flight_value_that_left_the_test_model_is_flagged() {
    let flight = load("test-specs/paper-stack.toml");
    let from = "rotational_stiffness_n_m_rad = 1.0904e5";
    assert!(flight.text.contains(from));
    let text = flight
        .text
        .replacen(from, "rotational_stiffness_n_m_rad = 1.2e5", 1);
    let edited = Scene::parse(&flight.path, &text).unwrap();
    let spec = edited.file.calibration.clone().expect("[calibration]");
    let c = calibration::run(&edited, &spec).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    assert!(c.warnings[0].contains("stack.interface.rotational_stiffness_n_m_rad"));
}

#[test]
fn a_calibration_naming_a_missing_key_is_a_located_error() {
    let flight = load("test-specs/paper-stack.toml");
    let text = flight.text.replacen(
        "\"stack.interface.axial_stiffness_n_m\",",
        "\"stack.interface.axial_n_m\",",
        1,
    );
    let e = Scene::parse(&flight.path, &text).unwrap_err().to_string();
    assert!(
        e.contains("calibration.parameters") && e.contains("axial_n_m"),
        "{e}"
    );
}
