//! A few modes of mid-size models against the peers (`satqual bench modal`, section "A few
//! modes"): frame towers of beams and point masses (a model CalculiX holds as it is), the
//! lowest [`MODES`] modes, by `satqual modal` as a process, by scipy's eigsh and LAPACK's
//! subset eigh on the same exported matrices, and by CalculiX (`ccx`, 3-node B32R beams on the
//! same geometry and element count, which it expands into 20-node bricks).

use super::modal::{
    REPEAT_BELOW_S, REPEATS, cli_time_with, frequencies, python_json, python_with_scipy, sci,
};
use crate::Error;
use crate::catalogue::generated::{FrameTower, TowerMember};
use crate::fem::FeModel;
use crate::modal::{ModalOptions, analyze};
use crate::spec::{Scene, SolverChoice};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// Modes asked for: "a few", as a first look at a design asks.
const MODES: usize = 12;
/// Tower heights (floors of a 4 × 3 grid): about 1000, 2200 and 3400 DOFs.
const LEVELS: [usize; 3] = [4, 9, 14];

#[derive(Serialize)]
pub(super) struct PeerRow {
    dofs: usize,
    modes: usize,
    satqual_process_s: Option<f64>,
    eigsh_s: Option<f64>,
    lapack_s: Option<f64>,
    calculix_process_s: Option<f64>,
    /// satqual's process time over the fastest peer's.
    ratio_over_best_peer: Option<f64>,
    max_rel_freq_diff_vs_eigsh: Option<f64>,
    /// A model difference, not a solver error: CalculiX's beams are bricks with rigid knots
    /// at the joints.
    max_rel_freq_diff_vs_calculix: Option<f64>,
    notes: Vec<String>,
}

/// Every tower of [`LEVELS`]; scenes, matrices and CalculiX decks go to `work`.
pub(super) fn run(work: &Path) -> Result<Vec<PeerRow>, Error> {
    let python = python_with_scipy();
    let ccx = calculix();
    LEVELS
        .iter()
        .map(|&levels| bench_tower(work, levels, python.as_deref(), ccx.as_deref()))
        .collect()
}

fn tower(levels: usize) -> FrameTower {
    FrameTower {
        beams_and_point_masses: true,
        ..FrameTower::clamped(4, 3, levels)
    }
}

fn bench_tower(
    work: &Path,
    levels: usize,
    python: Option<&Path>,
    ccx: Option<&Path>,
) -> Result<PeerRow, Error> {
    let t = tower(levels);
    let name = format!("tower-{levels}");
    let scene_path = work.join(format!("{name}.toml"));
    let text = t.scene();
    std::fs::write(&scene_path, &text).map_err(|e| Error::io(&scene_path, e))?;
    let scene = Scene::parse(&scene_path, &text)?;
    let model = FeModel::from_scene(&scene.model)?;
    let opts = ModalOptions {
        fmax_hz: None,
        modes: Some(MODES),
        solver: SolverChoice::Auto,
        stop_beyond_buckling: false,
        ..Default::default()
    };
    let sys = analyze(&model, &opts)?;
    let ours: Vec<f64> = sys.result.modes.iter().map(|m| m.frequency_hz).collect();
    let mut row = PeerRow {
        dofs: sys.reduction.n_red,
        modes: ours.len(),
        satqual_process_s: cli_time_with(&scene_path, &["--modes", &MODES.to_string()]),
        eigsh_s: None,
        lapack_s: None,
        calculix_process_s: None,
        ratio_over_best_peer: None,
        max_rel_freq_diff_vs_eigsh: None,
        max_rel_freq_diff_vs_calculix: None,
        notes: Vec::new(),
    };
    match python {
        None => row
            .notes
            .push("python3 with scipy not found: eigsh not run".into()),
        Some(py) => {
            let dir = work.join(format!("{name}-matrices"));
            crate::pipeline::workflows::matrices::export(&dir, &model, &sys)?;
            match scipy_few_modes(py, &dir) {
                Ok((te, tl, f)) => {
                    row.eigsh_s = Some(te);
                    row.lapack_s = Some(tl);
                    row.max_rel_freq_diff_vs_eigsh = Some(max_rel_diff(&ours, &f));
                }
                Err(e) => row.notes.push(e),
            }
        }
    }
    match ccx {
        None => row.notes.push("ccx (CalculiX) not found: not run".into()),
        Some(ccx) => match run_calculix(ccx, work, &name, &t) {
            Ok((tc, f)) => {
                row.calculix_process_s = Some(tc);
                row.max_rel_freq_diff_vs_calculix = Some(max_rel_diff(&ours, &f));
            }
            Err(e) => row.notes.push(e),
        },
    }
    let best = [row.eigsh_s, row.lapack_s, row.calculix_process_s]
        .into_iter()
        .flatten()
        .reduce(f64::min);
    row.ratio_over_best_peer = row.satqual_process_s.zip(best).map(|(a, b)| a / b);
    Ok(row)
}

