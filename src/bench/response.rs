//! `satqual bench response`: run time against error for the response analyses, written to
//! `reports/bench/response.{json,md}`:
//! - random: Grms error of the response points against the number of frequency points, for
//!   the clustered grid and for a uniform log grid (reference: a 400 000-point log grid);
//! - sine: peak error of the response points against the number of points, without the
//!   golden-section refinement (reference: refined peaks on a dense clustered grid);
//! - modal truncation: error of modal superposition against the direct complex solution of
//!   (K − ω²M + iωC)·x = −p, against the number of modes, with and without the residual vector.

use crate::Error;
use crate::response::grid::{self, GridSpec};
use crate::response::{Prepared, SineOptions};
use crate::spec::Scene;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

#[derive(Serialize)]
struct GridRow {
    grid: String,
    points: usize,
    max_error_pct: f64,
    time_ms: f64,
}

#[derive(Serialize)]
struct TruncRow {
    axis: String,
    modes: usize,
    highest_mode_hz: f64,
    residual_vector: bool,
    /// Max over response points and frequencies of |H_modal − H_direct| / |H_direct|.
    point_error_pct: f64,
    /// Max over joints and bar stations of |F_modal − F_direct| / max_f |F_direct| (scaled by
    /// each output's peak, so that anti-resonances do not dominate; outputs the axis does not
    /// load are scaled by 1e-3 of the largest output of their kind, and at least 1e-6 of the
    /// largest load of any kind).
    load_error_pct: f64,
    time_ms: f64,
}

