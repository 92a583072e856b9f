//! Model updating: run time and iterations against the error of the recovered parameters, on
//! the round-trip cantilever of [`crate::catalogue::generated::update_round_trip_scene`] (E,
//! root spring and tip mass started 30% off, test frequencies from the true values with
//! seeded noise), and on the USC shaker beam's measured modes.

use crate::Error;
use crate::catalogue::generated::{
    STACK_UPDATE_PARAMS, UPDATE_TRUE, stack_update_model, stack_update_tables,
    update_round_trip_scene, update_section,
};
use crate::pipeline::workflows::{correlate, update};
use crate::spec::Scene;
use rand::SeedableRng;
use serde_json::{Value, json};
use std::path::Path;
use std::time::Instant;

/// The USC beam scene whose clamp spring and tip mass are updated to its impulse-test modes.
const USC: &str = "test-specs/correlation/usc-beam-update.toml";

fn parse(text: &str) -> Result<Scene, Error> {
    Ok(Scene::parse(Path::new("round-trip.toml"), text)?)
}

/// The first five z-bending frequencies at the true values: the synthetic test.
fn true_frequencies() -> Result<Vec<f64>, Error> {
    let c = correlate::run(&parse(&update_round_trip_scene(UPDATE_TRUE, &[10.0], ""))?)?;
    Ok(c.fe_modes
        .iter()
        .filter(|m| m.direction == Some("z"))
        .map(|m| m.frequency_hz)
        .take(5)
        .collect())
}

/// A standard normal draw (Box–Muller), for the seeded noise.
fn gauss(rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
    use rand::RngExt;
    let u1: f64 = rng.random::<f64>().max(1e-300);
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// One update timed: best wall time of `reps`, with its result's figures.
fn timed(scene: &Scene, reps: usize) -> Result<(f64, update::Update), Error> {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..reps {
        let t = Instant::now();
        let u = update::run(scene)?;
        best = best.min(t.elapsed().as_secs_f64());
        last = Some(u);
    }
    Ok((best, last.expect("reps ≥ 1")))
}

fn round_trip_row(test: &[f64], noise: f64) -> Result<Value, Error> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
    let noisy: Vec<f64> = test
        .iter()
        .map(|f| f * (1.0 + noise * gauss(&mut rng)))
        .collect();
    let start = [
        UPDATE_TRUE[0] * 1.3,
        UPDATE_TRUE[1] * 0.7,
        UPDATE_TRUE[2] * 1.3,
    ];
    let scene = parse(&update_round_trip_scene(start, &noisy, &update_section("")))?;
    let (seconds, u) = timed(&scene, 3)?;
    let max_err = u
        .parameters
        .iter()
        .zip(UPDATE_TRUE)
        .map(|(p, t)| (p.value / t - 1.0).abs())
        .fold(0.0, f64::max);
    Ok(json!({
        "case": format!("round trip, {:.1}% noise", 100.0 * noise),
        "seconds": seconds, "iterations": u.iterations, "converged": u.converged,
        "max_parameter_error": max_err,
        "rms_frequency_error_before_pct": u.residual_before_pct,
        "rms_frequency_error_after_pct": u.residual_after_pct,
    }))
}

/// The laterally moving modes (x or y effective mass) of the stack of `n` satellites at the
/// paper stack's values, read by the accelerometer on satellite 1: the synthetic test.
fn stack_test_modes(base: &str, n: usize) -> Result<Vec<(f64, Vec<f64>)>, Error> {
    let values = STACK_UPDATE_PARAMS.map(|p| p.1);
    let placeholder =
        "\n[test_modes]\n[[test_modes.mode]]\nfrequency_hz = 1.0\nshape = [1.0, 0.0, 0.0]\n";
    let text = stack_update_model(base, n, STACK_MODES, &values) + placeholder;
    let c = correlate::run(&parse(&text)?)?;
    Ok(c.fe_modes
        .iter()
        .filter(|m| matches!(m.direction, Some("x") | Some("y")))
        .map(|m| (m.frequency_hz, m.shape.clone()))
        .collect())
}

