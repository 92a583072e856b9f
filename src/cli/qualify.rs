//! `satqual qualify`: runs every analysis the scene asks for, gates the results, and writes
//! the report folder (HTML, Markdown, results.json, curves). Exit 0 when every gate passes,
//! 1 when one fails (the report is still written), 2 on bad input or a failed run.

use super::progress::Progress;
use super::{Outcome, Printer};
use satqual::Error;
use satqual::gates::{Group, Verdict};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Report folder (default: reports/<scene name>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print results.json to stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress or summary on stderr.
    #[arg(long)]
    pub quiet: bool,
}

/// A gate's name, value and limit with their unit (as the report writes them), and margin,
/// on one line.
fn gate_line(g: &Verdict) -> String {
    use satqual::report::format::quantity;
    format!(
        "{}: value {}, limit {}, margin {}",
        g.name,
        quantity(g.value, &g.unit),
        quantity(g.limit, &g.unit),
        satqual::gates::summary::margin_text(g)
    )
}

/// In family `group`, the worst failed gate of every kind other than the governing one's
/// (slip when gapping governs, say), so that no failing kind of check goes unnamed.
fn worst_failed_per_kind<'a>(
    gates: &'a [Verdict],
    group: Option<Group>,
    governing_kind: &str,
) -> Vec<&'a Verdict> {
    let mut worst: Vec<&Verdict> = Vec::new();
    let failed = gates.iter().filter(|g| g.group == group && !g.pass);
    for g in failed.filter(|g| !g.kind.is_empty() && g.kind != governing_kind) {
        match worst.iter_mut().find(|w| w.kind == g.kind) {
            Some(w) if g.margin < w.margin => *w = g,
            Some(_) => {}
            None => worst.push(g),
        }
    }
    worst
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let progress = Progress::start(args.quiet, args.json, "qualify");
    let q = satqual::pipeline::qualify(&scene, &progress);
    progress.finish();
    let q = q?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("reports").join(scene.name()));
    satqual::report::qualify::write(&out, &q)?;
    for (_, w) in q.warnings() {
        eprintln!("warning: {}: {w}", args.scene.display());
    }
    let p = Printer::new(args.json);
    if !args.quiet || args.json {
        let mut t = String::new();
        let nfail = q.gates.iter().filter(|g| !g.pass).count();
        let _ = writeln!(
            t,
            "{}: {} ({} gates, {} failed)",
            scene.name(),
            if q.pass { "PASS" } else { "FAIL" },
            q.gates.len(),
            nfail
        );
        for f in satqual::gates::summary::families(&q.gates) {
            let verdict = if f.failed == 0 { "pass" } else { "FAIL" };
            let family = f.group.map_or("other", |g| g.label());
            let _ = writeln!(
                t,
                "  {family}: {verdict} ({} of {} failed); governing {}",
                f.failed,
                f.total,
                gate_line(f.governing)
            );
            for g in worst_failed_per_kind(&q.gates, f.group, &f.governing.kind) {
                let _ = writeln!(t, "    also failed: {}", gate_line(g));
            }
        }
        for s in &q.skipped {
            let _ = writeln!(t, "  skipped {}: {}", s.analysis, s.reason);
        }
        let _ = write!(t, "report: {}", out.join("report.html").display());
        if !args.quiet {
            p.human(&t);
        }
    }
    p.json(&q)?;
    Ok(if q.pass {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}
