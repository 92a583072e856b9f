//! Command-line front end. Each subcommand lives in its own file with its clap arguments and a
//! `run` function that calls the library and prints. The `Printer` enforces the contract: with
//! `--json` the machine-readable result goes to stdout and the human summary to stderr.

use clap::{Parser, Subcommand};
use satqual::Error;
use std::io::Write;

mod bench;
mod campaign;
mod correlate;
mod ema;
mod expand;
mod frf;
mod log_args;
mod merge;
mod modal;
mod progress;
mod psd;
mod qualify;
mod random;
mod separate;
mod separate_shock;
mod separate_sweep;
mod signature;
mod sine;
mod srs;
mod sweep;
mod update;

#[derive(Parser, Debug)]
#[command(
    name = "satqual",
    version,
    about = "Qualify a preloaded stack of flat satellites: FE modal and response prediction, test-log post-processing, lock-integrity gates and separation dynamics"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Natural frequencies, effective masses and (with static loads) the buckling factor.
    Modal(modal::Args),
    /// Write a [stack] scene out as the generic model (TOML) on stdout.
    Expand(expand::Args),
    /// In-orbit release: separation dynamics of the stack, optionally a Monte Carlo.
    Separate(separate::Args),
    /// Write the Slurm array script of a sharded Monte Carlo and its merge job.
    Campaign(campaign::Args),
    /// Join the part files of a sharded `separate --monte-carlo` into one result.
    Merge(merge::Args),
    /// Run every analysis the scene asks for, gate the results, write the report.
    Qualify(qualify::Args),
    /// Sine-sweep base-excitation response, joint loads and lock-integrity margins.
    Sine(sine::Args),
    /// Random-vibration base-excitation response (Grms, 3σ), loads and margins.
    Random(random::Args),
    /// Welch PSD of a log (CSV or text, UFF58/58b, .lvm, .mat, TDMS, WAV): Grms, RMS, peaks, tolerance bands against a profile.
    Psd(psd::Args),
    /// Frequency response H1/H2 and coherence between two channels, with resonances and Q.
    Frf(frf::Args),
    /// Experimental modal analysis: modes, damping and shapes from FRFs (LSCF + LSFD, or peaks).
    Ema(ema::Args),
    /// Test-analysis correlation: paired modes, frequency errors, MAC, cross-orthogonality.
    Correlate(correlate::Args),
    /// Model updating: scene parameters fitted to the paired test frequencies.
    Update(update::Args),
    /// Compare the resonances of signatures taken before and after a test.
    Signature(signature::Args),
    /// Sine-sweep tracking: response per unit drive against drive frequency, fn and Q.
    Sweep(sweep::Args),
    /// Shock response spectrum of a shock record, checked against a specification.
    Srs(srs::Args),
    /// Work-precision tables: run time against error, written to reports/bench/.
    Bench(bench::Args),
}

/// How a command that ran to completion ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Pass,
    GateFailed,
}

pub fn run(cli: Cli) -> Result<Outcome, Error> {
    match cli.command {
        Command::Modal(a) => modal::run(a),
        Command::Expand(a) => expand::run(a),
        Command::Separate(a) => separate::run(a),
        Command::Campaign(a) => campaign::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Qualify(a) => qualify::run(a),
        Command::Sine(a) => sine::run(a),
        Command::Random(a) => random::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Psd(a) => psd::run(a),
        Command::Frf(a) => frf::run(a),
        Command::Ema(a) => ema::run(a),
        Command::Correlate(a) => correlate::run(a),
        Command::Update(a) => update::run(a),
        Command::Signature(a) => signature::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Srs(a) => srs::run(a),
    }
}

/// Routes output per the CLI contract.
pub struct Printer {
    pub json: bool,
}

impl Printer {
    pub fn new(json: bool) -> Self {
        Printer { json }
    }

    /// Human-readable text: stdout normally, stderr when `--json` owns stdout.
    pub fn human(&self, text: &str) {
        if self.json {
            let _ = writeln!(std::io::stderr(), "{text}");
        } else {
            let _ = writeln!(std::io::stdout(), "{text}");
        }
    }

    /// The machine-readable result, printed only with `--json`. Its numbers are checked with
    /// or without `--json`: a non-finite result is an error, never a number printed as text.
    pub fn json<T: serde::Serialize>(&self, value: &T) -> Result<(), Error> {
        satqual::output_check::check_json(value, "JSON output")?;
        if self.json {
            let s = serde_json::to_string_pretty(value).map_err(|e| Error::Other(e.to_string()))?;
            let _ = writeln!(std::io::stdout(), "{s}");
        }
        Ok(())
    }
}

/// Whether two paths name one file (the output may not exist yet: compare its folder).
pub(crate) fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    use std::path::{Path, PathBuf};
    let canon = |p: &Path| -> Option<PathBuf> {
        if let Ok(c) = p.canonicalize() {
            return Some(c);
        }
        let dir = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        Some(dir.canonicalize().ok()?.join(p.file_name()?))
    };
    a == b || matches!((canon(a), canon(b)), (Some(x), Some(y)) if x == y)
}
