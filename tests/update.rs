//! `satqual update`: model updating against paired test frequencies.

use crate::common::{load, parse, rel, run_text, temp_dir};
use satqual::catalogue::generated::{
    UPDATE_TRUE as TRUE, update_round_trip_scene as round_trip_scene, update_section,
};
use satqual::pipeline::plan::{ModalOverrides, modal_options};
use satqual::pipeline::workflows::correlate;
use satqual::pipeline::workflows::correlate::test_modes;
use satqual::pipeline::workflows::update;
use satqual::pipeline::workflows::update::problem::{Problem, Target};
use satqual::spec::Scene;

const USC: &str = "test-specs/correlation/usc-beam-update.toml";

/// The updating problem of a scene with every test mode a target of weight 1.
fn problem(scene: &Scene) -> Problem<'_> {
    let spec = scene.file.update.clone().expect("[update]");
    let params = update::params(scene, &spec);
    let (test, _) = test_modes::test_modes(scene).unwrap();
    let targets = (0..test.len())
        .map(|t| Target {
            test: t,
            weight: 1.0,
        })
        .collect();
    Problem {
        base: scene,
        params,
        targets,
        test,
        opts: modal_options(scene, &ModalOverrides::default()),
    }
}

/// The analytic Jacobian (Fox–Kapoor sensitivities from assembled-matrix differences) against
/// central differences of full eigen-solves (relative step 1e-4 in ln p; truncation error
/// O(1e-8) of the entry), to 1e-4 of the largest entry.
#[test]
fn sensitivities_match_finite_differences_of_eigen_solves() {
    let scene = load(USC);
    let pr = problem(&scene);
    let start: Vec<f64> = pr.params.iter().map(|p| p.start * 3.0).collect();
    let s = pr.solve(&start).unwrap();
    let j = pr.jacobian(&s).unwrap();
    let h = 1e-4;
    let big = j.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for c in 0..pr.params.len() {
        let at = |sign: f64| {
            let mut v = start.clone();
            v[c] *= (sign * h).exp();
            pr.residuals(&pr.solve(&v).unwrap())
        };
        let fd = (at(1.0) - at(-1.0)) / (2.0 * h);
        for i in 0..fd.len() {
            assert!(
                (fd[i] - j[(i, c)]).abs() < 1e-4 * big,
                "param {c} target {i}: analytic {} vs FD {}",
                j[(i, c)],
                fd[i]
            );
        }
    }
}

/// The first five z-bending frequencies of the model at the true values: the synthetic test.
fn true_frequencies() -> Vec<f64> {
    let scene = parse(&round_trip_scene(TRUE, &[10.0], ""));
    let c = correlate::run(&scene).unwrap();
    let z: Vec<f64> = (c.fe_modes.iter())
        .filter(|m| m.direction == Some("z"))
        .map(|m| m.frequency_hz)
        .take(5)
        .collect();
    assert_eq!(z.len(), 5, "{:?}", c.fe_modes);
    z
}

/// Noise-free round trip: started 30% off (+30%, −30%, +30%), the update recovers the values
/// that made the test frequencies. Reference: TRUE itself; tolerance 2% (the brief's), the
/// measured error is far below it (the fit is exact up to the solver's stopping rule).
#[test]
fn a_perturbed_model_recovers_the_values_that_made_the_test_frequencies() {
    let test = true_frequencies();
    let start = [TRUE[0] * 1.3, TRUE[1] * 0.7, TRUE[2] * 1.3];
    let scene = parse(&round_trip_scene(start, &test, &update_section("")));
    let u = update::run(&scene).unwrap();
    assert!(
        u.converged,
        "{:?} after {} iterations",
        u.stop, u.iterations
    );
    // The root spring and the tip mass shift the z modes nearly in proportion (their
    // estimates are correlated at ~0.99, which the output says); nothing else may be warned of.
    let other = u.warnings.iter().find(|w| !w.contains("are correlated at"));
    assert!(other.is_none(), "{other:?}");
    for (p, t) in u.parameters.iter().zip(TRUE) {
        assert!(
            rel(p.value, t) < 0.02,
            "{}: {} vs true {t}",
            p.path,
            p.value
        );
        assert!(p.identifiable, "{}", p.path);
    }
    for t in &u.targets {
        assert!(t.error_after_pct.abs() < 1e-4, "{t:?}");
        assert!(
            t.error_before_pct.abs() > 1.0,
            "the start must be off: {t:?}"
        );
    }
    assert_eq!(u.singular_values.len(), 3);
    // Measured 1.5e-10 … 2.8e-9 in 5 iterations; 1e-6 bounds the stopping rule's slack.
    for (p, t) in u.parameters.iter().zip(TRUE) {
        assert!(
            rel(p.value, t) < 1e-6,
            "{}: {} vs true {t}",
            p.path,
            p.value
        );
    }
    eprintln!(
        "round trip: {} iterations, errors {:?}",
        u.iterations,
        u.parameters
            .iter()
            .zip(TRUE)
            .map(|(p, t)| rel(p.value, t))
            .collect::<Vec<_>>()
    );
}

