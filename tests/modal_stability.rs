//! Numerical stability of the modal solve: stiff springs against the clamped beam they
//! emulate, a free-free beam and a mechanism (rigid-body modes at 0 Hz), the conditioning
//! warning, a preload just below and just above buckling, and a qualification that has nothing
//! to stand on. Every model is the 1 m, 20 × 20 mm steel beam of
//! `test-specs/verification/cantilever.toml` (20 Euler-Bernoulli elements): EI = 2800 N·m²,
//! ρA = 3.14 kg/m, EA/L = 8.4e7 N/m.

use crate::common::{load, parse, rel};
use satqual::modal::ModalResult;
use satqual::spec::SolverChoice;
use std::f64::consts::PI;

const CANTILEVER: &str = "test-specs/verification/cantilever.toml";
const EI: f64 = 210e9 * 0.02 * 0.02 * 0.02 * 0.02 / 12.0;
const RHO_A: f64 = 7850.0 * 0.02 * 0.02;
const EA_OVER_L: f64 = 210e9 * 0.02 * 0.02;

/// Euler-Bernoulli beam frequency for the root βL of its boundary conditions (L = 1 m):
/// f = (βL)² / (2π) · √(EI / ρA).
fn beam_hz(beta_l: f64) -> f64 {
    beta_l * beta_l / (2.0 * PI) * (EI / RHO_A).sqrt()
}

fn scene_text() -> String {
    std::fs::read_to_string(crate::common::repo_path(CANTILEVER)).unwrap()
}

fn modes_of(text: &str, modes: usize) -> ModalResult {
    modes_with(text, modes, SolverChoice::Auto)
}

fn modes_with(text: &str, modes: usize, solver: SolverChoice) -> ModalResult {
    let scene = parse(text);
    satqual::pipeline::modal_with_solver(&scene, None, Some(modes), Some(solver))
        .unwrap_or_else(|e| panic!("{solver:?}: {e}"))
        .1
        .result
}

/// Both solvers, each held to the same checks.
const SOLVERS: [SolverChoice; 2] = [SolverChoice::Dense, SolverChoice::Sparse];

fn clamped() -> ModalResult {
    let scene = load(&crate::common::repo_path(CANTILEVER).display().to_string());
    satqual::pipeline::modal(&scene, None, Some(10))
        .unwrap()
        .1
        .result
}

/// The cantilever with its clamp replaced by a spring to a supported node 9.
fn root_spring(k: [f64; 6]) -> String {
    let spring = format!(
        "[[node]]\nid = 9\nposition_m = [0.0, 0.0, 0.0]\n\n[[spring]]\nname = \"root\"\nnodes = [9, 1]\nstiffness = {k:?}\n\n[[support]]\nnode = 9"
    );
    scene_text().replacen("[[support]]\nnode = 1", &spring, 1)
}

/// Reference: the clamped scene's own modes (so the mesh error cancels), to 1e-6 relative; the
/// springs k = r·(EA/L, EI/L) emulate the clamp to 1/r, far below that for r ≥ 1e8. Before the
/// shift-invert solve, r = 1e12 gave −2.6% / +8.4% and r = 1e15 negative eigenvalues.
#[test]
fn stiff_root_springs_give_the_clamped_frequencies() {
    let reference = clamped();
    for r in [1e8, 1e10, 1e12, 1e15] {
        let (t, b) = (r * EA_OVER_L, r * EI);
        for solver in SOLVERS {
            let res = modes_with(&root_spring([t, t, t, b, b, b]), 10, solver);
            for i in 0..8 {
                let (f, f0) = (res.modes[i].frequency_hz, reference.modes[i].frequency_hz);
                let s = &res.solver;
                assert!(
                    rel(f, f0) < 1e-6,
                    "{s}, r = {r:e}, mode {}: {f} vs {f0}",
                    i + 1
                );
            }
            assert_eq!(res.rigid_body_modes, 0);
        }
        let dense = modes_with(&root_spring([t, t, t, b, b, b]), 10, SolverChoice::Dense);
        let dense = dense.dense.as_ref().expect("dense solver");
        assert!(dense.max_backward_error < 1e-8, "r = {r:e}: {dense:?}");
    }
    // The clamped model itself against βL = 1.875104 (clamped-free), within the 20-element
    // mesh error of a cubic beam (1e-4).
    let f1 = beam_hz(1.875_104_07);
    assert!(rel(reference.modes[0].frequency_hz, f1) < 1e-4);
    assert!(rel(reference.modes[1].frequency_hz, f1) < 1e-4);
}

