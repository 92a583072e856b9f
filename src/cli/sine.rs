//! `satqual sine`: base-driven sine-sweep response of a scene's `[sine]` level, per axis:
//! response-point peaks, joint loads, guide-bar stresses and the lock-integrity margins.

use super::progress::Progress;
use super::{Outcome, Printer};
use satqual::Error;
use satqual::gates::Verdict;
use satqual::pipeline::{plan, workflows};
use satqual::response;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with a [sine] section.
    pub scene: PathBuf,
    /// Only this axis (x, y or z); default: the scene's `sine.axes`.
    #[arg(long)]
    pub axis: Option<String>,
    /// Write CSV curves and SVG plots to this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Serialize)]
struct Output<'a> {
    scene: String,
    damping: String,
    pass: bool,
    axes: &'a [response::SineAxis],
}

/// The damping as applied; `modes_used` (the most any axis kept) names per-mode ratios given
/// for modes beyond it, which the response never reaches.
pub fn damping_text(
    d: &satqual::spec::analysis::DampingSpec,
    given: bool,
    modes_used: usize,
) -> String {
    let base = base_damping_text(d, given);
    let unused: Vec<String> = d
        .modes
        .iter()
        .flatten()
        .filter(|m| m.mode > modes_used)
        .map(|m| m.mode.to_string())
        .collect();
    if unused.is_empty() {
        base
    } else {
        format!(
            "{base}; the ratios given for mode(s) {} are not applied: the response uses modes 1–{modes_used}",
            unused.join(", ")
        )
    }
}

