//! `satqual bench modal`: the sparse modal solver on stacks of 6, 20, 60, 120 and 200
//! satellites (every mode below 2 kHz), against `scipy.sparse.linalg.eigsh` in shift-invert
//! mode on the same exported matrices at the same tolerance, plus the dense/sparse crossover
//! that sets the cost model of `SolverChoice::Auto` (`modal::auto_prefers_sparse`), a few
//! modes against eigsh, LAPACK and CalculiX ([`super::modal_peers`]), and the band-edge sweep
//! of `fmax` ([`super::modal_sweep`]).
//! Writes `modal.json` and `modal.md`.
//!
//! The stacks come from `test-specs/paper-stack.toml` with `satellites = N` substituted (and
//! the guide bars lengthened by one pitch per added satellite, so that they still reach
//! through the stack).
//!
//! Peak memory is the process's VmHWM after resetting it (`/proc/self/clear_refs` ← 5) before
//! each solve (the in-process solve keeps the shapes, which the export for eigsh needs); that
//! of the `satqual modal` process, which drops them, is its VmHWM read every few milliseconds
//! in one more run. Timings are wall-clock (the short ones of the process and LAPACK a median of
//! five): a benchmark, never a test.

use crate::Error;
use crate::catalogue::{self, generated::FrameTower};
use crate::error::ModalError;
use crate::fem::FeModel;
use crate::modal::{ModalOptions, analyze};
use crate::spec::{Scene, SolverChoice};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

const FMAX_HZ: f64 = 2000.0;
const SATELLITES: [usize; 5] = [6, 20, 60, 120, 200];
/// The tolerance both solvers are given: eigsh's `tol` (‖OP·y − θ·y‖ ≤ tol·|θ|, ARPACK's
/// criterion) and the sparse module's `RESIDUAL_TOL` (the same bound scaled to a relative
/// eigenvalue error, see `modal::sparse`).
const TOL: f64 = crate::modal::sparse::RESIDUAL_TOL;
/// eigsh is stopped after this long: the ratio is then an upper bound.
const EIGSH_LIMIT_S: f64 = 300.0;
/// Largest stack also solved densely, for the crossover.
const DENSE_MAX_DOFS: usize = 2500;

#[derive(Serialize)]
struct StackRow {
    satellites: usize,
    dofs: usize,
    modes_below_fmax: usize,
    sturm_count: Option<usize>,
    time_s: f64,
    /// The dense solver on the same model (up to `DENSE_MAX_DOFS`).
    dense_time_s: Option<f64>,
    peak_memory_mb: Option<f64>,
    factorizations: usize,
    slices: usize,
    max_backward_error: f64,
    eigsh_time_s: Option<f64>,
    ratio_satqual_over_eigsh: Option<f64>,
    max_rel_freq_diff_vs_eigsh: Option<f64>,
    eigsh_note: Option<String>,
    /// `satqual modal --fmax` as a user runs it, whole process (start, scene, solve, output).
    cli_time_s: Option<f64>,
    /// That process's peak resident memory.
    cli_peak_mb: Option<f64>,
    /// LAPACK `eigh(K, M, subset_by_value)` (scipy, one OpenBLAS thread) on the same matrices,
    /// eigenvectors included, up to `DENSE_MAX_DOFS`.
    lapack_time_s: Option<f64>,
    ratio_cli_over_lapack: Option<f64>,
    /// How the row's model differs from the family's (the bar–bore contact closed).
    model_note: Option<String>,
}

impl StackRow {
    fn failed(satellites: usize, time_s: f64, error: String) -> StackRow {
        StackRow {
            satellites,
            dofs: 0,
            modes_below_fmax: 0,
            sturm_count: None,
            time_s,
            dense_time_s: None,
            peak_memory_mb: peak_mb(),
            factorizations: 0,
            slices: 0,
            max_backward_error: f64::NAN,
            eigsh_time_s: None,
            ratio_satqual_over_eigsh: None,
            max_rel_freq_diff_vs_eigsh: None,
            eigsh_note: Some(format!("satqual failed: {error}")),
            cli_time_s: None,
            cli_peak_mb: None,
            lapack_time_s: None,
            ratio_cli_over_lapack: None,
            model_note: None,
        }
    }
}

