//! `satqual qualify`: runs every analysis the scene asks for, gates the results, and writes
//! the report folder (HTML, Markdown, results.json, curves). Exit 0 when every gate passes,
//! 1 when one fails (the report is still written), 2 on bad input or a failed run.

use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::Progress;
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

/// Progress on stderr through an indicatif spinner, which draws only when stderr is a
/// terminal and the stage takes long enough to be worth it.
struct Spinner {
    bar: Option<indicatif::ProgressBar>,
}

impl Progress for Spinner {
    fn stage(&self, name: &str) {
        if let Some(b) = &self.bar {
            b.set_message(name.to_string());
        }
    }
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let bar = if args.quiet {
        None
    } else {
        let b = indicatif::ProgressBar::new_spinner();
        b.enable_steady_tick(std::time::Duration::from_millis(200));
        Some(b)
    };
    let spinner = Spinner { bar };
    let q = satqual::pipeline::qualify(&scene, &spinner);
    if let Some(b) = &spinner.bar {
        b.finish_and_clear();
    }
    let q = q?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("reports").join(scene.name()));
    satqual::report::qualify::write(&out, &q)?;
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
        for g in q.gates.iter().filter(|g| !g.pass) {
            let _ = writeln!(
                t,
                "  FAILED {}: value {:.4}, limit {:.4}, margin {:+.1}%",
                g.name,
                g.value,
                g.limit,
                g.margin * 100.0
            );
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