/// The cantilever cut at mid-span into two 10-element halves whose coincident end nodes are
/// tied by the spring `tie` of k = 1e12 in all six DOFs.
fn tied_beam() -> String {
    let tie = "[[node]]\nid = 3\nposition_m = [0.5, 0.0, 0.0]\n\n[[node]]\nid = 4\nposition_m = [0.5, 0.0, 0.0]\n\n[[spring]]\nname = \"tie\"\nnodes = [3, 4]\nstiffness = [1e12, 1e12, 1e12, 1e12, 1e12, 1e12]\n\n[[beam]]\nnodes = [1, 3]";
    let second = "theory = \"euler-bernoulli\"\n\n[[beam]]\nnodes = [4, 2]\nsection = \"bar\"\nmaterial = \"steel\"\nelements = 10\norientation = [0.0, 0.0, 1.0]\ntheory = \"euler-bernoulli\"\n";
    scene_text()
        .replacen("[[beam]]\nnodes = [1, 2]", tie, 1)
        .replacen("elements = 20", "elements = 10", 1)
        .replacen("theory = \"euler-bernoulli\"\n", second, 1)
}

/// The beam cut at mid-span into two 10-element halves whose coincident end nodes are tied by
/// k = 1e12 in all six DOFs: the same modes as the continuous beam (the clamped scene, 1e-6
/// relative). Before, +53% dense, −8% sparse. The tie is 1.8e7 times the rotational stiffness
/// of an element (4EI/Le = 2.2e5 N·m): MAXRATIO above 1e7, so a warning names it.
#[test]
fn a_stiff_tie_at_mid_span_keeps_the_continuous_beam_and_is_flagged() {
    let text = tied_beam();
    let reference = clamped();
    for solver in SOLVERS {
        let res = modes_with(&text, 10, solver);
        for i in 0..8 {
            let (f, f0) = (res.modes[i].frequency_hz, reference.modes[i].frequency_hz);
            let s = &res.solver;
            assert!(rel(f, f0) < 1e-6, "{s}, mode {}: {f} vs {f0}", i + 1);
        }
        let max_ratio = match (&res.dense, &res.sparse) {
            (Some(d), _) => d.max_ratio,
            (_, Some(s)) => s.max_ratio,
            _ => panic!("no solver statistics"),
        };
        assert!(max_ratio > 1e7, "{}: MAXRATIO {max_ratio:e}", res.solver);
        assert!(
            res.warnings
                .iter()
                .any(|w| w.contains("MAXRATIO") && w.contains("tie") && w.contains("[[rigid]]")),
            "{}: {:?}",
            res.solver,
            res.warnings
        );
    }
    let res = modes_of(&text, 10);
    // The same tie at r = 1e15 (8.4e22 N/m, 2.8e18 N·m/rad) is beyond double precision: the
    // modes it gives are not the beam's, and that must not pass silently.
    let beyond = modes_of(
        &text.replacen(
            "[1e12, 1e12, 1e12, 1e12, 1e12, 1e12]",
            "[8.4e22, 8.4e22, 8.4e22, 2.8e18, 2.8e18, 2.8e18]",
            1,
        ),
        10,
    );
    let exact = rel(
        beyond.modes[0].frequency_hz,
        reference.modes[0].frequency_hz,
    ) < 1e-6;
    assert!(
        exact || beyond.warnings.iter().any(|w| w.contains("tie")),
        "{:?}",
        beyond.warnings
    );
    assert!(
        res.warnings
            .iter()
            .any(|w| w.contains("MAXRATIO") && w.contains("tie") && w.contains("[[rigid]]")),
        "{:?}",
        res.warnings
    );
}

