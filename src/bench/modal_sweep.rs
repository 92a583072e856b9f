//! The band-edge sweep of `satqual bench modal`: the sparse solver at every `fmax` from 500 to
//! 2000 Hz in steps of 5 Hz on the paper stack with three meshes, each solve checked for
//! completion and for its mode count against the Sturm count and against an independent
//! count (the dense solver's eigenvalues below the same shift).

use crate::Error;
use crate::catalogue::{self, generated::stack_with_mesh};
use crate::fem::FeModel;
use crate::modal::{ModalOptions, analyze};
use crate::spec::{Scene, SolverChoice};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// (bar elements per satellite pitch, column elements per half column): the default mesh and
/// the two finer ones whose 25-fold column-joint clusters sit near 2 kHz.
const MESHES: [(usize, usize); 3] = [(2, 1), (8, 2), (4, 4)];
const FMAX_FROM_HZ: usize = 500;
const FMAX_TO_HZ: usize = 2000;
const FMAX_STEP_HZ: usize = 5;

#[derive(Serialize)]
pub(super) struct SweepRow {
    bar_elements: usize,
    column_elements: usize,
    dofs: usize,
    runs: usize,
    /// Solves that returned without error.
    completed: usize,
    /// Completed solves whose mode count equals the Sturm count and the dense count.
    counts_proven: usize,
    total_time_s: f64,
    max_time_s: f64,
    /// The first few failures: fmax and what happened.
    failures: Vec<String>,
}

/// Runs the sweep on every mesh.
pub(super) fn run() -> Result<Vec<SweepRow>, Error> {
    let path = Path::new(catalogue::PAPER_STACK);
    let base = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut rows = Vec::new();
    for (bar, column) in MESHES {
        let text = stack_with_mesh(&base, column, bar);
        let scene = Scene::parse(Path::new("sweep.toml"), &text)?;
        let model = crate::pipeline::fe_model(&scene)?;
        rows.push(sweep_mesh(&model, bar, column)?);
    }
    Ok(rows)
}

fn options(fmax_hz: Option<f64>, solver: SolverChoice) -> ModalOptions {
    ModalOptions {
        fmax_hz,
        modes: None,
        solver,
        stop_beyond_buckling: false,
        ..Default::default()
    }
}

fn sweep_mesh(model: &FeModel, bar: usize, column: usize) -> Result<SweepRow, Error> {
    let dense = analyze(model, &options(None, SolverChoice::Dense))?.result;
    let lambdas: Vec<f64> = dense.modes.iter().map(|m| m.eigenvalue).collect();
    let mut row = SweepRow {
        bar_elements: bar,
        column_elements: column,
        dofs: dense.dofs,
        runs: 0,
        completed: 0,
        counts_proven: 0,
        total_time_s: 0.0,
        max_time_s: 0.0,
        failures: Vec::new(),
    };
    for f in (FMAX_FROM_HZ..=FMAX_TO_HZ).step_by(FMAX_STEP_HZ) {
        let fmax = f as f64;
        row.runs += 1;
        let t0 = Instant::now();
        let out = analyze(model, &options(Some(fmax), SolverChoice::Sparse));
        let t = t0.elapsed().as_secs_f64();
        row.total_time_s += t;
        row.max_time_s = row.max_time_s.max(t);
        let problem = match out {
            Err(e) => Some(format!("{fmax} Hz: {e}")),
            Ok(sys) => {
                row.completed += 1;
                let st = sys.result.sparse.unwrap_or_default();
                let below = lambdas.iter().filter(|&&l| l < st.sturm_sigma).count();
                let found = sys.result.modes.len();
                if st.fmax_count == Some(found) && found == below {
                    row.counts_proven += 1;
                    None
                } else {
                    Some(format!(
                        "{fmax} Hz: {found} modes, Sturm count {:?}, dense count {below}",
                        st.fmax_count
                    ))
                }
            }
        };
        if let Some(p) = problem
            && row.failures.len() < 5
        {
            row.failures.push(p);
        }
    }
    eprintln!(
        "sweep mesh ({bar}, {column}): {}/{} completed, {} proven, {:.1} s",
        row.completed, row.runs, row.counts_proven, row.total_time_s
    );
    Ok(row)
}

/// The sweep's section of `modal.md`.
pub(super) fn markdown(rows: &[SweepRow]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## Band edges: a sweep of fmax\n\nThe sparse solver at every fmax from {FMAX_FROM_HZ} \
         to {FMAX_TO_HZ} Hz in steps of {FMAX_STEP_HZ} Hz, on the 6-satellite stack with three \
         meshes (bar elements per pitch, column elements per half column); the finer two repeat \
         a column-joint mode 25 times near 2 kHz. \"Proven\": the mode count equals the Sturm \
         count at the band's top and the dense solver's count of eigenvalues below the same \
         shift.\n"
    );
    let _ = writeln!(
        s,
        "| mesh | DOFs | runs | completed | proven | total [s] | slowest [s] | failures |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---|");
    for r in rows {
        let _ = writeln!(
            s,
            "| ({}, {}) | {} | {} | {} | {} | {:.1} | {:.3} | {} |",
            r.bar_elements,
            r.column_elements,
            r.dofs,
            r.runs,
            r.completed,
            r.counts_proven,
            r.total_time_s,
            r.max_time_s,
            if r.failures.is_empty() {
                "none".to_string()
            } else {
                r.failures.join("; ")
            }
        );
    }
    s
}