#[derive(Serialize)]
struct CrossRow {
    dofs: usize,
    modes: usize,
    dense_s: f64,
    sparse_s: f64,
    /// Each path's worst backward error ‖Kφ − λMφ‖ / (‖|K||φ|‖ + |λ|·‖|M||φ|‖).
    dense_backward_error: Option<f64>,
    sparse_backward_error: Option<f64>,
    /// Largest |f_sparse − f_dense| / f_dense over the modes.
    max_rel_freq_diff: f64,
}

#[derive(Serialize)]
struct Report {
    model: String,
    /// /proc/loadavg before and after: the machine is shared, wall times scale with it.
    load_average: [String; 2],
    fmax_hz: f64,
    tolerance: f64,
    stacks: Vec<StackRow>,
    crossover: Vec<CrossRow>,
    few_modes: Vec<super::modal_peers::PeerRow>,
    /// The cost model of `SolverChoice::Auto`: dense s per DOF³, sparse s per DOF·mode.
    auto_cost_model: [f64; 2],
    fmax_sweep: Vec<super::modal_sweep::SweepRow>,
}

/// The table as (JSON, Markdown); the matrices for eigsh go to `out/modal-work`.
pub fn run(out: &Path) -> Result<(String, String), Error> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let work = out.join("modal-work");
    std::fs::create_dir_all(&work).map_err(|e| Error::io(&work, e))?;
    let load0 = load_average();
    let python = python_with_scipy();
    let (model_note, scenes) = stack_scenes()?;
    let mut stacks = Vec::new();
    // eigsh only gets slower with the stack: once stopped at its time limit it is not run on
    // the larger ones.
    let mut eigsh_stopped = false;
    for (n, text) in scenes {
        let py = python.as_deref().filter(|_| !eigsh_stopped);
        let mut row = bench_stack(&work, n, &text, py)?;
        // A stack beyond its buckling load with open bores (the 120-satellite one, 66 m of
        // bars) is measured with the bars bearing on the bores, and says so.
        if let Some(err) = row
            .eigsh_note
            .clone()
            .filter(|e| e.starts_with("satqual failed") && e.contains("buckling load"))
        {
            let closed = catalogue::generated::with_closed_bores(&text);
            row = bench_stack(&work, n, &closed, py)?;
            let why = err.trim_start_matches("satqual failed: ");
            row.model_note = Some(format!("bar_bore = \"closed\": with open bores {why}"));
        }
        if eigsh_stopped && python.is_some() {
            row.eigsh_note = Some(format!(
                "eigsh not run: stopped at {EIGSH_LIMIT_S:.0} s on a smaller stack"
            ));
        }
        eigsh_stopped |= row
            .eigsh_note
            .as_deref()
            .is_some_and(|e| e.contains("did not finish"));
        stacks.push(row);
    }
    let crossover = crossover()?;
    let few_modes = super::modal_peers::run(&work)?;
    let fmax_sweep = super::modal_sweep::run()?;
    let report = Report {
        model: model_note,
        load_average: [load0, load_average()],
        fmax_hz: FMAX_HZ,
        tolerance: TOL,
        stacks,
        crossover,
        few_modes,
        auto_cost_model: [
            crate::modal::DENSE_S_PER_DOF3,
            crate::modal::SPARSE_S_PER_DOF_MODE,
        ],
        fmax_sweep,
    };
    Ok((super::to_json(&report)?, markdown(&report)))
}