/// Largest |a − b|/|b| over the pairs both lists have.
fn max_rel_diff(ours: &[f64], theirs: &[f64]) -> f64 {
    ours.iter()
        .zip(theirs)
        .map(|(a, b)| (a - b).abs() / b.abs())
        .fold(0.0, f64::max)
}

/// eigsh (shift-invert below the spectrum, the lowest [`MODES`]) and LAPACK's subset eigh
/// (the lowest [`MODES`] by index) on the exported K and M: (eigsh s, LAPACK s, eigsh Hz).
fn scipy_few_modes(py: &Path, dir: &Path) -> Result<(f64, f64, Vec<f64>), String> {
    let script = format!(
        r#"
import json, time, numpy as np, scipy.io, scipy.linalg as la, scipy.sparse.linalg as sla
K = scipy.io.mmread(r"{k}").tocsc(); M = scipy.io.mmread(r"{m}").tocsc()
def median_time(call):
    runs = []
    while len(runs) < ({repeats} if not runs or runs[0] < {repeat_below} else 1):
        t = time.perf_counter(); out = call(); runs.append(time.perf_counter() - t)
    return sorted(runs)[len(runs) // 2], out
t, (w, v) = median_time(lambda: sla.eigsh(K, k={modes}, M=M, sigma=-1.0, which="LM", tol={tol}))
Kd = K.toarray(); Md = M.toarray()
t2, _ = median_time(lambda: la.eigh(Kd, Md, subset_by_index=[0, {last}]))
f = np.sort(np.sqrt(np.abs(w)) / (2 * np.pi))
print(json.dumps({{"eigsh": t, "lapack": t2, "freq": f.tolist()}}))
"#,
        k = dir.join("K.mtx").display(),
        m = dir.join("M.mtx").display(),
        modes = MODES,
        last = MODES - 1,
        tol = crate::modal::sparse::RESIDUAL_TOL,
        repeats = REPEATS,
        repeat_below = REPEAT_BELOW_S,
    );
    let v = python_json(py, &script, "eigsh")?;
    let te = v["eigsh"].as_f64().ok_or("eigsh output: no time")?;
    let tl = v["lapack"].as_f64().ok_or("eigsh output: no LAPACK time")?;
    Ok((te, tl, frequencies(&v)?))
}

/// `ccx` on PATH, if installed (`apt-get install calculix-ccx`).
fn calculix() -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("ccx"))
        .find(|p| p.is_file())
}

/// Writes the tower's CalculiX deck, runs `ccx` on one thread and reads its frequencies:
/// (process wall time, the median of [`REPEATS`] runs when one is short; Hz ascending).
fn run_calculix(
    ccx: &Path,
    work: &Path,
    name: &str,
    t: &FrameTower,
) -> Result<(f64, Vec<f64>), String> {
    let deck = work.join(format!("{name}.inp"));
    std::fs::write(&deck, calculix_deck(t)).map_err(|e| format!("{}: {e}", deck.display()))?;
    let once = || -> Result<(f64, std::process::Output), String> {
        let t0 = Instant::now();
        let out = std::process::Command::new(ccx)
            .args(["-i", name])
            .current_dir(work)
            .env("OMP_NUM_THREADS", "1")
            .output()
            .map_err(|e| format!("ccx: {e}"))?;
        Ok((t0.elapsed().as_secs_f64(), out))
    };
    let (first, out) = once()?;
    let mut times = vec![first];
    while first < REPEAT_BELOW_S && times.len() < REPEATS {
        times.push(once()?.0);
    }
    times.sort_by(f64::total_cmp);
    let time = times[times.len() / 2];
    let dat = work.join(format!("{name}.dat"));
    let text = std::fs::read_to_string(&dat).unwrap_or_default();
    let f = calculix_frequencies(&text);
    if !out.status.success() || f.len() < MODES {
        let log = String::from_utf8_lossy(&out.stdout);
        let err = log
            .lines()
            .find(|l| l.contains("ERROR"))
            .unwrap_or("no frequencies");
        return Err(format!("ccx failed: {}", err.trim()));
    }
    Ok((time, f))
}

