//! `satqual bench WHAT`: work-precision tables (run time against error), written as JSON and
//! Markdown to `reports/bench/`. Timings are measured here, never asserted in tests.

use super::Outcome;
use satqual::Error;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Which table: fem, modal, response, psd, separation.
    pub what: String,
    /// Output folder.
    #[arg(long, default_value = "reports/bench")]
    pub out: PathBuf,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    match args.what.as_str() {
        "fem" => super::bench_fem::run(&args.out).map(|_| Outcome::Pass),
        "modal" => super::bench_modal::run(&args.out).map(|_| Outcome::Pass),
        "separation" => super::bench_separation::run(&args.out),
        "response" => super::bench_response::run(&args.out).map(|_| Outcome::Pass),
        "psd" => super::bench_psd::run(&args.out),
        other => Err(Error::Other(format!("unknown benchmark `{other}`"))),
    }
}
