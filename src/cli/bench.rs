//! `satqual bench WHAT`: work-precision tables (run time against error), written as JSON and
//! Markdown to `reports/bench/` by the library's `bench` module. With `--json` the table's
//! JSON also goes to stdout (and the Markdown to stderr).

use super::{Outcome, Printer};
use satqual::Error;
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Which table: fem, modal, response, psd, separation, ema.
    pub what: String,
    /// Output folder.
    #[arg(long, default_value = "reports/bench")]
    pub out: PathBuf,
    /// Print the machine-readable result on stdout (the table goes to stderr).
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let table = satqual::bench::run(&args.what, &args.out)?;
    let printer = Printer::new(args.json);
    printer.human(&table.markdown);
    printer.human(&format!(
        "wrote {}",
        args.out
            .join(format!("{}.{{json,md}}", table.name))
            .display()
    ));
    if args.json {
        // Printed as written to the file: the bench JSON keeps its own field order.
        let _ = writeln!(std::io::stdout(), "{}", table.json);
    }
    Ok(Outcome::Pass)
}