/// One stack of the table: the sparse solve (timed), the dense one up to `DENSE_MAX_DOFS`, and
/// eigsh on the exported matrices when python3 with scipy is there.
fn bench_stack(
    work: &Path,
    n: usize,
    text: &str,
    python: Option<&Path>,
) -> Result<StackRow, Error> {
    let path = work.join(format!("stack-{n}.toml"));
    crate::report::write_atomic(&path, text.as_bytes())?;
    let model = match Scene::load(&path).and_then(|sc| crate::pipeline::fe_model(&sc)) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("stack {n}: {e}");
            return Ok(StackRow::failed(n, 0.0, e.to_string()));
        }
    };
    reset_peak();
    let t0 = Instant::now();
    let sys = match analyze(
        &model,
        &ModalOptions {
            fmax_hz: Some(FMAX_HZ),
            modes: None,
            solver: SolverChoice::Sparse,
            stop_beyond_buckling: true,
            ..Default::default()
        },
    ) {
        Ok(sys) => sys,
        // As `satqual modal` refuses it (pipeline::modal_with_solver): the modes of a stack
        // beyond its buckling load are not those of a stable structure.
        Err(Error::Modal(ModalError::BeyondBuckling { factor })) => {
            eprintln!("stack {n}: beyond its buckling load (factor {factor:.3})");
            return Ok(StackRow::failed(
                n,
                t0.elapsed().as_secs_f64(),
                format!(
                    "the preload is above the stack's buckling load (buckling factor {factor:.3})"
                ),
            ));
        }
        Err(e) => {
            // A failed size is a result of the benchmark, reported, not an abort.
            eprintln!("stack {n}: {e}");
            return Ok(StackRow::failed(
                n,
                t0.elapsed().as_secs_f64(),
                e.to_string(),
            ));
        }
    };
    let time_s = t0.elapsed().as_secs_f64();
    let peak = peak_mb();
    let r = &sys.result;
    let st = r.sparse.clone().unwrap_or_default();
    eprintln!(
        "stack {n}: {} DOFs, {} modes below {FMAX_HZ} Hz, {time_s:.3} s",
        r.dofs,
        r.modes.len()
    );
    let dense_time_s = if r.dofs <= DENSE_MAX_DOFS {
        let t0 = Instant::now();
        analyze(
            &model,
            &ModalOptions {
                fmax_hz: Some(FMAX_HZ),
                modes: None,
                solver: SolverChoice::Dense,
                stop_beyond_buckling: false,
                ..Default::default()
            },
        )?;
        Some(t0.elapsed().as_secs_f64())
    } else {
        None
    };
    let mut row = StackRow {
        satellites: n,
        dofs: r.dofs,
        modes_below_fmax: r.modes.len(),
        sturm_count: st.fmax_count,
        time_s,
        dense_time_s,
        peak_memory_mb: peak,
        factorizations: st.factorizations,
        slices: st.slices,
        max_backward_error: st.max_backward_error,
        eigsh_time_s: None,
        ratio_satqual_over_eigsh: None,
        max_rel_freq_diff_vs_eigsh: None,
        eigsh_note: None,
        cli_time_s: cli_time(&path),
        cli_peak_mb: cli_peak_mb(&path),
        lapack_time_s: None,
        ratio_cli_over_lapack: None,
        model_note: None,
    };
    match python {
        None => row.eigsh_note = Some("python3 with scipy not found: not run".into()),
        Some(py) => {
            let dir = work.join(format!("stack-{n}-matrices"));
            crate::pipeline::workflows::matrices::export(&dir, &model, &sys)?;
            let kfile = if r.prestress.is_some() {
                "KKG.mtx"
            } else {
                "K.mtx"
            };
            match eigsh(py, &dir, kfile, r.modes.len(), r.dofs) {
                Ok((t, f, lapack)) => {
                    row.lapack_time_s = lapack;
                    row.ratio_cli_over_lapack = row.cli_time_s.zip(lapack).map(|(c, l)| c / l);
                    let ours: Vec<f64> = r.modes.iter().map(|m| m.frequency_hz).collect();
                    let diff = ours
                        .iter()
                        .zip(&f)
                        .map(|(a, b)| (a - b).abs() / b.abs())
                        .fold(0.0, f64::max);
                    row.eigsh_time_s = Some(t);
                    row.ratio_satqual_over_eigsh = Some(time_s / t);
                    row.max_rel_freq_diff_vs_eigsh = Some(diff);
                    if f.len() != ours.len() {
                        row.eigsh_note = Some(format!("eigsh returned {} values", f.len()));
                    }
                }
                Err(e) => row.eigsh_note = Some(e),
            }
        }
    }
    Ok(row)
}