/// 2% noise: each test frequency times (1 + 0.02·g), g standard normal (ChaCha8, seed 19).
/// The tolerance follows from the noise: the true values must lie inside the reported 95%
/// intervals (linearised, from the fit's own residual with m − n = 2 degrees of freedom).
#[test]
fn with_noisy_test_frequencies_the_true_values_lie_in_the_95_percent_intervals() {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
    let test: Vec<f64> = (true_frequencies().iter())
        .map(|f| f * (1.0 + 0.02 * crate::common::gauss(&mut rng)))
        .collect();
    let start = [TRUE[0] * 0.7, TRUE[1] * 1.3, TRUE[2] * 0.7];
    let scene = parse(&round_trip_scene(start, &test, &update_section("")));
    let u = update::run(&scene).unwrap();
    assert!(u.converged, "{}", u.stop);
    for (p, t) in u.parameters.iter().zip(TRUE) {
        let (lo, hi) = (p.ci_low.unwrap(), p.ci_high.unwrap());
        assert!(
            lo <= t && t <= hi,
            "{}: true {t} outside [{lo}, {hi}] (fit {})",
            p.path,
            p.value
        );
        eprintln!(
            "noisy: {} = {} (true {t}), 95% [{lo:.4e}, {hi:.4e}]",
            p.path, p.value
        );
    }
    assert!(u.residual_after_pct > 0.0 && u.residual_after_pct < u.residual_before_pct);
}

/// The root spring's torsion stiffness (rx): no z-bending mode twists the root, so its column
/// of the sensitivity matrix is zero. Without regularization the update refuses, at that
/// parameter's line, naming it; with it, the update runs and flags it not identifiable.
#[test]
fn a_parameter_no_paired_mode_feels_is_not_identifiable() {
    let test = true_frequencies();
    let torsion = crate::common::UNFELT_TORSION;
    let text = round_trip_scene(TRUE, &test, &(update_section("") + torsion));
    crate::common::assert_refused_as_unidentifiable(&text, "spring.0.stiffness.3");
    let regularized = round_trip_scene(
        TRUE,
        &test,
        &(update_section("regularization = 1e-6\n") + torsion),
    );
    let u = update::run(&parse(&regularized)).unwrap();
    crate::common::assert_only_the_last_unidentifiable(&u);
    // Regularization pulls toward the start, which is the truth here: it stays there.
    assert!(
        rel(u.parameters[3].value, 1e7) < 1e-9,
        "{:?}",
        u.parameters[3]
    );
}

/// The preload moves the prestress stiffness K_G, which the sensitivities do not carry: its
/// column would read zero and call it unidentifiable. The update refuses it instead, at its
/// line, saying why (the six-satellite paper stack, one test mode at its first x mode).
#[test]
fn a_preload_parameter_is_refused_with_the_reason() {
    use satqual::catalogue::generated::{STACK_UPDATE_PARAMS, stack_update_model};
    let base =
        std::fs::read_to_string(crate::common::repo_path("test-specs/paper-stack.toml")).unwrap();
    let values = STACK_UPDATE_PARAMS.map(|p| p.1);
    let text = stack_update_model(&base, 6, 8, &values)
        + "\n[test_modes]\n[[test_modes.mode]]\nfrequency_hz = 6.0\nshape = [1.0, 0.0, 0.0]\n"
        + "\n[update]\n[[update.parameter]]\npath = \"stack.preload_total_n\"\nlower = 2e4\nupper = 9e4\n";
    let e = update::run(&parse(&text))
        .expect_err("must refuse")
        .to_string();
    let parts = ["changes the static loads", "prestress"];
    crate::common::assert_error_at(&e, &text, "stack.preload_total_n", &parts);
}

