//! The preloaded stack: calibration against the paper's shaker test, the preload
//! path, buckling, the expansion round trip, and bad stack input.

use satqual::modal::ModalSystem;
use satqual::spec::Scene;
use std::path::Path;

use crate::common::load;

fn solve(scene: &Scene) -> (satqual::fem::FeModel, ModalSystem) {
    satqual::pipeline::modal(scene, None, None).unwrap_or_else(|e| panic!("{e}"))
}

fn with_text(scene: &Scene, from: &str, to: &str) -> Scene {
    assert!(scene.text.contains(from), "scene lacks {from:?}");
    Scene::parse(&scene.path, &scene.text.replacen(from, to, 1)).unwrap()
}

/// The mode with the largest effective-mass fraction along `dir` (0 = x, 1 = y, 2 = z): the
/// resonance a sine sweep along that axis excites most.
fn dominant(sys: &ModalSystem, dir: usize) -> f64 {
    sys.result
        .modes
        .iter()
        .max_by(|a, b| {
            a.effective_mass_fraction.to_array()[dir]
                .total_cmp(&b.effective_mass_fraction.to_array()[dir])
        })
        .unwrap()
        .frequency_hz
}

#[test]
fn shaker_2sat_matches_measured_modes() {
    // Source: paper §5.1.1 / Fig. 17a, measured first resonances x 29.1 Hz, y 31.2 Hz,
    // z 77.6 Hz. Tolerance 3% (the calibration's acceptance
    // limit); the joint stiffnesses were calibrated for this.
    let (_, sys) = solve(&load("test-specs/shaker-2sat.toml"));
    for (dir, measured) in [(0, 29.1), (1, 31.2), (2, 77.6)] {
        let f = dominant(&sys, dir);
        assert!(
            (f - measured).abs() / measured < 0.03,
            "axis {dir}: model {f:.2} Hz vs measured {measured} Hz"
        );
    }
}

fn bar_and_interface_forces(
    model: &satqual::fem::FeModel,
    sys: &ModalSystem,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let ps = sys
        .result
        .prestress
        .as_ref()
        .expect("a stack is prestressed");
    let mut bars = Vec::new();
    for m in &ps.members {
        if m.name.starts_with("bar ") && m.name.ends_with("segment 1") {
            bars.push(m.axial_force_n);
        }
    }
    // Interface springs, grouped by level (the text before " column").
    let mut levels: Vec<(String, Vec<f64>)> = Vec::new();
    for s in &ps.springs {
        if let Some(level) = s.name.strip_prefix("interface ") {
            let key = level.split(" column").next().unwrap().to_string();
            match levels.iter_mut().find(|(k, _)| *k == key) {
                Some((_, v)) => v.push(s.force_n[2]),
                None => levels.push((key, vec![s.force_n[2]])),
            }
        }
    }
    let _ = model;
    (bars, levels.into_iter().map(|(_, v)| v).collect())
}

#[test]
fn preload_path_is_closed() {
    // Equilibrium of the clamped loop (exact): the four bar tensions sum to the preload, and
    // the four column joints at every level carry the same total in compression. 1e-9 relative.
    let scene = load("test-specs/paper-stack.toml");
    let p = scene.file.stack.as_ref().unwrap().preload_total_n;
    let (model, sys) = solve(&scene);
    let (bars, levels) = bar_and_interface_forces(&model, &sys);
    assert_eq!(bars.len(), 4);
    let t: f64 = bars.iter().sum();
    assert!(
        (t - p).abs() <= 1e-9 * p,
        "bar tensions sum to {t} N, preload {p} N"
    );
    assert!(bars.iter().all(|&b| b > 0.0), "bars in tension: {bars:?}");
    assert_eq!(levels.len(), 6, "one joint level under each satellite");
    for l in &levels {
        assert_eq!(l.len(), 4);
        let c: f64 = l.iter().sum();
        assert!(
            (c + p).abs() <= 1e-9 * p,
            "joint level carries {c} N, expected −{p} N"
        );
    }
    let lambda = sys
        .result
        .prestress
        .as_ref()
        .unwrap()
        .buckling_factor
        .expect("columns in compression can buckle");
    assert!(lambda > 1.0, "buckling factor {lambda}");
}