/// The frequencies (cycles/time column) of the `.dat` file's eigenvalue table.
fn calculix_frequencies(dat: &str) -> Vec<f64> {
    let Some(at) = dat.find("E I G E N V A L U E   O U T P U T") else {
        return Vec::new();
    };
    dat[at..]
        .lines()
        .skip(1)
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .skip_while(|w| w.first().and_then(|x| x.parse::<usize>().ok()).is_none())
        .take_while(|w| w.len() == 5 && w[0].parse::<usize>().is_ok())
        .filter_map(|w| w[3].parse::<f64>().ok())
        .collect()
}

/// The tower as a CalculiX deck: each member in the scene's element count of B32R beams (a
/// mid-side node each), PIPE and RECT sections oriented as satqual's (local 1 along global z
/// for floor beams, along y for columns), MASS elements at the top, the base clamped, and a
/// frequency step for the lowest [`MODES`].
fn calculix_deck(t: &FrameTower) -> String {
    let mut nodes: Vec<(usize, [f64; 3])> = t.nodes();
    let mut next_node = nodes.iter().map(|n| n.0).max().unwrap_or(0) + 1;
    let mut sets: [Vec<String>; 3] = Default::default();
    let mut next_el = 1;
    for m in t.members() {
        let chain = subdivide(&m, t.elements, &mut nodes, &mut next_node);
        for pair in chain.windows(3).step_by(2) {
            let set = member_set(&m);
            sets[set].push(format!("{next_el},{},{},{}", pair[0], pair[1], pair[2]));
            next_el += 1;
        }
    }
    let mut s = String::from("*NODE,NSET=NALL\n");
    for (id, [x, y, z]) in &nodes {
        let _ = writeln!(s, "{id},{x:.9},{y:.9},{z:.9}");
    }
    for (set, lines) in ["TUBEX", "RECTY", "TUBEZ"].iter().zip(&sets) {
        let _ = writeln!(s, "*ELEMENT,TYPE=B32R,ELSET={set}\n{}", lines.join("\n"));
    }
    for (i, (node, kg)) in t.top_masses().into_iter().enumerate() {
        let _ = writeln!(
            s,
            "*ELEMENT,TYPE=MASS,ELSET=M{i}\n{},{node}\n*MASS,ELSET=M{i}\n{kg}",
            next_el + i
        );
    }
    let base: Vec<String> = t.base_nodes().iter().map(|n| n.to_string()).collect();
    let _ = writeln!(
        s,
        "*NSET,NSET=BASE\n{}\n*BOUNDARY\nBASE,1,6",
        base.join(",\n")
    );
    // The scene's steel, tube (60/50 mm) and rectangle (0.04 wide, 0.03 high along z).
    s.push_str(
        "*MATERIAL,NAME=STEEL\n*ELASTIC\n210e9,0.3\n*DENSITY\n7850\n\
         *BEAM SECTION,ELSET=TUBEX,MATERIAL=STEEL,SECTION=PIPE\n0.03,0.005\n0,0,1\n\
         *BEAM SECTION,ELSET=TUBEZ,MATERIAL=STEEL,SECTION=PIPE\n0.03,0.005\n0,1,0\n\
         *BEAM SECTION,ELSET=RECTY,MATERIAL=STEEL,SECTION=RECT\n0.03,0.04\n0,0,1\n",
    );
    let _ = writeln!(s, "*STEP\n*FREQUENCY,SOLVER=SPOOLES\n{MODES}\n*END STEP");
    s
}

/// Index into the deck's element sets: tube floor beams, rectangle floor beams, columns.
fn member_set(m: &TowerMember) -> usize {
    match (m.section, m.axis) {
        ("rect", _) => 1,
        (_, 2) => 2,
        _ => 0,
    }
}