fn free_free() -> String {
    scene_text().replacen("[[support]]\nnode = 1\ndofs = \"123456\"\n", "", 1)
}

/// No support: six rigid-body modes at exactly 0 Hz along x, y, z, rx, ry, rz, then the
/// free-free bending pair at βL = 4.730041 (within the 20-element mesh error, 1e-4).
#[test]
fn a_free_free_beam_has_six_rigid_body_modes_at_zero() {
    for solver in SOLVERS {
        free_free_modes_are_checked(modes_with(&free_free(), 8, solver));
    }
}

fn free_free_modes_are_checked(res: ModalResult) {
    assert_eq!(res.rigid_body_modes, 6, "{}", res.solver);
    assert_eq!(res.rigid_body_directions, ["x", "y", "z", "rx", "ry", "rz"]);
    for m in &res.modes[..6] {
        assert!(m.rigid_body && m.frequency_hz == 0.0, "{m:?}");
    }
    let f1 = beam_hz(4.730_040_7);
    assert!(
        rel(res.modes[6].frequency_hz, f1) < 1e-4,
        "{}",
        res.modes[6].frequency_hz
    );
    assert!(rel(res.modes[7].frequency_hz, f1) < 1e-4);
}

/// A mechanism: the root held in translation only (a pin; rotational stiffness 0) leaves three
/// rigid-body rotations about it, then the pinned-free bending pair at βL = 3.926602 (the
/// pinned-free beam's flexible roots equal the clamped-pinned ones), mesh error 1e-4.
#[test]
fn a_pinned_root_is_a_mechanism_with_three_zero_modes() {
    let t = 1e8 * EA_OVER_L;
    for solver in SOLVERS {
        let res = modes_with(&root_spring([t, t, t, 0.0, 0.0, 0.0]), 5, solver);
        assert_eq!(res.rigid_body_modes, 3, "{}", res.solver);
        let f1 = beam_hz(3.926_602_3);
        assert!(
            rel(res.modes[3].frequency_hz, f1) < 1e-4,
            "{}: {}",
            res.solver,
            res.modes[3].frequency_hz
        );
        assert!(rel(res.modes[4].frequency_hz, f1) < 1e-4);
    }
}

/// The cantilever as a column under a tip load P along −x: the model's own buckling load P_cr
/// (from P = 1000 N and its buckling factor) is within the mesh error (1e-4) of Euler's
/// π²EI/(4L²); at 0.99 P_cr the modes come out with buckling factor 1/0.99, at 1.01 P_cr the
/// modal analysis and `qualify` refuse with the [[static_load]] located.
#[test]
fn a_preload_beyond_buckling_is_a_located_error_and_below_it_a_result() {
    let loaded = |p: f64| {
        format!(
            "{}\n[[static_load]]\nnode = 2\nforce_n = [{:?}, 0.0, 0.0]\n",
            scene_text(),
            -p
        )
    };
    let run = |p: f64| satqual::pipeline::modal(&parse(&loaded(p)), None, Some(4));
    let factor = |p: f64| buckling_factor_of(run(p));
    let p_cr = 1000.0 * factor(1000.0);
    assert!(rel(p_cr, PI * PI * EI / 4.0) < 1e-4, "{p_cr}");
    assert!(rel(factor(0.99 * p_cr), 1.0 / 0.99) < 1e-6);
    let below = run(0.99 * p_cr).unwrap().1.result;
    assert!(below.modes.iter().all(|m| m.frequency_hz > 0.0));
    let err = run(1.01 * p_cr)
        .expect_err("beyond buckling must be refused")
        .to_string();
    // `qualify` takes the same modal path and refuses the same way, never a verdict.
    let q = satqual::pipeline::qualify(&parse(&loaded(1.01 * p_cr)), &satqual::pipeline::Silent);
    let Err(qerr) = q else {
        panic!("qualify beyond buckling must be refused")
    };
    assert!(qerr.to_string().contains("static_load[0]"), "{qerr}");
    assert!(
        err.contains("static_load[0]") && err.contains("buckling"),
        "{err}"
    );
}