#[derive(Serialize)]
struct Bench {
    random_scene: String,
    random_axis: String,
    random_reference_points: usize,
    random: Vec<GridRow>,
    sine_scene: String,
    sine_axis: String,
    sine: Vec<GridRow>,
    truncation_scene: String,
    truncation_frequencies: usize,
    direct_time_ms: f64,
    truncation: Vec<TruncRow>,
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn load(path: &str) -> Result<Scene, Error> {
    Scene::load(Path::new(path))
}

/// Grms of the given point rows on a grid (piecewise power-law rule).
fn grms(
    frf: &crate::response::ModalFrf,
    rows: &[usize],
    f: &[f64],
    table: &[(f64, f64)],
) -> Vec<f64> {
    let mut psd = vec![vec![0.0; f.len()]; rows.len()];
    let mut h = Vec::new();
    for (k, &x) in f.iter().enumerate() {
        frf.eval_rows(x, rows, &mut h);
        let s = crate::units::loglog_interp(table, x);
        for (r, v) in h.iter().enumerate() {
            psd[r][k] = v.norm_sqr() * s;
        }
    }
    psd.iter().map(|p| grid::integrate(f, p).sqrt()).collect()
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
        * 100.0
}

/// The table as (JSON, Markdown).
pub fn run() -> Result<(String, String), Error> {
    // ---- random: paper stack, x axis, at the scene's Q = 15 and at Q = 100 ----
    let rs = crate::catalogue::PAPER_STACK;
    let scene = load(rs)?;
    let (model, sys) = crate::pipeline::modal(&scene, None, None)?;
    let prep = Prepared::new(&scene, &model, &sys)?;
    let (spec, _) = scene
        .file
        .random
        .as_ref()
        .ok_or_else(|| Error::Other(format!("{rs} has no [random]")))?
        .applied(Some(sys.result.total_mass_kg))
        .map_err(|e| Error::Other(format!("{rs}: {e}")))?;
    let table = spec.table();
    let (lo, hi) = (table[0].0, table[table.len() - 1].0);
    let n_ref = 400_000;
    let mut random = Vec::new();
    for q in [None, Some(100.0)] {
        let mut p = Prepared::new(&scene, &model, &sys)?;
        if let Some(q) = q {
            p.damping = crate::spec::analysis::DampingSpec {
                q: Some(q),
                ..Default::default()
            };
        }
        let qname = format!("Q = {:.0}", 0.5 / p.damping.zeta_at(100.0));
        let axis = 0;
        let basis = p.basis(axis, None, true)?;
        let frf = p.modal_frf(&basis);
        let rows: Vec<usize> = p.outputs.points.iter().map(|x| x.rows[axis]).collect();
        let reference = grms(&frf, &rows, &grid::log_n(lo, hi, n_ref), &table);
        for (pd, pm, tail) in [
            (10, 5, 0.0),
            (20, 11, 0.0),
            (30, 21, 0.0),
            (60, 41, 0.0),
            (100, 81, 0.0),
            (20, 21, 1.25),
            (60, 41, 1.25),
        ] {
            let g = GridSpec {
                per_decade: pd,
                per_mode: pm,
                halfwidth: 5.0,
                tail_ratio: tail,
                ..GridSpec::RANDOM
            };
            let t = Instant::now();
            let f = crate::response::random::grid_for(&spec, &basis, g)?;
            let v = grms(&frf, &rows, &f, &table);
            let tails = if tail > 1.0 {
                format!(", tails ×{tail}")
            } else {
                String::new()
            };
            let default = if g == GridSpec::RANDOM {
                " (default)"
            } else {
                ""
            };
            random.push(GridRow {
                grid: format!("{qname}: clustered {pd}/decade + {pm}/mode (±5ζ){tails}{default}"),
                points: f.len(),
                max_error_pct: max_rel(&v, &reference),
                time_ms: ms(t),
            });
        }
        for n in [300usize, 1000, 3000, 10_000, 30_000] {
            let t = Instant::now();
            let f = grid::log_n(lo, hi, n);
            let v = grms(&frf, &rows, &f, &table);
            random.push(GridRow {
                grid: format!("{qname}: uniform log"),
                points: n,
                max_error_pct: max_rel(&v, &reference),
                time_ms: ms(t),
            });
        }
    }

    // ---- sine: shaker-2sat, x axis ----
    let ss = crate::catalogue::SHAKER_2SAT;
    let s2 = load(ss)?;
    let (m2, sys2) = crate::pipeline::modal(&s2, None, None)?;
    let p2 = Prepared::new(&s2, &m2, &sys2)?;
    let sspec = s2
        .file
        .sine
        .clone()
        .ok_or_else(|| Error::Other(format!("{ss} has no [sine]")))?;
    let dense = GridSpec {
        per_decade: 200,
        per_mode: 401,
        halfwidth: 4.0,
        tail_ratio: 0.0,
        ..GridSpec::SINE
    };
    let r = crate::response::sine::run(
        &p2,
        &sspec,
        0,
        &SineOptions {
            grid: dense,
            ..Default::default()
        },
    )?;
    let peak_ref: Vec<f64> = r.peaks.iter().map(|p| p.acceleration_g).collect();
    let b2 = p2.basis(0, None, true)?;
    let f2 = p2.modal_frf(&b2);
    let rows2: Vec<usize> = p2.outputs.points.iter().map(|p| p.rows[0]).collect();
    let (slo, shi) = sspec.band();
    let modes2 = b2.excited_modes();
    let peaks_on = |f: &[f64]| -> Vec<f64> {
        let mut best = vec![0.0f64; rows2.len()];
        let mut h = Vec::new();
        for &x in f {
            f2.eval_rows(x, &rows2, &mut h);
            let a = sspec.level_g(x);
            for (b, v) in best.iter_mut().zip(&h) {
                *b = b.max(v.norm() * a);
            }
        }
        best
    };
    let mut sine = Vec::new();
    for (pd, pm) in [(10, 5), (20, 11), (40, 21), (60, 41), (60, 81)] {
        let g = GridSpec {
            per_decade: pd,
            per_mode: pm,
            halfwidth: 4.0,
            tail_ratio: 0.0,
            ..GridSpec::SINE
        };
        let t = Instant::now();
        let f = grid::clustered(slo, shi, &modes2, g, &[5.0, 8.0, 100.0])?;
        let v = peaks_on(&f);
        sine.push(GridRow {
            grid: format!("clustered {pd}/decade + {pm}/mode (±4ζ)"),
            points: f.len(),
            max_error_pct: max_rel(&v, &peak_ref),
            time_ms: ms(t),
        });
    }
    for n in [100usize, 300, 1000, 3000, 10_000] {
        let t = Instant::now();
        let f = grid::log_n(slo, shi, n);
        let v = peaks_on(&f);
        sine.push(GridRow {
            grid: "uniform log".into(),
            points: n,
            max_error_pct: max_rel(&v, &peak_ref),
            time_ms: ms(t),
        });
    }

    // ---- truncation: paper stack, against the direct solution, 5–100 Hz ----
    let mut fgrid = grid::log_n(5.0, 100.0, 40);
    for m in &sys.result.modes {
        if m.frequency_hz > 5.0 && m.frequency_hz < 100.0 {
            fgrid.push(m.frequency_hz);
        }
    }
    fgrid.sort_by(f64::total_cmp);
    let mut truncation = Vec::new();
    let mut direct_ms = 0.0;
    for axis in [0usize, 2] {
        let t = Instant::now();
        let d = prep.direct_frf(axis)?;
        let hd = crate::response::frf::on_grid(&d, &fgrid);
        direct_ms += ms(t);
        // (row, class): class 0 = forces (N), 1 = moments (N·m).
        let load_rows: Vec<(usize, usize)> = prep
            .outputs
            .interfaces
            .iter()
            .flat_map(|i| {
                i.rows
                    .iter()
                    .enumerate()
                    .map(|(c, &r)| (r, c / 3))
                    .collect::<Vec<_>>()
            })
            .chain(prep.outputs.stations.iter().flat_map(|s| {
                s.rows
                    .iter()
                    .enumerate()
                    .map(|(c, &r)| (r, usize::from(c > 0)))
                    .collect::<Vec<_>>()
            }))
            .collect();
        let raw: Vec<f64> = load_rows
            .iter()
            .map(|&(r, _)| hd.iter().map(|h| h[r].norm()).fold(0.0, f64::max))
            .collect();
        // An output that the axis does not load (a z force under x drive) has a round-off
        // peak: scale its error by 1e-3 of the largest output of its class instead.
        let class_max: Vec<f64> = (0..2)
            .map(|c| {
                load_rows
                    .iter()
                    .zip(&raw)
                    .filter(|((_, k), _)| *k == c)
                    .map(|(_, &v)| v)
                    .fold(0.0, f64::max)
            })
            .collect();
        // A class that the axis does not load at all (bending under a symmetric z drive) is
        // round-off throughout: floor it at 1e-6 of the largest load of any kind.
        let all_max = class_max[0].max(class_max[1]);
        let peak: Vec<f64> = load_rows
            .iter()
            .zip(&raw)
            .map(|(&(_, c), &v)| v.max(1e-3 * class_max[c]).max(1e-6 * all_max))
            .collect();
        let point_rows: Vec<usize> = prep.outputs.points.iter().map(|p| p.rows[axis]).collect();
        // Mode counts by cut-off frequency: below, at, and above the 100 Hz band edge.
        let count = |fc: f64| {
            sys.result
                .modes
                .iter()
                .filter(|m| m.frequency_hz <= fc)
                .count()
        };
        let mut counts: Vec<usize> = [
            50.0,
            100.0,
            125.0,
            150.0,
            200.0,
            300.0,
            500.0,
            1000.0,
            f64::INFINITY,
        ]
        .iter()
        .map(|&fc| count(fc))
        .collect();
        counts.dedup();
        for n in counts {
            for residual in [false, true] {
                let t = Instant::now();
                let b = prep.basis(axis, Some(n), residual)?;
                let mf = prep.modal_frf(&b);
                let hm = crate::response::frf::on_grid(&mf, &fgrid);
                let el = ms(t);
                let mut pe = 0.0f64;
                let mut le = 0.0f64;
                for k in 0..fgrid.len() {
                    for &r in &point_rows {
                        pe = pe.max((hm[k][r] - hd[k][r]).norm() / hd[k][r].norm());
                    }
                    for (i, &(r, _)) in load_rows.iter().enumerate() {
                        if peak[i] > 0.0 {
                            let e = (hm[k][r] - hd[k][r]).norm() / peak[i];
                            le = le.max(e);
                        }
                    }
                }
                truncation.push(TruncRow {
                    axis: crate::response::axis_name(axis).into(),
                    modes: b.n_modes,
                    highest_mode_hz: b.frequency_hz(b.n_modes.saturating_sub(1)),
                    residual_vector: b.len() > b.n_modes,
                    point_error_pct: pe * 100.0,
                    load_error_pct: le * 100.0,
                    time_ms: el,
                });
            }
        }
    }
    let bench = Bench {
        random_scene: rs.into(),
        random_axis: "x".into(),
        random_reference_points: n_ref,
        random,
        sine_scene: ss.into(),
        sine_axis: "x".into(),
        sine,
        truncation_scene: rs.into(),
        truncation_frequencies: fgrid.len(),
        direct_time_ms: direct_ms,
        truncation,
    };
    Ok((super::to_json(&bench)?, markdown(&bench)))
}

fn markdown(b: &Bench) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# satqual bench response\n");
    let _ = writeln!(
        s,
        "## Random: Grms error against frequency points\n\n{} axis {}, every response point, at the scene's damping and at Q = 100; reference: {} log-spaced points. Error = max over points.\n",
        b.random_scene, b.random_axis, b.random_reference_points
    );
    let _ = writeln!(
        s,
        "| grid | points | max Grms error % | time ms |\n|---|---:|---:|---:|"
    );
    for r in &b.random {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2e} | {:.1} |",
            r.grid, r.points, r.max_error_pct, r.time_ms
        );
    }
    let _ = writeln!(
        s,
        "\n## Sine: peak error against frequency points (no refinement)\n\n{} axis {}; reference: refined peaks on a 200/decade + 401/mode grid.\n",
        b.sine_scene, b.sine_axis
    );
    let _ = writeln!(
        s,
        "| grid | points | max peak error % | time ms |\n|---|---:|---:|---:|"
    );
    for r in &b.sine {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2e} | {:.1} |",
            r.grid, r.points, r.max_error_pct, r.time_ms
        );
    }
    let _ = writeln!(
        s,
        "\n## Modal truncation against the direct solution (5–100 Hz)\n\n{}: {} frequencies (40 log-spaced + every mode in the band); the direct complex solves took {:.0} ms for both axes. Point error: max |H_modal − H_direct|/|H_direct| over response points and frequencies; load error: max over joint forces and bar-station loads, scaled by each output's peak.\n",
        b.truncation_scene, b.truncation_frequencies, b.direct_time_ms
    );
    let _ = writeln!(
        s,
        "| axis | modes | highest mode Hz | residual vector | point error % | load error % | time ms |\n|---|---:|---:|---|---:|---:|---:|"
    );
    for r in &b.truncation {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {:.3e} | {:.3e} | {:.1} |",
            r.axis,
            r.modes,
            r.highest_mode_hz,
            if r.residual_vector { "yes" } else { "no" },
            r.point_error_pct,
            r.load_error_pct,
            r.time_ms
        );
    }
    s
}