/// The member's node chain with `elements` 3-node segments: its two end nodes and the new
/// interior and mid-side nodes, evenly spaced (appended to `nodes`).
fn subdivide(
    m: &TowerMember,
    elements: usize,
    nodes: &mut Vec<(usize, [f64; 3])>,
    next: &mut usize,
) -> Vec<usize> {
    let at = |id: usize, nodes: &[(usize, [f64; 3])]| {
        nodes
            .iter()
            .find(|n| n.0 == id)
            .map(|n| n.1)
            .unwrap_or_default()
    };
    let (a, b) = (at(m.nodes[0], nodes), at(m.nodes[1], nodes));
    let steps = 2 * elements.max(1);
    let mut chain = vec![m.nodes[0]];
    for k in 1..steps {
        let f = k as f64 / steps as f64;
        nodes.push((*next, [0, 1, 2].map(|c| a[c] + f * (b[c] - a[c]))));
        chain.push(*next);
        *next += 1;
    }
    chain.push(m.nodes[1]);
    chain
}

/// The section's Markdown: the table and what it compares.
pub(super) fn markdown(rows: &[PeerRow]) -> String {
    let mut s = format!(
        "\n## A few modes: against eigsh, LAPACK and CalculiX\n\nThe lowest {MODES} modes of \
         frame towers of beams and point masses (a 4 × 3 grid, 2 elements per member, clamped). \
         satqual: the `satqual modal --modes {MODES}` process (the auto solver). eigsh \
         (shift-invert below the spectrum) and LAPACK `eigh(subset_by_index)`: the call alone on \
         the exported matrices, one OpenBLAS thread. CalculiX 2.20: the `ccx` process on one \
         thread, B32R beams on the same nodes and element count (CalculiX expands them into \
         20-node bricks with rigid knots at the joints, so its model is stiffer: the last column \
         is that model difference, not a solver error). Ratio: satqual over the fastest peer. Every \
         time is the median of {REPEATS} runs (those under {REPEAT_BELOW_S} s; longer ones run once).\n\n\
         | DOFs | modes | satqual process [s] | eigsh [s] | LAPACK subset [s] | CalculiX process [s] | satqual/best peer | max rel Δf vs eigsh | max rel Δf vs CalculiX | note |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n"
    );
    let f = |v: Option<f64>, p: usize| v.map_or("–".into(), |x| format!("{x:.p$}"));
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.dofs,
            r.modes,
            f(r.satqual_process_s, 3),
            f(r.eigsh_s, 3),
            f(r.lapack_s, 3),
            f(r.calculix_process_s, 3),
            f(r.ratio_over_best_peer, 2),
            sci(r.max_rel_freq_diff_vs_eigsh),
            sci(r.max_rel_freq_diff_vs_calculix),
            r.notes.join("; ")
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The deck of a one-floor tower holds every member (12 columns, 9 x-beams and 8 y-beams
    /// on the 4 × 3 grid) as 2 B32R elements, and every top mass; a `.dat` eigenvalue table
    /// is read back in its frequency column.
    #[test]
    fn deck_holds_the_tower_and_the_table_reads_back() {
        let t = tower(1);
        let deck = calculix_deck(&t);
        let members = t.members().len();
        assert_eq!(members, 12 + 9 + 8);
        let mut in_beams = false;
        let mut b32 = 0;
        for l in deck.lines() {
            if l.starts_with('*') {
                in_beams = l.starts_with("*ELEMENT,TYPE=B32R");
            } else if in_beams {
                b32 += 1;
            }
        }
        assert_eq!(b32, 2 * members);
        assert_eq!(deck.matches("TYPE=MASS").count(), 12);
        let dat = "     E I G E N V A L U E   O U T P U T\n\n MODE NO    EIGENVALUE   FREQUENCY\n\
                   \n      1   0.5555875E+03   0.2357090E+02   0.3751426E+01   0.0000000E+00\n\
                   \x20     2   0.9125705E+03   0.3020878E+02   0.4807877E+01   0.0000000E+00\n\n";
        assert_eq!(calculix_frequencies(dat), vec![3.751426, 4.807877]);
    }
}
