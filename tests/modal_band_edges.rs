//! The sparse solver at band and slice edges: a sweep of `fmax` over the paper stack on three
//! meshes (the default, (bar 8, column 2) and (4, 4)), whose columns repeat one joint mode 25
//! times. Every solve must complete, and return exactly as many modes as the Sturm count at
//! its top, which must equal an independent count: the dense solver's eigenvalues below the
//! same shift (the top may move up by a few 1e-8 into a gap of the spectrum, so the count is
//! taken at the shift the solver reports). `satqual bench modal` runs the whole sweep, 500 to
//! 2000 Hz in steps of 5 Hz; this is a subset of it: the values that used to fail, the band
//! top exactly on the 25-fold cluster, and a few ordinary ones.

use satqual::catalogue::{self, generated::stack_with_mesh};
use satqual::fem::FeModel;
use satqual::modal::{ModalOptions, ModalResult, analyze};
use satqual::spec::SolverChoice;

use crate::common::parse;

fn model(bar_elements: usize, column_elements: usize) -> FeModel {
    let base = std::fs::read_to_string(catalogue::PAPER_STACK).unwrap();
    let scene = parse(&stack_with_mesh(&base, column_elements, bar_elements));
    FeModel::from_scene(&scene.model).unwrap()
}

fn solve(model: &FeModel, solver: SolverChoice, fmax_hz: Option<f64>) -> ModalResult {
    analyze(
        model,
        &ModalOptions {
            fmax_hz,
            modes: None,
            solver,
            stop_beyond_buckling: false,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{solver:?} at fmax {fmax_hz:?}: {e}"))
    .result
}

/// The first frequency repeated at least 20 times (the column joints' local mode).
fn cluster_frequency(dense: &ModalResult) -> f64 {
    let f: Vec<f64> = dense.modes.iter().map(|m| m.frequency_hz).collect();
    f.iter()
        .copied()
        .find(|&x| f.iter().filter(|&&y| (y - x).abs() <= 1e-9 * x).count() >= 20)
        .expect("the stack repeats its column-joint mode")
}

/// Sparse solves at each `fmax`: completed, mode count = Sturm count = the dense count below
/// the reported top.
fn check_sweep(model: &FeModel, fmaxes: &[f64]) {
    let dense = solve(model, SolverChoice::Dense, None);
    let mut all = fmaxes.to_vec();
    // The band top exactly on the repeated mode, and on the 25-fold cluster nearest 2 kHz.
    all.push(cluster_frequency(&dense));
    for fmax in all {
        let sparse = solve(model, SolverChoice::Sparse, Some(fmax));
        let st = sparse.sparse.as_ref().unwrap();
        let count = st.fmax_count.unwrap();
        assert_eq!(
            sparse.modes.len(),
            count,
            "fmax {fmax}: modes vs Sturm count"
        );
        let top = st.sturm_sigma;
        // The top is at most a few EDGE_GAP (1e-8) above (2π·fmax)².
        let lmax = (2.0 * std::f64::consts::PI * fmax).powi(2);
        assert!(
            top >= lmax && top <= lmax * (1.0 + 1e-6),
            "fmax {fmax}: top {top} vs {lmax}"
        );
        let below = dense.modes.iter().filter(|m| m.eigenvalue < top).count();
        assert_eq!(count, below, "fmax {fmax}: Sturm count vs dense count");
    }
}

#[test]
fn fmax_sweep_default_mesh_completes_with_the_sturm_count() {
    check_sweep(&model(2, 1), &[500.0, 1000.0, 1500.0, 1980.0, 2000.0]);
}

#[test]
fn fmax_sweep_mesh_8_2_completes_with_the_sturm_count() {
    // 1995 and 2000 Hz: a 25-fold cluster at 1990.4 Hz just below the top of the band.
    check_sweep(&model(8, 2), &[645.0, 1000.0, 1990.0, 1995.0, 2000.0]);
}

#[test]
fn fmax_sweep_mesh_4_4_completes_with_the_sturm_count() {
    // 1980 Hz: a 25-fold cluster at 1952.9 Hz below the top of the band.
    check_sweep(&model(4, 4), &[500.0, 1955.0, 1980.0, 2000.0]);
}