/// Bad `[update]` keys are errors at their line, naming the key.
#[test]
fn bad_update_keys_are_located() {
    let test = true_frequencies();
    let base = round_trip_scene(TRUE, &test, &update_section(""));
    for (from, to, needle) in [
        (
            "path = \"mass.0.mass_kg\"",
            "path = \"mass.3.mass_kg\"",
            "has no element 3",
        ),
        (
            "path = \"mass.0.mass_kg\"",
            "path = \"title\"",
            "not a number",
        ),
        ("max_iterations = 50", "max_iterations = 0", "at least 1"),
        (
            "max_iterations = 50",
            "max_iterations = 50\nregularization = -1.0",
            "must be positive",
        ),
        ("lower = 0.3333333333333333", "lower = 2.0", "outside"),
        (
            "max_iterations = 50",
            "max_iterations = 50\nstep = 1",
            "unknown field",
        ),
    ] {
        let e = crate::common::scene_error(&base, from, to);
        let line = crate::common::line_of(&base.replacen(from, to, 1), to.lines().last().unwrap());
        assert!(e.starts_with(&format!("bad.toml:{line}:")), "{to}: {e}");
        assert!(e.contains(needle), "{to}: {e}");
    }
}

/// The USC cantilever (test-specs/correlation/usc-beam-update.toml): the nominal model is
/// ~11% high on the three impulse-test modes 6.62 / 41.4 / 117.5 Hz (docs/correlation.md);
/// updating the clamp's rotational stiffness and the tip mass brings each within 1% (the
/// brief's requirement, not widened). The two parameters shift the three modes nearly in
/// proportion, and the output must say so: their estimates are correlated beyond 0.99.
#[test]
fn the_usc_beam_is_brought_within_one_percent() {
    let scene = load(USC);
    let u = update::run(&scene).unwrap();
    assert!(u.converged, "{}", u.stop);
    let test: Vec<f64> = u.targets.iter().map(|t| t.test_hz).collect();
    assert_eq!(test, vec![6.62, 41.4, 117.5]);
    for t in &u.targets {
        assert!(t.error_before_pct > 9.0, "nominal model ~11% high: {t:?}");
        assert!(t.error_after_pct.abs() < 1.0, "{t:?}");
        eprintln!(
            "USC mode {}: test {} Hz, before {:.4} ({:+.3}%), after {:.4} ({:+.3}%), MAC {}",
            t.test_mode,
            t.test_hz,
            t.before_hz,
            t.error_before_pct,
            t.after_hz,
            t.error_after_pct,
            t.mac
        );
    }
    assert_eq!(u.singular_values.len(), 2);
    assert!(u.correlation[0][1].abs() > 0.99, "{:?}", u.correlation);
    assert!(
        u.warnings.iter().any(|w| w.contains("are correlated at")),
        "{:?}",
        u.warnings
    );
    eprintln!(
        "USC: {} iterations, {:?}, sv {:?}",
        u.iterations, u.parameters, u.singular_values
    );
}