/// Kinetic-energy share of the guide-bar nodes in a mode.
fn bar_share(model: &satqual::fem::FeModel, sys: &ModalSystem, mode: usize) -> f64 {
    let shape = &sys.result.modes[mode].shape;
    let mut mphi = vec![0.0; shape.len()];
    for &(i, j, v) in &sys.m {
        mphi[i] += v * shape[j];
    }
    let mut bar = 0.0;
    for (r, &full) in sys.reduction.red_to_full.iter().enumerate() {
        let node = &model.nodes[full / 6];
        // Scene nodes of the bars have ids ≥ 10000000; the nodes inside a subdivided bar
        // segment are labelled after their member, "bar c segment j".
        if node.id.is_some_and(|id| id >= 10_000_000) || node.label.starts_with("bar ") {
            bar += shape[r] * mphi[r];
        }
    }
    bar
}

#[test]
fn doubling_the_preload_follows_beam_column_theory() {
    // Source: exact beam-column results for one bar. Lateral frequency of a pinned-pinned bar
    // under tension N: f = f0·√(1 + N·L²/(π²EI)), so f(2N)/f(N) = √((1+2a)/(1+a)), a = N·L²/(π²EI).
    // Linear buckling: K_G is proportional to the preload, so λ(2P) = λ(P)/2 exactly (1e-9).
    // The modes compared are the stack's pure bar modes: combinations of the four bars that
    // leave the satellites at rest (≥ 99.9% of the kinetic energy in the bars), i.e. one bar
    // pinned at its root and held laterally by the compression device. The free 0.2 m stub
    // above the device and the device's lateral compliance are what the formula leaves out:
    // frequencies and the ratio are compared within 0.5%.
    let scene = load("test-specs/paper-stack.toml");
    let doubled = with_text(
        &scene,
        "preload_total_n = 45000.0",
        "preload_total_n = 90000.0",
    );
    let (m1, s1) = solve(&scene);
    let (m2, s2) = solve(&doubled);
    let l1 = s1
        .result
        .prestress
        .as_ref()
        .unwrap()
        .buckling_factor
        .unwrap();
    let l2 = s2
        .result
        .prestress
        .as_ref()
        .unwrap()
        .buckling_factor
        .unwrap();
    assert!(
        (l2 - l1 / 2.0).abs() <= 1e-9 * l1,
        "λ(P) = {l1}, λ(2P) = {l2}"
    );
    let first_bar_mode = |m: &satqual::fem::FeModel, s: &ModalSystem| {
        (0..s.result.modes.len())
            .find(|&k| bar_share(m, s, k) > 0.999)
            .map(|k| s.result.modes[k].frequency_hz)
            .unwrap()
    };
    let (f1, f2) = (first_bar_mode(&m1, &s1), first_bar_mode(&m2, &s2));
    let st = scene.file.stack.as_ref().unwrap();
    let l = st.stack_top_z();
    let ei = 200e9 * std::f64::consts::PI * st.bar_diameter_m.powi(4) / 64.0;
    let a = st.preload_total_n / 4.0 * l * l / (std::f64::consts::PI.powi(2) * ei);
    let expect = ((1.0 + 2.0 * a) / (1.0 + a)).sqrt();
    assert!(f2 > f1, "tension stiffens the bars: {f1} -> {f2}");
    assert!(
        ((f2 / f1) - expect).abs() / expect < 5e-3,
        "ratio {} vs beam-column {expect}",
        f2 / f1
    );
    let mu = 7850.0 * std::f64::consts::PI * st.bar_diameter_m.powi(2) / 4.0;
    let f0 = std::f64::consts::PI / (2.0 * l * l) * (ei / mu).sqrt();
    let exact = f0 * (1.0 + a).sqrt();
    assert!(
        (f1 - exact).abs() / exact < 5e-3,
        "bar mode {f1} Hz vs beam-column {exact} Hz"
    );
}