/// An unsupported model does not qualify: its rigid-body modes are 0 Hz first frequencies,
/// which fail every frequency minimum; nothing is silently dropped.
#[test]
fn an_unsupported_model_does_not_pass_qualify() {
    let q = satqual::pipeline::qualify(&parse(&free_free()), &satqual::pipeline::Silent).unwrap();
    assert!(!q.pass);
    let freq: Vec<_> = q
        .gates
        .iter()
        .filter(|g| g.name.contains("frequency"))
        .collect();
    assert_eq!(freq.len(), 3, "{:?}", q.gates);
    assert!(
        freq.iter()
            .all(|g| !g.pass && g.value == 0.0 && g.name.contains("rigid-body"))
    );
}

/// A near-massless body (1e-6 kg, 1e-12 kg·m²) hung on the tip by a 1e4 N/m spring: its own
/// modes go to the top of the spectrum (√(k/m)/2π ≈ 16 kHz, and 15.9 MHz in rotation) with
/// every frequency finite and positive, and the beam's modes stay the clamped scene's to 1e-6
/// (the mass lowers f₁ by about ½·m·φ_tip² = ½·1e-6·4/(ρAL) = 6.4e-7 relative). The 15.9 MHz
/// modes sit 1e12 above the first in λ, where shift-invert resolves them only to a backward
/// error of ~1e-6: that is reported as a warning naming the mode, not passed over.
#[test]
fn a_near_massless_body_does_not_disturb_the_structure() {
    let body = "[[node]]\nid = 5\nposition_m = [1.0, 0.0, 0.0]\n\n[[mass]]\nnode = 5\nmass_kg = 1e-6\ninertia_kg_m2 = [1e-12, 1e-12, 1e-12]\n\n[[spring]]\nname = \"hanger\"\nnodes = [2, 5]\nstiffness = [1e4, 1e4, 1e4, 1e4, 1e4, 1e4]\n\n[[support]]";
    let text = scene_text().replacen("[[support]]", body, 1);
    let res = modes_of(&text, 1000);
    assert_eq!(res.modes.len(), res.dofs);
    assert!(
        res.modes
            .iter()
            .all(|m| m.frequency_hz.is_finite() && m.frequency_hz > 0.0)
    );
    let dense = res.dense.as_ref().unwrap();
    if dense.max_backward_error > 1e-8 {
        assert!(
            res.warnings.iter().any(|w| w.contains("backward error")),
            "{:?}",
            res.warnings
        );
    }
    let reference = clamped();
    for i in 0..8 {
        let (f, f0) = (res.modes[i].frequency_hz, reference.modes[i].frequency_hz);
        assert!(rel(f, f0) < 1e-6, "mode {}: {f} vs {f0}", i + 1);
    }
}