fn markdown(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Modal benchmark: sparse shift-invert Lanczos\n");
    let _ = writeln!(
        s,
        "Every mode below {} Hz; tolerance {:e} for both solvers (eigsh `tol`; satqual's relative \
         eigenvalue-error bound, see `modal::sparse`). Model: {}. \
         satqual time: `modal::analyze` end to end (assembly, prestress static solve, buckling, \
         eigen-solve, effective masses); eigsh time: the `eigsh` call alone (its LU included, \
         reading the files excluded). `satqual modal` process: the command as a user runs it \
         (`--fmax`, the auto solver, JSON out), whole process from start to exit. LAPACK: \
         `scipy.linalg.eigh(K, M, subset_by_value=(−∞, (2π·fmax)²))` with eigenvectors on the \
         same matrices, dense copies made before the clock starts. eigsh and LAPACK on one \
         OpenBLAS thread. Wall clock on this machine ({} cores, shared: load average {} before \
         and {} after the run): the `satqual modal` process and LAPACK the median of {} runs \
         where one takes under {} s, everything else one run.\n",
        r.fmax_hz,
        r.tolerance,
        r.model,
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
        r.load_average[0],
        r.load_average[1],
        REPEATS,
        REPEAT_BELOW_S
    );
    let _ = writeln!(
        s,
        "| satellites | DOFs | modes < fmax | Sturm count | satqual [s] | dense [s] | peak mem [MB] | eigsh [s] | satqual/eigsh | max rel Δf | `satqual modal` process [s] | process peak mem [MB] | LAPACK eigh subset [s] | process/LAPACK | note |"
    );
    let _ = writeln!(
        s,
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let opt = |v: Option<f64>, p: usize| v.map(|x| format!("{x:.p$}")).unwrap_or("–".into());
    for row in &r.stacks {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            row.satellites,
            row.dofs,
            row.modes_below_fmax,
            row.sturm_count.map(|c| c.to_string()).unwrap_or("–".into()),
            row.time_s,
            opt(row.dense_time_s, 3),
            opt(row.peak_memory_mb, 0),
            opt(row.eigsh_time_s, 3),
            opt(row.ratio_satqual_over_eigsh, 3),
            row.max_rel_freq_diff_vs_eigsh
                .map(|x| format!("{x:.1e}"))
                .unwrap_or("–".into()),
            opt(row.cli_time_s, 3),
            opt(row.cli_peak_mb, 0),
            opt(row.lapack_time_s, 3),
            opt(row.ratio_cli_over_lapack, 2),
            [row.model_note.clone(), row.eigsh_note.clone()]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    // The stack rows that ran both solvers, as measured in this run.
    let stack_pairs = r
        .stacks
        .iter()
        .filter_map(|row| {
            row.dense_time_s.map(|d| {
                format!(
                    "{} DOFs: dense {d:.3} s, sparse {:.3} s",
                    row.dofs, row.time_s
                )
            })
        })
        .collect::<Vec<_>>()
        .join("; ");
    let _ = writeln!(
        s,
        "\n## Dense or sparse: the crossover\n\nThe dense solver's cost is fixed by the DOFs (all modes, \
         O(n³)); the sparse one's grows with the modes asked for. On generated frame towers (beams, \
         offset masses, springs) with the lowest tenth of the modes (at most 100), see the table below; \
         on the stack, where about 45% of all modes lie below 2 kHz: {stack_pairs}. `Auto` models \
         the dense cost as {:.1e} s × DOFs³ + {:.1e} s × DOFs × modes² (the kept modes' \
         orthonormalisation and checks) and the sparse one as {:.1e} s × DOFs × max(modes, {}) \
         (constants fitted to this table, see `modal::auto_prefers_sparse`) and takes the cheaper; \
         up to {} DOFs it stays dense. Error of each path: its worst backward error \
         ‖Kφ − λMφ‖ / (‖|K||φ|‖ + |λ|·‖|M||φ|‖), and the largest relative difference of the two \
         paths' frequencies. The last column is `Auto`'s choice.\n",
        r.auto_cost_model[0],
        crate::modal::DENSE_S_PER_DOF_MODE2,
        r.auto_cost_model[1],
        crate::modal::SPARSE_MIN_MODES,
        crate::modal::AUTO_DENSE_DOFS
    );
    let _ = writeln!(
        s,
        "| DOFs | modes | dense [s] | dense backward error | sparse [s] | sparse backward error | max rel Δf | auto |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---:|---:|---|");
    for c in &r.crossover {
        let auto = if crate::modal::auto_prefers_sparse(c.dofs, c.modes) {
            "sparse"
        } else {
            "dense"
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {} | {:.3} | {} | {:.1e} | {auto} |",
            c.dofs,
            c.modes,
            c.dense_s,
            sci(c.dense_backward_error),
            c.sparse_s,
            sci(c.sparse_backward_error),
            c.max_rel_freq_diff
        );
    }
    s.push_str(&super::modal_peers::markdown(&r.few_modes));
    s.push_str(&super::modal_sweep::markdown(&r.fmax_sweep));
    s
}

/// A value in scientific notation with one decimal, or a dash.
pub(super) fn sci(v: Option<f64>) -> String {
    v.map_or("–".into(), |x| format!("{x:.1e}"))
}

pub(super) fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn peak_mb() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    Some(vm_hwm_kb(&s)? / 1024.0)
}

pub(super) fn python_with_scipy() -> Option<PathBuf> {
    let ok = std::process::Command::new("python3")
        .args(["-c", "import scipy.sparse.linalg, scipy.io"])
        .output()
        .ok()?
        .status
        .success();
    ok.then(|| PathBuf::from("python3"))
}

/// `satqual modal SCENE --fmax FMAX --json` by this executable, output discarded: the wall
/// time of the whole process, as a user sees it. `None` when it does not run.
fn cli_time(scene: &Path) -> Option<f64> {
    cli_time_with(scene, &["--fmax", &FMAX_HZ.to_string()])
}

/// `satqual modal SCENE ARGS --json` by this executable, output discarded: the process's wall
/// time (the median of [`REPEATS`] runs when one takes less than [`REPEAT_BELOW_S`]), or
/// `None` when it does not run.
pub(super) fn cli_time_with(scene: &Path, args: &[&str]) -> Option<f64> {
    let once = || -> Option<f64> {
        let mut command = modal_process(scene, args)?;
        let t0 = Instant::now();
        let status = command.status().ok()?;
        let t = t0.elapsed().as_secs_f64();
        status.success().then_some(t)
    };
    let first = once()?;
    if first >= REPEAT_BELOW_S {
        return Some(first);
    }
    let mut times = vec![first];
    for _ in 1..REPEATS {
        times.push(once()?);
    }
    times.sort_by(f64::total_cmp);
    Some(times[REPEATS / 2])
}

/// The peak resident memory of `satqual modal SCENE --fmax FMAX --json` by this executable:
/// its VmHWM, read every 5 ms until it exits (a sampled high-water mark, so a lower bound by at
/// most what the last 5 ms allocate). `None` when it does not run.
fn cli_peak_mb(scene: &Path) -> Option<f64> {
    let mut child = modal_process(scene, &["--fmax", &FMAX_HZ.to_string()])?
        .spawn()
        .ok()?;
    let status_file = format!("/proc/{}/status", child.id());
    let mut peak: Option<f64> = None;
    loop {
        if let Some(kb) = std::fs::read_to_string(&status_file)
            .ok()
            .and_then(|s| vm_hwm_kb(&s))
        {
            peak = Some(peak.unwrap_or(0.0).max(kb / 1024.0));
        }
        match child.try_wait().ok()? {
            Some(status) => return status.success().then_some(peak).flatten(),
            None => std::thread::sleep(std::time::Duration::from_millis(5)),
        }
    }
}

/// `satqual modal SCENE ARGS --json` by this executable, its output discarded.
fn modal_process(scene: &Path, args: &[&str]) -> Option<std::process::Command> {
    let mut command = std::process::Command::new(std::env::current_exe().ok()?);
    command
        .arg("modal")
        .arg(scene)
        .args(args)
        .arg("--json")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null());
    Some(command)
}