#[test]
fn expanded_model_solves_to_the_same_answer() {
    // `satqual expand` writes the generic model; loading that text must give the same modes
    // (same arithmetic, so to round-off: 1e-12 relative).
    let scene = load("test-specs/shaker-2sat.toml");
    let text = toml::to_string(&scene.model).unwrap();
    let generic = Scene::parse(Path::new("expanded.toml"), &text).unwrap();
    assert!(generic.file.stack.is_none());
    let (_, a) = solve(&scene);
    let (_, b) = solve(&generic);
    assert_eq!(a.result.modes.len(), b.result.modes.len());
    for (x, y) in a.result.modes.iter().zip(&b.result.modes) {
        assert!((x.frequency_hz - y.frequency_hz).abs() <= 1e-12 * x.frequency_hz.abs().max(1.0));
    }
    // And through the binary.
    let out = crate::common::satqual()
        .args(["expand", "test-specs/shaker-2sat.toml"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("[[preload]]") && s.contains("[[spring]]") && !s.contains("[stack]"));
}

/// The expanded reference scene (with `[calibration]`, `[separation]` and the stack's default
/// response points) loads as it is written: the sections that act on the stack's parameters
/// are left out with a note, and `sine` gives the same peak at every stack response point
/// (same model and arithmetic: the printed values, to their 3 decimals, are equal).
#[test]
fn the_expanded_reference_scene_loads_and_keeps_its_response_points() {
    let dir = crate::common::temp_dir("expand-reference");
    let out = crate::common::satqual()
        .args(["expand", "test-specs/paper-stack.toml"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("# Left out: [separation], [calibration]"),
        "{}",
        &text[..600]
    );
    for section in ["[separation]", "[calibration]", "[stack]"] {
        assert!(!text.contains(&format!("\n{section}")), "{section} written");
    }
    let p = dir.join("expanded.toml");
    std::fs::write(&p, &text).unwrap();
    let peaks = |scene: &str| {
        let (code, out, err) = crate::common::run_text(&["sine", scene, "--axis", "x"], None);
        assert!(code == 0 || code == 1, "{err}");
        out.lines()
            .filter(|l| l.contains(" peak "))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let original = peaks("test-specs/paper-stack.toml");
    assert!(original.iter().any(|l| l.contains("sat 6")), "{original:?}");
    assert_eq!(peaks(p.to_str().unwrap()), original);
}

fn stack_err(from: &str, to: &str) -> String {
    let scene = load("test-specs/shaker-2sat.toml");
    assert!(scene.text.contains(from), "scene lacks {from:?}");
    let text = scene.text.replacen(from, to, 1);
    match Scene::parse(Path::new("bad-stack.toml"), &text) {
        Err(e) => e.to_string(),
        Ok(s) => satqual::pipeline::modal(&s, None, None)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_else(|| panic!("{to} accepted")),
    }
}

refused_input_cases! {
    error: stack_err;
    no_satellites: "satellites = 2 " => "satellites = 0 ",
        contains ["stack.satellites", "at least one satellite"], starting "bad-stack.toml:";
    zero_preload: "preload_total_n = 45000.0" => "preload_total_n = 0.0",
        contains ["stack.preload_total_n", "must be positive"];
    negative_preload: "preload_total_n = 45000.0" => "preload_total_n = -5.0",
        contains ["stack.preload_total_n"];
    bars_shorter_than_the_stack: "bar_length_m = 1.2" => "bar_length_m = 0.9",
        contains ["stack.bar_length_m", "shorter than the stack"];
    bar_wider_than_the_bore: "bar_diameter_m = 0.020" => "bar_diameter_m = 0.030",
        contains ["stack.bar_diameter_m", "does not fit"];
    // Columns wider than their 0.9 m spacing would overlap each other (a diameter typed in
    // millimetres is refused before, by its plausible range: tests/hostile_inputs.rs).
    column_wider_than_its_spacing: "column_outer_diameter_m = 0.050" => "column_outer_diameter_m = 1.5",
        contains ["stack.column_outer_diameter_m", "columns of 1.5 m outer diameter overlap"];
    shear_key_of_an_unknown_material: "material = \"al7075-t6\", shear_area" => "material = \"ti\", shear_area",
        contains ["stack.interface.shear_key.material", "material `ti` is not defined"];
    shear_key_with_a_zero_area: "shear_area_m2 = 6.715e-4" => "shear_area_m2 = 0.0",
        contains ["stack.interface.shear_key.shear_area_m2", "must be positive"];
    buckling_mesh_of_no_elements: "column_elements = 1" => "column_elements = 1\nbuckling_column_elements = 0",
        contains ["stack.buckling_column_elements", "at least 1"];
    shear_key_with_an_unknown_key: "bearing_area_m2 = 3.6e-4" => "bearing_area_m2 = 3.6e-4, length_m = 0.01",
        contains ["unknown field `length_m`"];
}

#[test]
fn preload_above_buckling_load_is_an_error() {
    // 45 kN scaled by 1e4: far above the columns' buckling load; the error gives that load.
    let e = stack_err("preload_total_n = 45000.0", "preload_total_n = 4.5e8");
    assert!(
        e.contains("stack.preload_total_n") && e.contains("above the stack's buckling load"),
        "{e}"
    );
    assert!(e.contains(" N (buckling factor"), "{e}");
}

#[test]
fn modal_json_lists_prestress_members() {
    let out = crate::common::satqual()
        .args(["modal", "test-specs/shaker-2sat.toml", "--json"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let ps = &v["prestress"];
    assert!(ps["buckling_factor"].as_f64().unwrap() > 1.0);
    let members = ps["members"].as_array().unwrap();
    assert!(
        members
            .iter()
            .any(|m| m["name"] == "bar 1 segment 1"
                && m["axial_force_n"].as_f64().unwrap() > 11_000.0)
    );
    assert!(
        members
            .iter()
            .any(|m| m["name"].as_str().unwrap().contains("column"))
    );
}

#[test]
fn closed_bores_brace_a_long_stack() {
    // 120 satellites on 66 m guide bars (one 0.55 m pitch per satellite added). With open
    // bores the columns form one 66 m Euler column under 45 kN, braced only at the base and
    // the compression device: beyond its buckling load (factor 0.62, reported by `satqual
    // bench modal`), which must be an error. With the bars bearing on the bores at every level
    // (`bar_bore = "closed"`), bar tension and column compression act on one laterally tied
    // section: the global mode disappears and only short column segments can buckle, so the
    // factor must exceed 1, and the axial preload path (lateral springs only) stays exact.
    let base = load("test-specs/paper-stack.toml");
    let text = satqual::catalogue::generated::stack_with_satellites(&base.text, 120);
    let long = Scene::parse(&base.path, &text).unwrap();
    let open = satqual::pipeline::modal(&long, None, Some(1))
        .expect_err("open bores: beyond the buckling load")
        .to_string();
    assert!(open.contains("above the stack's buckling load"), "{open}");
    let closed = Scene::parse(
        &base.path,
        &satqual::catalogue::generated::with_closed_bores(&text),
    )
    .unwrap();
    let (model, sys) =
        satqual::pipeline::modal(&closed, None, Some(1)).unwrap_or_else(|e| panic!("{e}"));
    let ps = sys.result.prestress.as_ref().unwrap();
    let lambda = ps
        .buckling_factor
        .expect("columns in compression can buckle");
    assert!(lambda > 1.0, "closed bores: buckling factor {lambda}");
    let p = 45000.0;
    let (bars, levels) = bar_and_interface_forces(&model, &sys);
    let t: f64 = bars.iter().sum();
    assert!((t - p).abs() <= 1e-9 * p, "bar tensions sum to {t} N");
    assert_eq!(levels.len(), 120);
    for l in &levels {
        let c: f64 = l.iter().sum();
        assert!((c + p).abs() <= 1e-9 * p, "joint level carries {c} N");
    }
    // Every closed contact is there: 4 bars × 120 levels.
    let contacts = ps
        .springs
        .iter()
        .filter(|s| s.name.contains("bore contact"))
        .count();
    assert_eq!(contacts, 480);
}

#[test]
fn buckling_is_refused_before_the_modes_are_extracted() {
    // The stop comes from `modal::analyze` itself, right after the buckling solve, so a stack
    // beyond its buckling load costs no eigen-solve. Without the stop the same model yields
    // modes and the factor (< 1) for whoever asks for them explicitly.
    use satqual::error::ModalError;
    use satqual::modal::{ModalOptions, analyze};
    let scene = with_text(
        &load("test-specs/paper-stack.toml"),
        "preload_total_n = 45000.0",
        "preload_total_n = 4.5e8",
    );
    let model = satqual::pipeline::fe_model(&scene).unwrap();
    let opts = |stop| ModalOptions {
        fmax_hz: Some(500.0),
        modes: None,
        solver: Default::default(),
        stop_beyond_buckling: stop,
        ..Default::default()
    };
    match analyze(&model, &opts(true)) {
        Err(satqual::Error::Modal(ModalError::BeyondBuckling { factor })) => {
            assert!(factor > 0.0 && factor < 1.0, "factor {factor}")
        }
        Err(e) => panic!("expected BeyondBuckling, got {e}"),
        Ok(_) => panic!("expected BeyondBuckling, got modes"),
    }
    let sys = analyze(&model, &opts(false)).unwrap_or_else(|e| panic!("{e}"));
    let factor = sys.result.prestress.unwrap().buckling_factor.unwrap();
    assert!(factor < 1.0, "factor {factor}");
}

/// The buckling factor is taken on `buckling_column_elements` per half column (default 4),
/// the modes on `column_elements`. References: the same stack meshed at 4 for the modes too
/// (the same buckling model, solved once sparse and once by the modes' solver: 1e-9), and the
/// convergence table of docs/fem.md (`satqual modal`, 4-decimal values: 50.8998 at 1 element,
/// 50.6419 at 4; to 1e-4 of the last printed digit).
#[test]
fn the_buckling_factor_is_taken_on_the_finer_column_mesh() {
    let factor = |scene: &Scene| {
        let (_, sys) = solve(scene);
        let ps = sys.result.prestress.expect("preloaded");
        (ps.buckling_factor.expect("buckles"), ps.buckling_model)
    };
    let scene = load("test-specs/paper-stack.toml");
    let (default, on) = factor(&scene);
    assert!(on.unwrap().contains("4 elements per half column"));
    let fine = with_text(&scene, "column_elements = 1", "column_elements = 4");
    let (fine_factor, fine_on) = factor(&fine);
    assert!(fine_on.is_none(), "the modes' model is the buckling model");
    assert!(
        (default - fine_factor).abs() < 1e-9 * fine_factor,
        "{default} {fine_factor}"
    );
    assert!((default - 50.6419).abs() < 1e-4, "{default}");
    let coarse = with_text(
        &scene,
        "column_elements = 1",
        "column_elements = 1\nbuckling_column_elements = 1",
    );
    let (coarse_factor, coarse_on) = factor(&coarse);
    assert!(coarse_on.is_none());
    assert!((coarse_factor - 50.8998).abs() < 1e-4, "{coarse_factor}");
}
