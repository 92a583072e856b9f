//! The sparse modal path (shift-invert block Lanczos with a Sturm-count proof, sparse static
//! solve and buckling) against the dense path, which is itself verified against analytic and
//! NAFEMS references in `fem_verification.rs`. The dense path is the reference here; each
//! tolerance is named where it is used:
//! - frequencies: 1e-8 relative (the requirement on the sparse path: "the dense and sparse
//!   paths agree to 1e-8");
//! - effective masses: 1e-8 of the direction's total rigid-body mass (same bound);
//! - static displacement: 1e-9 of its norm; buckling factor: 1e-8 relative.

use satqual::catalogue::{self, generated::FrameTower};
use satqual::error::{Error, FemError, ModalError};
use satqual::fem::FeModel;
use satqual::modal::{ModalOptions, ModalResult, Shapes, analyze, sparse::sturm_check};
use satqual::spec::{Scene, SolverChoice};

const FREQ_TOL: f64 = 1e-8;
const MASS_TOL: f64 = 1e-8;
/// Modes closer than this (relative) are compared as a group. The dense reference's
/// eigenvectors of two modes that close are mixed by round-off: on the 12-satellite stack
/// faer gives the x effective mass of the pair at 1574.449951 / 1574.450011 Hz (3.8e-8 apart)
/// to the lower one, where LAPACK (scipy.linalg.eigh on the exported K + K_G and M) and the
/// mirror-symmetry classes, which cannot mix them, give it to the upper one.
const GROUP_GAP: f64 = 1e-6;

use crate::common::load;

use crate::common::parse;