/// The VmHWM line of a /proc status file, kB.
fn vm_hwm_kb(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Runs that take less than this are repeated [`REPEATS`] times and their median reported:
/// on a shared machine one run of a tenth of a second scatters by ±10%.
pub(super) const REPEAT_BELOW_S: f64 = 3.0;
pub(super) const REPEATS: usize = 5;

/// Runs eigsh in shift-invert mode for the lowest `k` modes, and up to `DENSE_MAX_DOFS`
/// LAPACK's subset eigh; returns (eigsh seconds, eigsh frequencies, LAPACK seconds). Both on
/// one OpenBLAS thread, their fastest setting on this shared 2-core machine.
fn eigsh(
    py: &Path,
    dir: &Path,
    kfile: &str,
    k: usize,
    n: usize,
) -> Result<(f64, Vec<f64>, Option<f64>), String> {
    if k == 0 || k >= n {
        return Err(format!("eigsh needs 0 < k < n (k = {k}, n = {n})"));
    }
    // σ below the spectrum (the lowest stack mode is a few Hz), as the Lanczos starts.
    let script = format!(
        r#"
import json, time, numpy as np, scipy.io, scipy.sparse.linalg as sla
K = scipy.io.mmread(r"{k}").tocsc(); M = scipy.io.mmread(r"{m}").tocsc()
t = time.perf_counter()
w = sla.eigsh(K, k={kk}, M=M, sigma=-1.0, which="LM", tol={tol}, return_eigenvectors=False)
t = time.perf_counter() - t
f = np.sort(np.sign(w) * np.sqrt(np.abs(w)) / (2 * np.pi))
lapack = None
if K.shape[0] <= {dense_max}:
    import scipy.linalg as la
    Kd = K.toarray(); Md = M.toarray(); lmax = (2 * np.pi * {fmax}) ** 2
    runs = []
    while len(runs) < ({repeats} if not runs or runs[0] < {repeat_below} else 1):
        t2 = time.perf_counter()
        la.eigh(Kd, Md, subset_by_value=(-np.inf, lmax))
        runs.append(time.perf_counter() - t2)
    lapack = sorted(runs)[len(runs) // 2]
print(json.dumps({{"time": t, "freq": f.tolist(), "lapack": lapack}}))
"#,
        k = dir.join(kfile).display(),
        m = dir.join("M.mtx").display(),
        kk = k,
        tol = TOL,
        dense_max = DENSE_MAX_DOFS,
        fmax = FMAX_HZ,
        repeats = REPEATS,
        repeat_below = REPEAT_BELOW_S
    );
    let v = python_json(py, &script, "eigsh")?;
    let t = v["time"].as_f64().ok_or("eigsh output: no time")?;
    Ok((t, frequencies(&v)?, v["lapack"].as_f64()))
}

/// The `freq` array of the peer scripts' JSON output, Hz.
pub(super) fn frequencies(v: &serde_json::Value) -> Result<Vec<f64>, String> {
    Ok(v["freq"]
        .as_array()
        .ok_or("eigsh output: no frequencies")?
        .iter()
        .filter_map(|x| x.as_f64())
        .collect())
}

/// Runs `script` with python3 on one OpenBLAS thread and parses the JSON it prints; stopped
/// after [`EIGSH_LIMIT_S`]. `what` names the peer in the errors.
pub(super) fn python_json(
    py: &Path,
    script: &str,
    what: &str,
) -> Result<serde_json::Value, String> {
    let mut child = std::process::Command::new(py)
        .args(["-c", script])
        .env("OPENBLAS_NUM_THREADS", "1")
        .env("OMP_NUM_THREADS", "1")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("python3: {e}"))?;
    let t0 = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if t0.elapsed().as_secs_f64() > EIGSH_LIMIT_S => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!(
                    "{what} did not finish within {EIGSH_LIMIT_S:.0} s (stopped)"
                ));
            }
            Ok(None) => std::thread::sleep(std::time::Duration::from_millis(50)),
            Err(e) => return Err(format!("python3: {e}")),
        }
    }
    let out = child
        .wait_with_output()
        .map_err(|e| format!("python3: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "{what} failed: {}",
            err.lines().last().unwrap_or("").trim()
        ));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("{what} output: {e}"))
}