/// End to end: the written scene keeps the input's comments, annotates each changed value,
/// re-loads, and its modes are the reported "after" frequencies (to 1e-9 relative: the values
/// are written in full precision); the input is byte-identical after the run; `--out` naming
/// the input is refused.
#[test]
fn the_written_scene_reloads_with_the_reported_frequencies() {
    let dir = temp_dir("update-cli");
    let out = dir.join("updated.toml");
    let input = std::fs::read(crate::common::repo_path(USC)).unwrap();
    let (code, stdout, stderr) = run_text(
        &["update", USC, "--out", out.to_str().unwrap(), "--json"],
        None,
    );
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(std::fs::read(crate::common::repo_path(USC)).unwrap(), input);
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    for key in [
        "parameters",
        "targets",
        "singular_values",
        "correlation",
        "iterations",
        "converged",
    ] {
        assert!(json.get(key).is_some(), "{key} missing: {stdout}");
    }
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(
        written.contains("# The clamp: springs from the ground node 9"),
        "{written}"
    );
    assert!(
        written.contains("# updated by satqual update from 1e5 (3 paired modes, residual"),
        "{written}"
    );
    assert!(
        written.contains("# updated by satqual update from 0.001 (3 paired modes"),
        "{written}"
    );
    let reloaded = load(out.to_str().unwrap());
    let c = correlate::run(&reloaded).unwrap();
    for (p, t) in c.pairs.iter().zip(json["targets"].as_array().unwrap()) {
        let after = t["after_hz"].as_f64().unwrap();
        assert!(
            rel(p.fe_hz, after) < 1e-9,
            "mode {}: {} vs {after}",
            p.test_mode,
            p.fe_hz
        );
    }
    let (code, _, stderr) = run_text(&["update", USC, "--out", USC], None);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("is the input scene"), "{stderr}");
    assert_eq!(std::fs::read(crate::common::repo_path(USC)).unwrap(), input);
}

/// Running out of iterations is said, not hidden: one iteration from 30% off cannot converge
/// (the noise-free run needs 5); `converged` is false, a warning says so, and the command exits
/// 1 while still writing the last iterate.
#[test]
fn running_out_of_iterations_is_a_warning_and_exit_code_1() {
    let test = true_frequencies();
    let start = [TRUE[0] * 1.3, TRUE[1] * 0.7, TRUE[2] * 1.3];
    let text = round_trip_scene(
        start,
        &test,
        &update_section("").replace("max_iterations = 50", "max_iterations = 1"),
    );
    let u = update::run(&parse(&text)).unwrap();
    assert!(
        !u.converged && u.iterations == 1,
        "{} {}",
        u.converged,
        u.iterations
    );
    assert!(
        u.warnings.iter().any(|w| w.starts_with("not converged")),
        "{:?}",
        u.warnings
    );
    let dir = temp_dir("update-maxit");
    let (scene, out) = (dir.join("scene.toml"), dir.join("updated.toml"));
    std::fs::write(&scene, &text).unwrap();
    let (code, stdout, stderr) = run_text(
        &[
            "update",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert!(stdout.contains("NOT converged") && out.exists(), "{stdout}");
}

#[test]
fn the_report_shows_parameters_frequencies_and_mac_before_and_after() {
    // The USC beam update (frequencies 6.62 / 41.4 / 117.5 Hz, upstream impulse test): the
    // report's frequency table carries the same before/after values as the JSON, and both MAC
    // heat maps are written; the folder is complete (md, html, json, plots).
    let dir = temp_dir("update-report");
    let (out, report) = (dir.join("updated.toml"), dir.join("report"));
    let (code, stdout, stderr) = run_text(
        &[
            "update",
            USC,
            "--out",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
            "--json",
        ],
        None,
    );
    assert_eq!(code, 0, "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let md = std::fs::read_to_string(report.join("report.md")).unwrap();
    for section in [
        "## Parameters",
        "## Frequencies",
        "## Correlation of the updated model",
        "## Identifiability",
        "## Plots",
    ] {
        assert!(md.contains(section), "{section} missing");
    }
    for t in json["targets"].as_array().unwrap() {
        let row = format!(
            "| {:.4} | {:.4} | {:.4} |",
            t["test_hz"].as_f64().unwrap(),
            t["before_hz"].as_f64().unwrap(),
            t["after_hz"].as_f64().unwrap()
        );
        assert!(md.contains(&row), "{row} not in the report");
    }
    for f in [
        "report.html",
        "results.json",
        "plots/mac-before.svg",
        "plots/mac-after.svg",
    ] {
        assert!(report.join(f).is_file(), "{f} missing");
    }
    let html = std::fs::read_to_string(report.join("report.html")).unwrap();
    assert!(html.contains("<svg"), "the heat maps are inline");
}
