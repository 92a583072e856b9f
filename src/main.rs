//! The `satqual` binary: parse argv (clap), call the library, print, and map the outcome to an
//! exit code. 0 = done and every gate passes; 1 = done but a gate failed; 2 = bad input or a
//! failed run. Only this binary prints or exits; the library returns values and errors.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    let args = <cli::Cli as clap::Parser>::parse();
    match cli::run(args) {
        Ok(cli::Outcome::Pass) => ExitCode::from(0),
        Ok(cli::Outcome::GateFailed) => ExitCode::from(1),
        Err(e) => {
            eprintln!("satqual: error: {e}");
            ExitCode::from(2)
        }
    }
}