/// The stack scenes: the paper stack with `satellites = N`.
fn stack_scenes() -> Result<(String, Vec<(usize, String)>), Error> {
    let path = Path::new(catalogue::PAPER_STACK);
    let base = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let scenes = SATELLITES
        .iter()
        .map(|&n| (n, catalogue::generated::stack_with_satellites(&base, n)))
        .collect();
    Ok((
        "test-specs/paper-stack.toml with `satellites = N` (guide bars lengthened by one pitch per added satellite)".into(),
        scenes,
    ))
}

/// Dense against sparse on generated frame towers of growing size.
fn crossover() -> Result<Vec<CrossRow>, Error> {
    let mut rows = Vec::new();
    for levels in [2usize, 4, 6, 9] {
        let text = FrameTower::clamped(4, 3, levels).scene();
        let scene = Scene::parse(Path::new("frame.toml"), &text)?;
        let model = FeModel::from_scene(&scene.model)?;
        let n = model.reduction()?.n_red;
        let modes = (n / 10).clamp(1, 100);
        let mut t = [0.0; 2];
        let mut results = Vec::new();
        for (i, solver) in [SolverChoice::Dense, SolverChoice::Sparse]
            .iter()
            .enumerate()
        {
            let t0 = Instant::now();
            let sys = analyze(
                &model,
                &ModalOptions {
                    fmax_hz: None,
                    modes: Some(modes),
                    solver: *solver,
                    stop_beyond_buckling: false,
                    ..Default::default()
                },
            )?;
            t[i] = t0.elapsed().as_secs_f64();
            results.push(sys.result);
        }
        let freqs = |r: &crate::modal::ModalResult| -> Vec<f64> {
            r.modes.iter().map(|m| m.frequency_hz).collect()
        };
        let (dense, sparse) = (&results[0], &results[1]);
        let max_rel_freq_diff = freqs(sparse)
            .iter()
            .zip(freqs(dense))
            .map(|(s, d)| (s - d).abs() / d.abs())
            .fold(0.0, f64::max);
        eprintln!(
            "crossover: {n} DOFs, {modes} modes: dense {:.3} s, sparse {:.3} s, max rel Δf {max_rel_freq_diff:.1e}",
            t[0], t[1]
        );
        rows.push(CrossRow {
            dofs: n,
            modes,
            dense_s: t[0],
            sparse_s: t[1],
            dense_backward_error: dense.dense.as_ref().map(|d| d.max_backward_error),
            sparse_backward_error: sparse.sparse.as_ref().map(|st| st.max_backward_error),
            max_rel_freq_diff,
        });
    }
    Ok(rows)
}
