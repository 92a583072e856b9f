//! `satqual bench WHAT`: work-precision tables (run time against error), written as JSON and
//! Markdown by the library's `bench` module to the folder given with `--out`. The tracked
//! tables in `reports/bench/` are regenerated only with `--update-tracked`, so that a trial
//! run never rewrites the repository's measured figures by accident. With `--json` the
//! table's JSON also goes to stdout (and the Markdown to stderr).

use super::progress::Progress;
use super::{Outcome, Printer};
use satqual::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The tracked tables, relative to the repository root.
const TRACKED: &str = "reports/bench";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Which table: fem, modal, response, psd, separation, ema, update.
    pub what: String,
    /// Output folder (required unless --update-tracked).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Regenerate the tracked tables in reports/bench/.
    #[arg(long)]
    pub update_tracked: bool,
    /// Print the machine-readable result on stdout (the table goes to stderr).
    #[arg(long)]
    pub json: bool,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
}

/// Where the tables go: `--out`, or the tracked folder with `--update-tracked`; `--out`
/// naming the tracked folder needs the flag too.
fn destination(args: &Args) -> Result<PathBuf, Error> {
    let tracked = |p: &Path| {
        let abs = |q: &Path| std::fs::canonicalize(q).unwrap_or_else(|_| q.to_path_buf());
        abs(p) == abs(Path::new(TRACKED))
    };
    match (&args.out, args.update_tracked) {
        (Some(out), false) if tracked(out) => Err(Error::Other(format!(
            "bench: --out {} is the tracked folder; add --update-tracked to regenerate it",
            out.display()
        ))),
        (Some(out), _) => Ok(out.clone()),
        (None, true) => Ok(PathBuf::from(TRACKED)),
        (None, false) => Err(Error::Other(format!(
            "bench: say where to write the tables: --out DIR, or --update-tracked for {TRACKED}/"
        ))),
    }
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let out = destination(&args)?;
    let progress = Progress::start(args.quiet, args.json, &format!("bench {}", args.what));
    let table = satqual::bench::run(&args.what, &out);
    progress.finish();
    let table = table?;
    let printer = Printer::new(args.json);
    printer.human(&table.markdown);
    printer.human(&format!(
        "wrote {}",
        out.join(format!("{}.{{json,md}}", table.name)).display()
    ));
    if args.json {
        // Printed as written to the file: the bench JSON keeps its own field order.
        let _ = writeln!(std::io::stdout(), "{}", table.json);
    }
    Ok(Outcome::Pass)
}
