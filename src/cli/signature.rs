//! `satqual signature BEFORE AFTER --input CH --output CH`: resonances of the FRF of each
//! signature, matched mode by mode; fails (exit 1) when a mode shifts more than
//! `--max-shift-pct` or changes amplitude more than `--max-amp-change-pct`, naming the mode.

use super::log_args::{LogArgs, WelchArgs};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{self, signature::SignatureRequest};
use satqual::signal::{PeakOptions, SignatureCriteria};
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Signature log taken before the test (CSV).
    pub before: PathBuf,
    /// Signature log taken after the test (CSV).
    pub after: PathBuf,
    #[arg(long)]
    pub input: String,
    #[arg(long)]
    pub output: String,
    #[arg(long, default_value_t = 5.0)]
    pub max_shift_pct: f64,
    #[arg(long, default_value_t = 20.0)]
    pub max_amp_change_pct: f64,
    /// Matching window between a mode before and a peak after, percent.
    #[arg(long, default_value_t = 25.0)]
    pub match_window_pct: f64,
    /// Modes compared (the strongest resonances of the before-signature).
    #[arg(long, default_value_t = 10)]
    pub modes: usize,
    #[arg(long, default_value_t = 6.0)]
    pub min_prominence_db: f64,
    /// Band searched for resonances, Hz [default: the band the before-input excites].
    #[arg(long)]
    pub fmin: Option<f64>,
    #[arg(long)]
    pub fmax: Option<f64>,
    #[command(flatten)]
    pub screen: super::frf::ScreenArgs,
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub reading: LogArgs,
    #[command(flatten)]
    pub welch: WelchArgs,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let wopts = args.welch.options()?;
    let peaks = PeakOptions {
        min_prominence_db: args.min_prominence_db,
        max_peaks: args.modes,
        f_min_hz: 0.0,
        f_max_hz: f64::INFINITY,
        db_per_decade: 20.0,
        ..PeakOptions::default()
    };
    let ingest = args.reading.ingest(None)?;
    let run = workflows::signature::run(&SignatureRequest {
        before: &args.before,
        after: &args.after,
        input: &args.input,
        output: &args.output,
        ingest,
        welch: wopts,
        welch_is_default: args.welch.all_default(),
        screen: Some(args.screen.screen(args.fmin, args.fmax)?),
        peaks,
        criteria: SignatureCriteria {
            max_shift_pct: args.max_shift_pct,
            max_amp_change_pct: args.max_amp_change_pct,
            match_window_pct: args.match_window_pct,
        },
    })?;
    let (before, after, rep) = (&run.before, &run.after, &run.report);
    super::frf::print_run_notes(before);
    super::frf::print_run_notes(after);
    let mut human = vec![format!(
        "signature {} -> {}: {} mode(s), {}",
        args.before.display(),
        args.after.display(),
        rep.modes.len(),
        if rep.pass { "PASS" } else { "FAIL" }
    )];
    for m in &rep.modes {
        human.push(format!(
            "  mode {}: {:.2} Hz -> {}  shift {}  amplitude {}  {}",
            m.mode,
            m.before_hz,
            m.after_hz
                .map_or("missing".into(), |f| format!("{f:.2} Hz")),
            m.shift_pct.map_or("-".into(), |s| format!("{s:+.2}%")),
            m.amplitude_change_pct
                .map_or("-".into(), |s| format!("{s:+.2}%")),
            if m.pass {
                "ok".to_string()
            } else {
                format!("FAIL: {}", m.reason)
            }
        ));
    }
    if rep.modes.is_empty() {
        human
            .push("  no resonance found in the before-signature: nothing to compare (FAIL)".into());
    }
    p.human(&human.join("\n"));
    super::frf::check_run_sources(before, "signature JSON output (before)")?;
    super::frf::check_run_sources(after, "signature JSON output (after)")?;
    satqual::output_check::check_sources(&rep, "signature JSON output")?;
    p.json(&json!({
        "before": args.before,
        "after": args.after,
        "input": args.input,
        "output": args.output,
        "fs_hz": before.frf.fs,
        "frequency_resolution_hz": before.frf.df,
        "criteria": rep.criteria,
        "modes": rep.modes,
        "new_after_hz": rep.new_after_hz,
        "failures": rep.failures,
        "before_peaks": before.resonances.iter().map(super::frf::peak_json).collect::<Vec<_>>(),
        "after_peaks": after.resonances.iter().map(super::frf::peak_json).collect::<Vec<_>>(),
        "before_run": super::frf::run_json(before),
        "after_run": super::frf::run_json(after),
        "pass": rep.pass,
    }))?;
    Ok(if rep.pass {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}