/// The stack of `n` satellites updated from the start of [`STACK_UPDATE_PARAMS`] to its
/// synthetic test modes.
fn stack_row(n: usize) -> Result<Value, Error> {
    let path = Path::new(crate::catalogue::PAPER_STACK);
    let base = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let test = stack_test_modes(&base, n)?;
    let values = STACK_UPDATE_PARAMS.map(|p| p.1 * p.2);
    let text = stack_update_model(&base, n, STACK_MODES, &values) + &stack_update_tables(&test);
    let scene = parse(&text)?;
    let (seconds, u) = timed(&scene, 1)?;
    let max_err = u
        .parameters
        .iter()
        .zip(STACK_UPDATE_PARAMS)
        .map(|(p, t)| (p.value / t.1 - 1.0).abs())
        .fold(0.0, f64::max);
    Ok(json!({
        "case": format!("{n}-satellite stack ({} test modes), 4 parameters (joint bending and axial stiffness, satellite mass, column diameter), started +30/−30/+30/−30%", test.len()),
        "seconds": seconds, "iterations": u.iterations, "converged": u.converged,
        "max_parameter_error": max_err,
        "rms_frequency_error_before_pct": u.residual_before_pct,
        "rms_frequency_error_after_pct": u.residual_after_pct,
    }))
}

/// FE modes each solve of the stack update extracts (sparse): the lowest lateral ones are
/// the targets.
const STACK_MODES: usize = 16;

pub fn run() -> Result<(String, String), Error> {
    let test = true_frequencies()?;
    let mut rows = Vec::new();
    for noise in [0.0, 0.005, 0.02] {
        eprintln!("bench update: round trip, {:.1}% noise ...", 100.0 * noise);
        rows.push(round_trip_row(&test, noise)?);
    }
    eprintln!("bench update: USC beam ...");
    let (seconds, u) = timed(&Scene::load(Path::new(USC))?, 3)?;
    rows.push(json!({
        "case": "USC beam (measured modes), clamp spring + tip mass",
        "seconds": seconds, "iterations": u.iterations, "converged": u.converged,
        "max_parameter_error": Value::Null,
        "rms_frequency_error_before_pct": u.residual_before_pct,
        "rms_frequency_error_after_pct": u.residual_after_pct,
    }));
    eprintln!("bench update: 60-satellite stack, 4 parameters ...");
    rows.push(stack_row(60)?);
    let report = json!({
        "what": "satqual update: bounded Levenberg-Marquardt with analytic eigenvalue sensitivities; best wall time of 3",
        "threads": rayon::current_num_threads(),
        "rows": rows,
    });
    Ok((super::to_json(&report)?, markdown(&report)))
}

fn markdown(r: &Value) -> String {
    let mut s = String::from("# satqual bench update\n\n");
    s.push_str(&format!(
        "{} ({} rayon threads). Round trip: the cantilever of `catalogue::generated::update_round_trip_scene`, E, root spring and tip mass started +30/−30/+30% off, test frequencies (five z-bending modes) from the true values times (1 + noise·g), g standard normal, seed 19. The parameter error is the largest relative error against the true values. Stack: `test-specs/paper-stack.toml` with N satellites (bars lengthened with the stack), the lowest 16 modes per solve (sparse), every other analysis dropped; its test modes are its own laterally moving modes at the paper stack's values, read by a triaxial accelerometer on satellite 1, paired by MAC; one run of `update` (the synthetic test made before the clock starts).\n\n",
        r["what"].as_str().unwrap_or(""),
        r["threads"]
    ));
    s.push_str("| case | wall [s] | iterations | converged | max parameter error | RMS frequency error before → after |\n|---|---:|---:|---|---:|---|\n");
    for row in r["rows"].as_array().into_iter().flatten() {
        s.push_str(&format!(
            "| {} | {:.3} | {} | {} | {} | {:.3}% → {:.3}% |\n",
            row["case"].as_str().unwrap_or(""),
            row["seconds"].as_f64().unwrap_or(f64::NAN),
            row["iterations"],
            row["converged"],
            row["max_parameter_error"]
                .as_f64()
                .map_or("– (no truth)".into(), |e| format!("{e:.2e}")),
            row["rms_frequency_error_before_pct"]
                .as_f64()
                .unwrap_or(0.0),
            row["rms_frequency_error_after_pct"].as_f64().unwrap_or(0.0),
        ));
    }
    s
}