/// A conditioning warning is not left on stderr of `modal`: `qualify` prints it and the
/// report's first screen lists it (the tie of `tied_beam`, MAXRATIO above 1e7).
#[test]
fn a_conditioning_warning_reaches_the_report() {
    let dir = crate::common::temp_dir("tie-report");
    let scene = dir.join("tie.toml");
    std::fs::write(&scene, tied_beam()).unwrap();
    let out = dir.join("report");
    let (code, _, stderr) = crate::common::run_text(
        &[
            "qualify",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        None,
    );
    assert!(code == 0 || code == 1, "exit {code}: {stderr}");
    assert!(
        stderr.contains("MAXRATIO") && stderr.contains("tie"),
        "{stderr}"
    );
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    let first_section = md.split("\n## ").next().unwrap();
    assert!(
        first_section.contains("warning") && first_section.contains("MAXRATIO"),
        "{first_section}"
    );
}

/// Extreme slenderness: the same 1 m cantilever with a 0.1 mm square section (L/h = 10 000,
/// axial to bending stiffness (L/h)² = 1e8 apart) keeps the clamped-free pair of
/// f = (βL)²/(2π)·√(EI/ρA)/L², βL = 1.875104 (h scales f linearly: 0.1/20 of the 20 mm beam),
/// within the 20-element mesh error (1e-4), on both solvers, with every eigenvalue checked.
#[test]
fn an_extremely_slender_beam_keeps_its_closed_form_frequencies() {
    let h: f64 = 1e-4;
    let text = scene_text()
        .replacen("width_m = 0.02", &format!("width_m = {h}"), 1)
        .replacen("height_m = 0.02", &format!("height_m = {h}"), 1);
    assert_ne!(text, scene_text());
    let f1 = 1.875_104_07f64.powi(2) / (2.0 * PI) * (210e9 * h * h / 12.0 / 7850.0).sqrt();
    for solver in SOLVERS {
        let res = modes_with(&text, 4, solver);
        for m in &res.modes[..2] {
            assert!(
                rel(m.frequency_hz, f1) < 1e-4,
                "{}: {} vs {f1}",
                res.solver,
                m.frequency_hz
            );
        }
        assert!(
            !res.warnings.iter().any(|w| w.contains("working precision")),
            "{}: {:?}",
            res.solver,
            res.warnings
        );
    }
}

/// A finely meshed cantilever (1000 elements, 6000 DOFs, element 1 mm against a 20 mm
/// section): the median K_ii/M_ii puts the bottom shift ~1e6× below the first eigenvalue,
/// where shift-invert cannot separate the low modes unless the first Lanczos shift is moved
/// into the spectrum. Reference: the clamped-free Euler-Bernoulli roots βL = 1.875104,
/// 4.694091 (analytic), within 1e-5 (the 1000-element discretisation error is ~1e-8).
#[test]
fn a_finely_meshed_cantilever_solves_its_low_modes() {
    let text = scene_text().replace("elements = 20", "elements = 1000");
    let res = modes_with(&text, 4, SolverChoice::Sparse);
    let f: Vec<f64> = res.modes.iter().map(|m| m.frequency_hz).collect();
    for (i, beta) in [1.875104, 1.875104, 4.694091, 4.694091].iter().enumerate() {
        assert!(rel(f[i], beam_hz(*beta)) < 1e-5, "mode {}: {}", i + 1, f[i]);
    }
    assert_eq!(res.rigid_body_modes, 0);
}

/// Zero-frequency modes in a model whose supports leave no rigid-body motion free cannot be
/// rigid-body modes: the cantilever meshed so finely (4000 elements of 0.25 mm) that the
/// first bending modes' stiffness φᵀKφ is below the round-off of K (ε·|φ|ᵀ|K||φ| ~ 1e4
/// rad²/s² against λ₁ = 1.1e4) must carry a warning saying so, not a silent
/// "rigid-body modes". The clamped root leaves 0 free motions, a pinned root 3, no support 6.
#[test]
fn zero_modes_beyond_the_free_rigid_motions_are_flagged() {
    let text = scene_text().replace("elements = 20", "elements = 4000");
    let res = modes_with(&text, 6, SolverChoice::Sparse);
    if res.rigid_body_modes > 0 {
        assert!(
            res.warnings
                .iter()
                .any(|w| w.contains("not rigid-body motions")),
            "{:?}",
            res.warnings
        );
    } else {
        assert!(rel(res.modes[0].frequency_hz, beam_hz(1.875104)) < 1e-3);
    }
    for (t, free) in [(free_free(), 6), (scene_text(), 0)] {
        let scene = parse(&t);
        let model = satqual::fem::model::FeModel::from_scene(&scene.model).unwrap();
        let red = model.reduction().unwrap();
        assert_eq!(model.free_rigid_motions(&red), free);
    }
}

/// The paper stack with its column joints made near-rigid by stiffness, as engineers model a
/// rigid connection: 1e9 → 1e12 N/m moved the stack buckling factor by 0.35%, so 1e12 → 1e15
/// moves it by about 1e-3 of that. Reference: the 1e12 model, tolerance 1e-4 relative. (The
/// short Lanczos that brackets the factor from above is loose by seven decades on the 1e15
/// model; the search for a shift below the factor followed it down only 40 steps of 0.7 and
/// gave up.) A rotational joint stiffness of 1e18 N·m/rad, 1e13 times the bars' bending,
/// leaves the static pivot at round-off: refused, naming the stiff spring as a cause.
#[test]
fn near_rigid_stack_joints_keep_the_buckling_factor() {
    let stack =
        std::fs::read_to_string(crate::common::repo_path("test-specs/paper-stack.toml")).unwrap();
    let with = |key: &str, value: &str| {
        let line = stack
            .lines()
            .find(|l| l.starts_with(&format!("{key} =")))
            .unwrap();
        stack.replacen(line, &format!("{key} = {value}"), 1)
    };
    let factor =
        |text: &str| buckling_factor_of(satqual::pipeline::modal(&parse(text), Some(200.0), None));
    let (stiff, rigid) = (
        factor(&with("axial_stiffness_n_m", "1e12")),
        factor(&with("axial_stiffness_n_m", "1e15")),
    );
    eprintln!("stack buckling factor: {stiff} at 1e12 N/m, {rigid} at 1e15 N/m");
    assert!(rel(rigid, stiff) < 1e-4, "{rigid} vs {stiff}");
    // Up to 2 kHz the 1e15 model holds a 25-fold cluster of column-joint modes at 660.95 Hz
    // whose Lanczos values were 1e-7 off and whose vectors had a backward error of 1.9e-2; the
    // polish fixes both (its λ moves beyond the second-order 1e-8 are proven by Sturm counts
    // around the cluster). Reference: the dense solve of the same model; tolerance 1e-9
    // relative on those modes (measured 5e-11; 5.7e-8 without the polish), and no warning.
    let text = with("axial_stiffness_n_m", "1e15");
    let solve = |solver| {
        satqual::pipeline::modal_with_solver(&parse(&text), Some(2000.0), None, Some(solver))
            .unwrap()
            .1
            .result
    };
    let (sparse, dense) = (solve(SolverChoice::Sparse), solve(SolverChoice::Dense));
    assert!(sparse.warnings.is_empty(), "{:?}", sparse.warnings);
    let cluster: Vec<_> = (sparse.modes.iter().zip(&dense.modes))
        .filter(|(s, _)| (s.frequency_hz - 660.946).abs() < 0.01)
        .collect();
    assert_eq!(cluster.len(), 25);
    for (s, d) in cluster {
        assert!(rel(s.frequency_hz, d.frequency_hz) < 1e-9, "{s:?} vs {d:?}");
    }
    // The 20-satellite stack with the same joints: a 95-fold cluster there, in which polishing
    // within the 1e-6 cluster spread alone left a backward error of 0.26 (a pair whose λ lies
    // outside that spread; on 60 satellites one was 4e-6 off): polished with the pairs of a
    // wider window, every pair passes the check.
    let twenty = satqual::catalogue::generated::stack_with_satellites(
        &with("axial_stiffness_n_m", "1e15"),
        20,
    );
    let res = satqual::pipeline::modal(&parse(&twenty), Some(2000.0), None)
        .unwrap()
        .1
        .result;
    assert!(res.warnings.is_empty(), "{:?}", res.warnings);
    let cluster = res
        .modes
        .iter()
        .filter(|m| (m.frequency_hz - 660.95).abs() < 0.01);
    assert_eq!(cluster.count(), 95);
    let text = with("rotational_stiffness_n_m_rad", "1e18");
    let err = satqual::pipeline::modal(&parse(&text), Some(200.0), None)
        .expect_err("pivots at round-off are refused")
        .to_string();
    assert!(err.contains("a spring many decades stiffer"), "{err}");
}

/// The buckling factor of a modal run that must succeed and find one.
fn buckling_factor_of<T>(run: Result<(T, satqual::modal::ModalSystem), satqual::Error>) -> f64 {
    run.unwrap()
        .1
        .result
        .prestress
        .unwrap()
        .buckling_factor
        .unwrap()
}
