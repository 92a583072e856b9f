//! `satqual srs LOG`: shock response spectrum per channel (maximax, positive, negative, primary,
//! residual, pseudo-velocity), peak acceleration and its time, and an optional tolerance check
//! against a shock specification; `--out DIR` writes the spectra as CSV and a log-log SVG plot.
//! The analysis is `satqual::signal::srs_of_file`; this file parses, prints and writes.

use super::log_args::LogArgs;
use super::{Outcome, Printer};
use satqual::Error;
use satqual::report::plot::{Series, loglog_svg};
use satqual::report::write_atomic;
use satqual::signal::srs::{SpecCheck, SpecTolerance, check_against_spec};
use satqual::signal::welch::round_to_micro;
use satqual::signal::{LogSrs, Offset, SrsOptions, read_profile, srs_of_file};
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Shock record: CSV or text with a header (and a time column or --fs), UFF58/58b time histories, LabVIEW .lvm, MATLAB .mat (v5), TDMS, WAV, Tektronix or Rigol CSV.
    pub log: PathBuf,
    /// Channels to process, comma-separated (default: every non-time column).
    #[arg(long, value_delimiter = ',')]
    pub channels: Option<Vec<String>>,
    /// Quality factor of the oscillators (damping ratio 1/(2Q)).
    #[arg(long, default_value_t = 10.0)]
    pub q: f64,
    #[arg(long, default_value_t = 10.0)]
    pub fmin: f64,
    /// Highest natural frequency, Hz (default: fs/10, at most 10 kHz).
    #[arg(long)]
    pub fmax: Option<f64>,
    /// Natural frequencies per octave (6 or 12 in the test standards).
    #[arg(long, default_value_t = 12)]
    pub per_octave: u32,
    /// Offset removed first: none, mean or pre-shock.
    #[arg(long, default_value = "mean")]
    pub offset: String,
    /// Shock specification: TOML `points = [[f_hz, level], ...]` or CSV `f_hz,level` (log-log).
    #[arg(long)]
    pub spec: Option<PathBuf>,
    /// Upper tolerance above the specification, dB.
    #[arg(long, default_value_t = 6.0)]
    pub upper_db: f64,
    /// Lower tolerance below the specification, dB.
    #[arg(long, default_value_t = 6.0)]
    pub lower_db: f64,
    /// Share of checked points allowed outside each limit.
    #[arg(long, default_value_t = 0.0)]
    pub allowed_fraction: f64,
    /// Write srs.csv and srs.svg here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub reading: LogArgs,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let ingest = args.reading.ingest(args.channels.clone())?;
    let opts = SrsOptions {
        q: args.q,
        fmin_hz: args.fmin,
        fmax_hz: args.fmax.unwrap_or(f64::INFINITY),
        per_octave: args.per_octave,
        offset: Offset::parse(&args.offset)?,
    };
    let res = srs_of_file(&args.log, &ingest, &opts)?;
    if let Some(record) = &res.ingest {
        super::log_args::print_notes(&record.notes);
        super::log_args::print_warnings(&record.warnings);
    }
    super::log_args::print_notes(&res.notes);
    if args.fmax.is_none() {
        super::log_args::print_notes(&[format!(
            "srs: natural frequencies up to {} Hz (default fs/10, at most 10 kHz; --fmax to change)",
            round_to_micro(res.options.fmax_hz)
        )]);
    }
    let checks = match &args.spec {
        Some(path) => spec_checks(path, &res, &args)?,
        None => Vec::new(),
    };
    let pass = checks.iter().all(|(_, c)| c.pass);
    let mut human = summary(&res);
    for (name, c) in &checks {
        human.push(format!(
            "  spec ({name}): {}; {:.1}% of {} points above +{} dB, {:.1}% below -{} dB; worst {:+.2} dB at {:.1} Hz",
            if c.pass { "pass" } else { "FAIL" },
            100.0 * c.fraction_above_upper,
            c.points.len(),
            c.tolerance.upper_db,
            100.0 * c.fraction_below_lower,
            c.tolerance.lower_db,
            c.worst_db,
            c.worst_hz
        ));
    }
    if let Some(dir) = &args.out {
        write_outputs(dir, &res)?;
        human.push(format!("  wrote {}/srs.csv, srs.svg", dir.display()));
    }
    p.human(&human.join("\n"));
    let what = format!("srs JSON output of {}", args.log.display());
    satqual::output_check::check_sources(&(&res, &checks), &what)?;
    p.json(&json!({
        "file": res.file,
        "fs_hz": res.fs_hz,
        "options": res.options,
        "residual_samples": res.residual_samples,
        "channels": res.channels,
        "ingest": res.ingest,
        "spec": checks.iter().map(|(n, c)| json!({"channel": n, "check": c})).collect::<Vec<_>>(),
        "pass": pass,
    }))?;
    Ok(if pass {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}

fn spec_checks(path: &Path, res: &LogSrs, args: &Args) -> Result<Vec<(String, SpecCheck)>, Error> {
    let spec = read_profile(path)?;
    let tol = SpecTolerance {
        upper_db: args.upper_db,
        lower_db: args.lower_db,
        allowed_fraction: args.allowed_fraction,
    };
    Ok(res
        .channels
        .iter()
        .map(|c| (c.name.clone(), check_against_spec(&c.srs, &spec, tol)))
        .collect())
}

fn summary(res: &LogSrs) -> Vec<String> {
    let o = &res.options;
    let mut lines = vec![format!(
        "{}: {} channel(s), fs {:.6} Hz, Q {}, {} to {} Hz at 1/{} octave, offset {:?}, residual {} zero samples",
        res.file.display(),
        res.channels.len(),
        res.fs_hz,
        o.q,
        round_to_micro(o.fmin_hz),
        round_to_micro(o.fmax_hz),
        o.per_octave,
        o.offset,
        res.residual_samples
    )];
    for c in &res.channels {
        let top = c
            .srs
            .iter()
            .fold(None, |b: Option<&satqual::signal::SrsPoint>, p| match b {
                Some(b) if b.maximax >= p.maximax => Some(b),
                _ => Some(p),
            });
        lines.push(format!(
            "  {:<20} peak {:.6} {} at {:.6e} s; SRS max {}",
            c.name,
            c.peak,
            c.unit,
            c.peak_time_s,
            top.map_or("-".into(), |t| format!(
                "{:.6} {} at {:.2} Hz",
                t.maximax, c.unit, t.frequency_hz
            ))
        ));
    }
    lines
}

fn write_outputs(dir: &Path, res: &LogSrs) -> Result<(), Error> {
    let mut csv = String::from(
        "channel,frequency_hz,maximax,positive,negative,primary,residual,pseudo_velocity\n",
    );
    for c in &res.channels {
        for s in &c.srs {
            csv.push_str(&format!(
                "{},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
                c.name,
                s.frequency_hz,
                s.maximax,
                s.positive,
                s.negative,
                s.primary,
                s.residual,
                s.pseudo_velocity
            ));
        }
    }
    write_atomic(&dir.join("srs.csv"), csv.as_bytes())?;
    let pts: Vec<Vec<(f64, f64)>> = res
        .channels
        .iter()
        .map(|c| c.srs.iter().map(|s| (s.frequency_hz, s.maximax)).collect())
        .collect();
    let series: Vec<Series> = res
        .channels
        .iter()
        .zip(&pts)
        .map(|(c, p)| Series {
            label: format!("{} (peak {:.4} {})", c.name, c.peak, c.unit),
            points: p,
        })
        .collect();
    let unit = res.channels.first().map_or("g", |c| c.unit.as_str());
    let title = format!("SRS maximax, Q = {}", res.options.q);
    let svg = loglog_svg(
        &title,
        "natural frequency [Hz]",
        &format!("SRS [{unit}]"),
        &series,
    )?;
    write_atomic(&dir.join("srs.svg"), svg.as_bytes())?;
    Ok(())
}