fn solve(
    scene: &Scene,
    solver: SolverChoice,
    fmax: Option<f64>,
    modes: Option<usize>,
) -> ModalResult {
    let model = FeModel::from_scene(&scene.model).unwrap();
    analyze(
        &model,
        &ModalOptions {
            fmax_hz: fmax,
            modes,
            solver,
            stop_beyond_buckling: false,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{solver:?}: {e}"))
    .result
}

/// A band edge in a clear gap of the dense spectrum, above at least `min_modes` modes, so that
/// no cluster of repeated frequencies is cut in two.
fn fmax_in_gap(dense_all: &ModalResult, min_modes: usize) -> f64 {
    let f: Vec<f64> = dense_all.modes.iter().map(|m| m.frequency_hz).collect();
    for i in min_modes.max(1)..f.len() {
        if f[i] - f[i - 1] > 1e-3 * f[i] {
            return 0.5 * (f[i] + f[i - 1]);
        }
    }
    panic!("no gap in the spectrum above mode {min_modes}");
}

/// Frequencies to 1e-8 relative; rigid-body modes (|f| below 1e-4 of the first elastic one)
/// are compared as "both rigid"; effective masses to 1e-8 of the direction's total, summed
/// over each group of modes whose dense frequencies lie within [`GROUP_GAP`] of each other: a
/// group's summed effective mass is that of its eigenspace, whatever basis each path chose.
fn assert_agree(dense: &ModalResult, sparse: &ModalResult, what: &str) -> f64 {
    assert_eq!(dense.modes.len(), sparse.modes.len(), "{what}: mode count");
    let f_ref = dense
        .modes
        .iter()
        .map(|m| m.frequency_hz.abs())
        .fold(0.0, f64::max);
    let rigid = 1e-4
        * dense
            .modes
            .iter()
            .map(|m| m.frequency_hz)
            .find(|f| f.abs() > 1e-3 * f_ref)
            .unwrap_or(f_ref);
    let mut worst = 0.0f64;
    for (d, s) in dense.modes.iter().zip(&sparse.modes) {
        let (fd, fs) = (d.frequency_hz, s.frequency_hz);
        if fd.abs() < rigid {
            assert!(
                fs.abs() < rigid,
                "{what}: mode {} rigid {fd} vs {fs}",
                d.index
            );
            continue;
        }
        let rel = (fd - fs).abs() / fd.abs();
        worst = worst.max(rel);
        assert!(
            rel <= FREQ_TOL,
            "{what}: mode {} {fd} Hz (dense) vs {fs} Hz (sparse), rel {rel:e}",
            d.index
        );
    }
    assert_group_masses_agree(dense, sparse, what);
    worst
}

/// The effective masses of [`assert_agree`], group by group.
fn assert_group_masses_agree(dense: &ModalResult, sparse: &ModalResult, what: &str) {
    let tot = dense.total_rigid_body_mass.to_array();
    let f: Vec<f64> = dense.modes.iter().map(|m| m.frequency_hz).collect();
    let mut start = 0;
    while start < f.len() {
        let mut end = start + 1;
        while end < f.len() && (f[end] - f[end - 1]).abs() <= GROUP_GAP * f[end].abs() {
            end += 1;
        }
        let sum = |r: &ModalResult| {
            r.modes[start..end].iter().fold([0.0; 6], |mut acc, m| {
                let e = m.effective_mass.to_array();
                (0..6).for_each(|a| acc[a] += e[a]);
                acc
            })
        };
        let (ed, es) = (sum(dense), sum(sparse));
        for a in 0..6 {
            let err = (ed[a] - es[a]).abs() / tot[a].max(f64::MIN_POSITIVE);
            assert!(
                err <= MASS_TOL,
                "{what}: modes {}..={} ({} Hz) effective mass dir {a}: {} vs {}, err {err:e}",
                start + 1,
                end,
                f[start],
                ed[a],
                es[a]
            );
        }
        start = end;
    }
}

/// A frame tower from the catalogue (see `FrameTower` for its members, masses and springs).
fn frame(nx: usize, ny: usize, levels: usize, elements: usize, free: bool, load_n: f64) -> String {
    FrameTower {
        nx,
        ny,
        levels,
        elements,
        free,
        load_n,
        beams_and_point_masses: false,
    }
    .scene()
}

#[test]
fn verification_scenes_dense_and_sparse_agree() {
    // The scenes of fem_verification.rs (cantilever, NAFEMS FV4 with a rigid arm and offset
    // masses, NAFEMS FV5), with the band edge in a gap above the scene's own mode count.
    for path in [
        "test-specs/verification/cantilever.toml",
        "test-specs/verification/nafems-fv4.toml",
        "test-specs/verification/nafems-fv5.toml",
    ] {
        let scene = load(path);
        let n = scene.file.modal.as_ref().and_then(|m| m.modes).unwrap_or(6);
        let all = solve(&scene, SolverChoice::Dense, None, None);
        let fmax = fmax_in_gap(&all, n);
        let d = solve(&scene, SolverChoice::Dense, Some(fmax), None);
        let s = solve(&scene, SolverChoice::Sparse, Some(fmax), None);
        assert!(s.solver.starts_with("sparse"), "{}", s.solver);
        assert!(d.solver.starts_with("dense"), "{}", d.solver);
        // Small models stay dense under Auto.
        let auto = solve(&scene, SolverChoice::Auto, Some(fmax), None);
        assert!(auto.solver.starts_with("dense"), "{}", auto.solver);
        let stats = s.sparse.as_ref().expect("sparse stats");
        assert_eq!(
            stats.fmax_count,
            Some(d.modes.len()),
            "{path}: Sturm count vs dense"
        );
        assert_agree(&d, &s, path);
    }
}

#[test]
fn large_frame_dense_and_sparse_agree_with_sturm_count() {
    // About 1900 reduced DOFs, masses with offsets and inertia, springs; a band with well over
    // one slice of modes so that the spectrum slicing and its Sturm edges are exercised.
    let scene = parse(&frame(4, 3, 8, 2, false, 0.0));
    let all = solve(&scene, SolverChoice::Dense, None, None);
    assert!(all.dofs > 1500, "{} DOFs", all.dofs);
    let fmax = fmax_in_gap(&all, 130);
    let d = solve(&scene, SolverChoice::Dense, Some(fmax), None);
    let s = solve(&scene, SolverChoice::Sparse, Some(fmax), None);
    let stats = s.sparse.as_ref().unwrap();
    assert!(stats.slices >= 2, "{stats:?}");
    // The Sturm count is the number of dense eigenvalues below fmax.
    assert_eq!(stats.fmax_count, Some(d.modes.len()));
    assert_eq!(s.modes.len(), d.modes.len());
    // Normwise backward error of every returned pair (sparse module doc: ~tolerance 1e-11).
    assert!(stats.max_backward_error < 1e-10, "{stats:?}");
    let worst = assert_agree(&d, &s, "frame");
    // A band of ~130 modes of ~1900 DOFs: the cost model of Auto picks sparse.
    let auto = solve(&scene, SolverChoice::Auto, Some(fmax), None);
    assert!(auto.solver.starts_with("sparse"), "{}", auto.solver);
    eprintln!(
        "frame: {} DOFs, {} modes below {fmax:.1} Hz, worst rel {worst:e}, {stats:?}",
        s.dofs,
        s.modes.len()
    );

    // The lowest N without a band edge: proven by the count at the last slice edge.
    let n = 40;
    let s = solve(&scene, SolverChoice::Sparse, None, Some(n));
    let d_n = ModalResult {
        modes: all.modes[..n].to_vec(),
        ..all.clone()
    };
    // A cluster cut at mode 40 would make the last modes' effective masses basis-dependent.
    assert!(
        all.modes[n].frequency_hz - all.modes[n - 1].frequency_hz
            > 1e-6 * all.modes[n].frequency_hz
    );
    assert_agree(&d_n, &s, "frame, lowest 40");
    let stats = s.sparse.as_ref().unwrap();
    assert!(stats.sturm_count >= n, "{stats:?}");
}

#[test]
fn free_free_frame_finds_rigid_body_modes() {
    // No supports: six rigid-body modes at 0 Hz, which the negative first shift factors.
    let scene = parse(&frame(3, 2, 4, 2, true, 0.0));
    let all = solve(&scene, SolverChoice::Dense, None, None);
    let fmax = fmax_in_gap(&all, 30);
    let d = solve(&scene, SolverChoice::Dense, Some(fmax), None);
    let s = solve(&scene, SolverChoice::Sparse, Some(fmax), None);
    let first_elastic = d.modes[6].frequency_hz;
    for m in &s.modes[..6] {
        assert!(
            m.frequency_hz.abs() < 1e-4 * first_elastic,
            "mode {}: {} Hz",
            m.index,
            m.frequency_hz
        );
    }
    assert!(s.modes[6].frequency_hz > 1e-2 * first_elastic);
    assert_eq!(s.sparse.as_ref().unwrap().fmax_count, Some(d.modes.len()));
    assert_agree(&d, &s, "free-free frame");
}

#[test]
fn prestress_static_solve_and_buckling_agree() {
    // Compressive top loads: the static solve (sparse LDLᵀ of K) and the buckling factor
    // (Lanczos on K⁻¹·(−K_G)) against the dense Cholesky solve and dense eigen-solve.
    let scene = parse(&frame(3, 2, 6, 2, false, 2.0e4));
    let model = FeModel::from_scene(&scene.model).unwrap();
    let run = |solver| {
        analyze(
            &model,
            &ModalOptions {
                fmax_hz: Some(50.0),
                modes: None,
                solver,
                stop_beyond_buckling: false,
                ..Default::default()
            },
        )
        .unwrap()
        .result
    };
    let d = run(SolverChoice::Dense);
    let s = run(SolverChoice::Sparse);
    let (pd, ps) = (d.prestress.as_ref().unwrap(), s.prestress.as_ref().unwrap());
    let norm = pd.displacement.iter().map(|x| x * x).sum::<f64>().sqrt();
    let diff = pd
        .displacement
        .iter()
        .zip(&ps.displacement)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        diff <= 1e-9 * norm,
        "static displacement: |Δu| = {diff:e}, |u| = {norm:e}"
    );
    let (ld, ls) = (pd.buckling_factor.unwrap(), ps.buckling_factor.unwrap());
    assert!(
        (ld - ls).abs() <= 1e-8 * ld,
        "buckling factor {ld} (dense) vs {ls} (sparse)"
    );
    assert!(ld > 1.0, "the test load should stay below buckling: {ld}");
    assert_agree(&d, &s, "prestressed frame");
}

#[test]
fn sturm_mismatch_fails_loudly() {
    assert_eq!(sturm_check(12, 12, 2000.0), Ok(()));
    assert_eq!(
        sturm_check(12, 11, 2000.0),
        Err(ModalError::SturmMismatch {
            expected: 12,
            found: 11,
            fmax_hz: 2000.0
        })
    );
    let msg = sturm_check(3, 4, 150.0).unwrap_err().to_string();
    assert!(
        msg.contains("3 modes lie below 150 Hz") && msg.contains("returned 4"),
        "{msg}"
    );
}

#[test]
fn sparse_without_a_band_is_refused() {
    let scene = load("test-specs/verification/nafems-fv4.toml");
    let model = FeModel::from_scene(&scene.model).unwrap();
    let e = analyze(
        &model,
        &ModalOptions {
            fmax_hz: None,
            modes: None,
            solver: SolverChoice::Sparse,
            stop_beyond_buckling: false,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("the sparse solver needs [modal] fmax_hz or modes"),
        "{e}"
    );
}

#[test]
fn sparse_static_solve_names_the_mechanism() {
    // A free frame under a static load cannot be solved: the sparse LDLᵀ of K meets a
    // pivot at round-off level and names a node and DOF, as the dense path does.
    let scene = parse(&frame(2, 2, 2, 1, true, 100.0));
    let model = FeModel::from_scene(&scene.model).unwrap();
    let e = analyze(
        &model,
        &ModalOptions {
            fmax_hz: Some(100.0),
            modes: None,
            solver: SolverChoice::Sparse,
            stop_beyond_buckling: false,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::Fem(FemError::Unconstrained { .. })),
        "{e}"
    );
}

#[test]
fn paper_stack_dense_and_sparse_agree() {
    // The sparse path's requirement: "the dense and sparse paths agree to 1e-8 relative on the
    // 6-satellite scene".
    // All modes below the scene's 2 kHz, the prestress (bar tensions) and the buckling factor.
    let scene = load("test-specs/paper-stack.toml");
    let fmax = scene.file.modal.as_ref().and_then(|m| m.fmax_hz);
    let model = FeModel::from_scene(&scene.model).unwrap();
    let run = |solver| {
        analyze(
            &model,
            &ModalOptions {
                fmax_hz: fmax,
                modes: None,
                solver,
                stop_beyond_buckling: false,
                ..Default::default()
            },
        )
        .unwrap()
        .result
    };
    let d = run(SolverChoice::Dense);
    let s = run(SolverChoice::Sparse);
    assert_eq!(s.sparse.as_ref().unwrap().fmax_count, Some(d.modes.len()));
    assert_agree(&d, &s, "paper stack");
    let (pd, ps) = (d.prestress.as_ref().unwrap(), s.prestress.as_ref().unwrap());
    let (ld, ls) = (pd.buckling_factor.unwrap(), ps.buckling_factor.unwrap());
    assert!((ld - ls).abs() <= 1e-8 * ld, "buckling factor {ld} vs {ls}");
    for (a, b) in pd.members.iter().zip(&ps.members) {
        let scale = pd
            .members
            .iter()
            .map(|m| m.axial_force_n.abs())
            .fold(0.0, f64::max);
        assert!(
            (a.axial_force_n - b.axial_force_n).abs() <= 1e-9 * scale,
            "{}: {} vs {}",
            a.name,
            a.axial_force_n,
            b.axial_force_n
        );
    }
}

#[test]
fn sparse_cli_output_is_independent_of_thread_count() {
    // Byte-identical `--json` whatever RAYON_NUM_THREADS: every faer call in the sparse path
    // is sequential and the Lanczos start blocks come from a seeded generator.
    let exe = env!("CARGO_BIN_EXE_satqual");
    let run = |threads: &str| {
        let out = std::process::Command::new(exe)
            .args([
                "modal",
                "test-specs/paper-stack.toml",
                "--solver",
                "sparse",
                "--json",
            ])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    let one = run("1");
    assert!(String::from_utf8_lossy(&one).contains("\"sturm_count\""));
    assert_eq!(one, run("2"), "1 vs 2 threads");
}

/// The paper stack with `n` satellites, its guide bars one 0.55 m pitch longer per added
/// satellite (as `satqual bench modal` builds them).
fn stack_with(n: usize) -> Scene {
    let base = std::fs::read_to_string(catalogue::PAPER_STACK).unwrap();
    parse(&catalogue::generated::stack_with_satellites(&base, n))
}

#[test]
fn twenty_satellite_stack_bands_and_cluster_match_eigsh() {
    // The Sturm-count proof and the sparse solver's accuracy on a stack large enough
    // for the paths the 6-satellite scene never takes: the band is cut into parallel bands
    // (932 modes below 2 kHz, bands of about 150), and the column joints' local mode,
    // repeated 84 times at 653 Hz, is taken whole by the cluster subspace iteration.
    // Reference: scipy.sparse.linalg.eigsh (ARPACK, shift-invert, tol 1e-14) on the matrices
    // this model exports, stored with the command that made them in
    // data/modal-refs/stack20_eigsh.py; tolerance 1e-8 relative, as for dense vs sparse on the
    // 6-satellite scene. (faer's dense solver is no reference here: on 2120 DOFs whose top
    // eigenvalue is ~1e14 rad²/s² its lowest modes carry ~1e-8 relative error.)
    let reference: Vec<f64> = std::fs::read_to_string("data/modal-refs/stack20-eigsh.csv")
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    let scene = stack_with(20);
    let s = solve(&scene, SolverChoice::Sparse, Some(2000.0), None);
    let st = s.sparse.as_ref().unwrap();
    assert!(st.bands >= 2, "bands: {}", st.bands);
    assert!(st.clusters >= 1, "clusters: {}", st.clusters);
    assert_eq!(st.fmax_count, Some(reference.len()), "Sturm count vs eigsh");
    // Its repeated bar-mode clusters are polished (inverse iteration + Rayleigh–Ritz) until
    // every pair passes the 1e-8 backward-error check (modal::checks::MAX_BACKWARD_ERROR).
    assert!(
        !s.warnings.iter().any(|w| w.contains("working precision")),
        "{:?}",
        s.warnings
    );
    assert_eq!(s.modes.len(), reference.len());
    let mut worst = 0.0f64;
    for (m, r) in s.modes.iter().zip(&reference) {
        let rel = (m.frequency_hz - r).abs() / r;
        worst = worst.max(rel);
        assert!(
            rel <= FREQ_TOL,
            "mode {}: {} Hz vs eigsh {r} Hz, rel {rel:e}",
            m.index,
            m.frequency_hz
        );
    }
    println!(
        "20 satellites: {} modes, {} bands, {} clusters, worst rel. difference to eigsh {worst:e}",
        s.modes.len(),
        st.bands,
        st.clusters
    );
    // Bands run on however many threads rayon has; the cuts do not depend on it.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| solve(&scene, SolverChoice::Sparse, Some(2000.0), None));
    let bits = |r: &ModalResult| -> Vec<u64> {
        r.modes
            .iter()
            .flat_map(|m| std::iter::once(m.frequency_hz).chain(m.shape.iter().copied()))
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(&one), bits(&s), "1 thread vs the default pool");
}

#[test]
fn auto_solves_only_what_the_scene_asks() {
    // The cost model of SolverChoice::Auto (modal::auto_prefers_sparse): a few modes of a model
    // of several hundred DOFs or more go to the sparse solver instead of solving every mode
    // and truncating; the answer is the dense one's lowest modes (tolerances of assert_agree).
    let stack = load(catalogue::PAPER_STACK);
    let five = solve(&stack, SolverChoice::Auto, None, Some(5));
    assert!(five.solver.starts_with("sparse"), "{}", five.solver);
    let all = solve(&stack, SolverChoice::Dense, None, None);
    let first5 = ModalResult {
        modes: all.modes[..5].to_vec(),
        ..all.clone()
    };
    assert_agree(&first5, &five, "paper stack, --modes 5");
    // A frame tower of 1476 DOFs asking for 12 modes.
    let tower = parse(&FrameTower::clamped(4, 3, 6).scene());
    let twelve = solve(&tower, SolverChoice::Auto, None, Some(12));
    assert!(twelve.dofs > 1400, "{} DOFs", twelve.dofs);
    assert!(twelve.solver.starts_with("sparse"), "{}", twelve.solver);
    // 300 of the stack's 692 modes at 2 kHz: the dense path's work on the 300 modes it keeps
    // makes it the dearer (model 0.16 s against 0.073 s), so it goes sparse; a verification
    // scene (120 DOFs) is dense whatever it asks.
    let band = solve(&stack, SolverChoice::Auto, Some(2000.0), None);
    assert!(band.solver.starts_with("sparse"), "{}", band.solver);
    let cantilever = load("test-specs/verification/cantilever.toml");
    let small = solve(&cantilever, SolverChoice::Auto, None, Some(3));
    assert!(small.solver.starts_with("dense"), "{}", small.solver);
}

/// `satqual modal` drops the shapes band by band as the sparse solver finishes them
/// (`Shapes::Drop`); every other number of the result is the one with the shapes kept, bit
/// for bit (the same arithmetic per mode), and the modes are numbered in order across the
/// bands. The 20-satellite stack at 2 kHz runs in several bands.
#[test]
fn dropping_the_shapes_changes_no_other_number() {
    let model = FeModel::from_scene(&stack_with(20).model).unwrap();
    let solve = |shapes| {
        let opts = ModalOptions {
            fmax_hz: Some(2000.0),
            modes: None,
            solver: SolverChoice::Sparse,
            stop_beyond_buckling: false,
            shapes,
        };
        analyze(&model, &opts).unwrap().result
    };
    let (keep, drop) = (solve(Shapes::Keep), solve(Shapes::Drop));
    assert!(keep.sparse.as_ref().unwrap().bands > 1);
    assert_eq!(
        serde_json::to_string(&keep).unwrap(),
        serde_json::to_string(&drop).unwrap()
    );
    assert!(drop.modes.iter().all(|m| m.shape.is_empty()));
    assert!(keep.modes.iter().all(|m| m.shape.len() == keep.dofs));
    assert!(keep.modes.iter().enumerate().all(|(i, m)| m.index == i + 1));
}

/// The paper stack with 12 satellites (1280 DOFs: classes of 320, above the smallest one the
/// solver splits off) and their centres of gravity offset by `offset` (m): an offset along x
/// breaks the mirror x ↦ −x, one along y the mirror y ↦ −y.
fn stack12_with_cg_offset(offset: [f64; 2]) -> Scene {
    let base = std::fs::read_to_string(catalogue::PAPER_STACK).unwrap();
    let line = "satellite_cg_offset_m = [0.0, 0.0, 0.0]";
    assert!(base.contains(line), "the paper stack's CG offset line");
    let text = base.replace(
        line,
        &format!(
            "satellite_cg_offset_m = [{}, {}, 0.0]",
            offset[0], offset[1]
        ),
    );
    parse(&catalogue::generated::stack_with_satellites(&text, 12))
}

/// A mirror-symmetric stack is solved one symmetry class at a time (`modal::mirrors`,
/// `modal::sparse::symmetry`); a stack whose mass breaks a mirror loses that mirror, and one
/// that breaks both is solved whole. Every variant agrees with the dense path (frequencies
/// and effective masses to 1e-8, the sparse path's requirement) with the classes' Sturm
/// counts summing to the dense mode count below fmax.
#[test]
fn mirror_symmetry_classes_agree_with_the_dense_path() {
    let cases: [([f64; 2], Option<&str>); 4] = [
        (
            [0.0, 0.0],
            Some("mirror planes x = 0.000000 m, y = 0.000000 m: 4 classes"),
        ),
        ([0.01, 0.0], Some("mirror planes y = 0.000000 m: 2 classes")),
        ([0.0, 0.01], Some("mirror planes x = 0.000000 m: 2 classes")),
        ([0.01, 0.02], None),
    ];
    for (offset, expected) in cases {
        let scene = stack12_with_cg_offset(offset);
        let d = solve(&scene, SolverChoice::Dense, Some(2000.0), None);
        let s = solve(&scene, SolverChoice::Sparse, Some(2000.0), None);
        let st = s.sparse.as_ref().unwrap();
        match expected {
            Some(text) => {
                let got = st.symmetry.as_deref().unwrap_or("none");
                assert!(got.starts_with(text), "offset {offset:?}: {got}");
                assert!(s.solver.contains("by mirror-symmetry class"));
            }
            None => assert_eq!(st.symmetry, None, "offset {offset:?}"),
        }
        assert_eq!(st.fmax_count, Some(d.modes.len()), "offset {offset:?}");
        assert_agree(&d, &s, &format!("CG offset {offset:?}"));
        assert!(s.modes.iter().enumerate().all(|(i, m)| m.index == i + 1));
    }
}

/// A request for the lowest N modes (no band) is solved whole even when the model has
/// mirrors: the N lowest could all lie in one class.
#[test]
fn the_lowest_modes_are_solved_whole() {
    let scene = stack12_with_cg_offset([0.0, 0.0]);
    let s = solve(&scene, SolverChoice::Sparse, None, Some(40));
    assert_eq!(s.sparse.as_ref().unwrap().symmetry, None);
    let d = solve(&scene, SolverChoice::Dense, None, Some(40));
    assert_agree(&d, &s, "lowest 40 modes");
}

/// A free-free steel grid of square-section beams, 5 × 5 nodes per floor at 0.5 m on 4 floors,
/// centred on x = y = 0: mirror-symmetric about x = 0, y = 0 and z = 0.75 m, with no support.
fn free_grid_scene() -> String {
    let mut s = String::from(
        "title = \"free-free symmetric grid\"\n\
         [[material]]\nname = \"steel\"\nyoungs_modulus_pa = 210e9\npoisson_ratio = 0.3\ndensity_kg_m3 = 7850\n\
         [[section]]\nname = \"bar\"\nshape = \"rectangle\"\nwidth_m = 0.02\nheight_m = 0.02\n",
    );
    let id = |i: usize, j: usize, k: usize| 1 + i + 5 * j + 25 * k;
    for k in 0..4 {
        for j in 0..5 {
            for i in 0..5 {
                let p = [
                    0.5 * (i as f64 - 2.0),
                    0.5 * (j as f64 - 2.0),
                    0.5 * k as f64,
                ];
                s += &format!("[[node]]\nid = {}\nposition_m = {p:?}\n", id(i, j, k));
            }
        }
    }
    let mut beam = |a: usize, b: usize, orientation: &str| {
        s += &format!(
            "[[beam]]\nnodes = [{a}, {b}]\nsection = \"bar\"\nmaterial = \"steel\"\nelements = 2\norientation = {orientation}\n"
        );
    };
    for k in 0..4 {
        for j in 0..5 {
            for i in 0..5 {
                if i < 4 {
                    beam(id(i, j, k), id(i + 1, j, k), "[0.0, 0.0, 1.0]");
                }
                if j < 4 {
                    beam(id(i, j, k), id(i, j + 1, k), "[0.0, 0.0, 1.0]");
                }
                if k < 3 {
                    beam(id(i, j, k), id(i, j, k + 1), "[1.0, 0.0, 0.0]");
                }
            }
        }
    }
    s
}

/// The class path on a model with rigid-body modes: each class holds those of its symmetry
/// (the negative first shift factors every class), and the result agrees with the dense path
/// (frequencies and effective masses to 1e-8, six modes at 0 Hz in both). Its third plane
/// (z) would make classes below the 300-DOF floor, so two are used.
#[test]
fn a_free_free_symmetric_grid_finds_its_rigid_body_modes_class_by_class() {
    let scene = parse(&free_grid_scene());
    let all = solve(&scene, SolverChoice::Dense, None, None);
    let fmax = fmax_in_gap(&all, 120);
    let d = solve(&scene, SolverChoice::Dense, Some(fmax), None);
    let s = solve(&scene, SolverChoice::Sparse, Some(fmax), None);
    let symmetry = s
        .sparse
        .as_ref()
        .unwrap()
        .symmetry
        .clone()
        .unwrap_or_default();
    let planes = "mirror planes x = 0.000000 m, y = 0.000000 m: 4 classes";
    assert!(symmetry.starts_with(planes), "{symmetry}");
    let rigid = |r: &ModalResult| r.modes.iter().filter(|m| m.rigid_body).count();
    assert_eq!((rigid(&d), rigid(&s)), (6, 6));
    assert_eq!(s.sparse.as_ref().unwrap().fmax_count, Some(d.modes.len()));
    assert_agree(&d, &s, "free-free grid");
}