fn base_damping_text(d: &satqual::spec::analysis::DampingSpec, given: bool) -> String {
    let base = match (d.q, d.zeta, &d.table) {
        (Some(q), _, _) => format!("Q = {q} (ζ = {:.4})", 0.5 / q),
        (_, Some(z), _) => format!("ζ = {z} (Q = {:.2})", 0.5 / z),
        (_, _, Some(t)) => format!("ζ(f) table of {} points", t.len()),
        _ => format!(
            "Q = {} (ζ = {:.3})",
            satqual::spec::analysis::DEFAULT_Q,
            0.5 / satqual::spec::analysis::DEFAULT_Q
        ),
    };
    if given {
        base
    } else {
        format!("{base}, default (no [damping] in the scene)")
    }
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let plan = plan::sine_command(&scene, args.axis.as_deref())?;
    let progress = Progress::start(args.quiet, args.json, "sine response");
    let run = workflows::response::sine(&scene, &plan)?;
    progress.finish();
    let (spec, results) = (&plan.spec, &run.axes);
    let pass = results.iter().all(|r| r.margins.iter().all(|m| m.pass));
    let modes_used = results.iter().map(|r| r.modes_used).max().unwrap_or(0);
    let p = Printer::new(args.json);
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{}: sine {:.1}–{:.1} Hz, damping {}",
        args.scene.display(),
        spec.band().0,
        spec.band().1,
        damping_text(&run.damping, scene.file.damping.is_some(), modes_used)
    );
    for r in results {
        let _ = writeln!(
            t,
            "axis {}: {} modes + residual vector: {}, {} frequencies",
            r.axis, r.modes_used, r.residual_vector, r.frequency_points
        );
        for pk in &r.peaks {
            let _ = writeln!(
                t,
                "  {:<12} peak {:>9.3} g at {:>8.2} Hz (x{:.2} the input)",
                pk.name, pk.acceleration_g, pk.frequency_hz, pk.transmissibility
            );
        }
        if let Some(i) = r
            .interfaces
            .iter()
            .max_by(|a, b| a.max_tension_n.total_cmp(&b.max_tension_n))
        {
            let _ = writeln!(
                t,
                "  worst joint tension {:.0} N ({}), shear {:.0} N",
                i.max_tension_n, i.name, i.max_shear_n
            );
        }
        if let Some(s) = r
            .bar_stations
            .iter()
            .max_by(|a, b| a.max_stress_pa.total_cmp(&b.max_stress_pa))
        {
            let _ = writeln!(
                t,
                "  worst guide-bar dynamic stress {:.1} MPa ({} at {:.2} Hz)",
                s.max_stress_pa / 1e6,
                s.name,
                s.frequency_hz
            );
        }
        summarize_margins(&mut t, &r.margins);
    }
    let _ = write!(
        t,
        "lock integrity: {}",
        if pass {
            "PASS"
        } else {
            "FAIL (a margin is negative)"
        }
    );
    p.human(&t);
    p.json(&Output {
        scene: args.scene.display().to_string(),
        damping: damping_text(&run.damping, scene.file.damping.is_some(), modes_used),
        pass,
        axes: results,
    })?;
    if let Some(dir) = &args.out {
        write_outputs(dir, results)?;
        p.human(&format!("curves and plots written to {}", dir.display()));
    }
    Ok(if pass {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}

/// Per axis the response, joint and bar curves (CSV) and a plot (SVG); all axes as JSON.
fn write_outputs(dir: &Path, results: &[response::SineAxis]) -> Result<(), Error> {
    for r in results {
        let name = format!("sine-{}", r.axis);
        satqual::report::write_atomic(
            &dir.join(format!("{name}.csv")),
            r.curves.to_csv("input_g").as_bytes(),
        )?;
        satqual::report::write_atomic(
            &dir.join(format!("{name}-interfaces.csv")),
            r.curves.csv_of("input_g", &r.curves.interfaces).as_bytes(),
        )?;
        satqual::report::write_atomic(
            &dir.join(format!("{name}-bars.csv")),
            r.curves.csv_of("input_g", &r.curves.bars).as_bytes(),
        )?;
        let svg = plot(
            &r.curves,
            &format!("Sine, axis {}: absolute acceleration", r.axis),
            "acceleration amplitude [g]",
            "input [g]",
            false,
        );
        satqual::report::write_atomic(&dir.join(format!("{name}.svg")), svg.as_bytes())?;
    }
    satqual::output_check::check_json(results, "sine.json")?;
    let json = serde_json::to_string_pretty(results).map_err(|e| Error::Other(e.to_string()))?;
    satqual::report::write_atomic(&dir.join("sine.json"), json.as_bytes())?;
    Ok(())
}

/// The worst margin of each kind.
pub fn summarize_margins(t: &mut String, ms: &[Verdict]) {
    let mut kinds: Vec<&str> = ms.iter().map(|m| m.kind.as_str()).collect();
    kinds.dedup();
    kinds.sort();
    kinds.dedup();
    for k in kinds {
        if let Some(m) = ms
            .iter()
            .filter(|m| m.kind == k)
            .min_by(|a, b| a.margin.total_cmp(&b.margin))
        {
            let _ = writeln!(
                t,
                "  min MS {:<12} {:>+9.2} ({}: {:.4e} vs allowable {:.4e}) {}",
                k,
                m.margin,
                m.name,
                m.value,
                m.limit,
                if m.pass { "pass" } else { "FAIL" }
            );
        }
    }
}

/// The response-point curves of an analysis, with the input dashed.
pub fn plot(
    c: &response::Curves,
    title: &str,
    y_label: &str,
    input_name: &str,
    log_y: bool,
) -> String {
    use satqual::report::svg_plot::{Plot, Series, render};
    let mut series = vec![Series {
        name: input_name,
        x: &c.frequency_hz,
        y: &c.input,
        dashed: true,
    }];
    for (n, v) in c
        .series
        .iter()
        .filter(|(n, _)| n.ends_with("[g]") || n.ends_with("[g2/Hz]"))
        .take(7)
    {
        series.push(Series {
            name: n,
            x: &c.frequency_hz,
            y: v,
            dashed: false,
        });
    }
    render(
        &Plot {
            title,
            x_label: "frequency [Hz]",
            y_label,
            log_x: true,
            log_y,
        },
        &series,
    )
}
