//! `satqual psd LOG`: Welch PSD per channel (or a UFF58 PSD read as is), Grms/RMS, peaks,
//! optional tolerance bands against a reference profile; `--out DIR` writes CSV curves and a
//! log-log SVG plot with the Grms in the legend.

use super::log_args::{LogArgs, WelchArgs, print_ingest_notes, print_notes};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{
    self,
    psd::{PsdRequest, PsdRun, ToleranceCheck, is_constant},
};
use satqual::report::plot::{Series, loglog_svg};
use satqual::report::write_atomic;

use satqual::error::SignalError;
use satqual::signal::welch::{
    MIN_DEFAULT_AVERAGES, MIN_NPERSEG, averages_note, resolution_note, short_log_nperseg,
};
use satqual::signal::{PsdSource, ToleranceSpec, WelchOptions, read_profile};
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Log file: CSV or text with a header (and a time column or --fs), UFF58/58b (time histories or PSDs), LabVIEW .lvm, MATLAB .mat (v5), TDMS, WAV, Tektronix or Rigol CSV.
    pub log: PathBuf,
    /// Channels to process, comma-separated (default: every non-time column).
    #[arg(long, value_delimiter = ',')]
    pub channels: Option<Vec<String>>,
    /// Reference profile (TOML `profile_g2_hz = [[f, g2], ...]` or CSV f_hz,g2_hz): tolerance bands.
    #[arg(long)]
    pub profile: Option<PathBuf>,
    /// Channel checked against the profile (default: the first).
    #[arg(long, requires = "profile")]
    pub control: Option<String>,
    #[arg(long, default_value_t = 3.0)]
    pub alarm_db: f64,
    #[arg(long, default_value_t = 6.0)]
    pub abort_db: f64,
    #[arg(long, default_value_t = 10.0)]
    pub grms_pct: f64,
    /// Peaks reported per channel.
    #[arg(long, default_value_t = 5)]
    pub peaks: usize,
    /// Write CSV curves and SVG plots here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub reading: LogArgs,
    #[command(flatten)]
    pub welch: WelchArgs,
}

fn csv_number(v: f64) -> String {
    format!("{v:.9e}")
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let ingest = args.reading.ingest(args.channels.clone())?;
    let wopts = args.welch.options()?;
    let tolerance = match &args.profile {
        Some(path) => Some(ToleranceCheck {
            control: args.control.clone(),
            profile: read_profile(path)?,
            spec: ToleranceSpec {
                alarm_db: args.alarm_db,
                abort_db: args.abort_db,
                grms_pct: args.grms_pct,
            },
        }),
        None => None,
    };
    let profile_band = tolerance.as_ref().map(|t| profile_span(&t.profile));
    let mut req = PsdRequest {
        log: &args.log,
        ingest,
        welch: wopts,
        peaks: Some(args.peaks),
        tolerance,
    };
    let run = match workflows::psd::run(&req) {
        // The default segment is for long random tests; a short log gets a shorter one.
        Err(Error::Signal(SignalError::SegmentTooLong { len, .. }))
            if args.welch.nperseg.is_none() && len >= MIN_NPERSEG =>
        {
            req.welch.nperseg = short_log_nperseg(len);
            print_notes(&[format!(
                "psd: the log has {len} samples, fewer than the default segment: nperseg {} (--nperseg to choose)",
                req.welch.nperseg
            )]);
            workflows::psd::run(&req)?
        }
        r => r?,
    };
    // A log only a few default segments long would be one raw periodogram or little more:
    // shorten the default segment as for a short log.
    let samples = run.first().samples as usize;
    let run = if args.welch.nperseg.is_none()
        && !run.psd.source.is_read_spectrum()
        && run.first().psd.segments < MIN_DEFAULT_AVERAGES
        && short_log_nperseg(samples) < req.welch.nperseg
    {
        print_notes(&[format!(
            "psd: the default segment of {} samples leaves {} average(s) of this {samples}-sample log: nperseg {} (--nperseg to choose)",
            req.welch.nperseg,
            run.first().psd.segments,
            short_log_nperseg(samples)
        )]);
        req.welch.nperseg = short_log_nperseg(samples);
        workflows::psd::run(&req)?
    } else {
        run
    };
    let wopts = req.welch;
    print_ingest_notes(run.psd.info.as_ref());
    print_notes(&run.psd.notes);
    let warnings = resolution_warnings(&run, &wopts, profile_band);
    super::log_args::print_warnings(&warnings);
    let mut human = summary(&args, &run, &wopts);
    let pass = run.tolerance.as_ref().is_none_or(|(_, t)| t.pass);
    if let Some(dir) = &args.out {
        write_outputs(dir, &run.psd)?;
        human.push(format!(
            "  wrote {}/psd.csv, third_octave.csv, psd.svg",
            dir.display()
        ));
    }
    p.human(&human.join("\n"));
    let grms: Vec<(f64, Option<f64>)> = run.psd.channels.iter().map(|c| (c.grms, c.rms)).collect();
    let df = run.first().psd.df;
    let sources = (run.psd.fs_hz, df, &grms, &run.peaks, &run.tolerance);
    let what = format!("psd JSON output of {}", args.log.display());
    satqual::output_check::check_sources(&sources, &what)?;
    let mut doc = document(&args, &run, &wopts, pass);
    let file_warnings = run.psd.info.as_ref().map(|i| i.ingest.warnings.clone());
    doc["warnings"] = json!([file_warnings.unwrap_or_default(), warnings].concat());
    p.json(&doc)?;
    Ok(if pass {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}

/// A warning when the segment is too short to resolve the band asked: the reference
/// profile's span when one is given, else DC to Nyquist.
fn resolution_warnings(
    run: &PsdRun,
    wopts: &WelchOptions,
    profile_band: Option<(f64, f64)>,
) -> Vec<String> {
    if run.psd.source.is_read_spectrum() {
        return Vec::new();
    }
    let fs = run.psd.fs_hz;
    let (lo, hi) = profile_band.unwrap_or((0.0, fs / 2.0));
    let first = run.first();
    resolution_note(fs, wopts.nperseg, lo, hi.min(fs / 2.0))
        .into_iter()
        .chain(averages_note(
            first.psd.segments,
            first.samples as usize,
            wopts.nperseg,
        ))
        .chain(run.psd.channels.iter().filter(|c| is_constant(c)).map(|c| {
            format!(
                "channel `{}` is constant (its fluctuation, {:.3e}, is round-off of its RMS {:.6}): no peaks",
                c.name,
                c.grms,
                c.rms.unwrap_or(0.0)
            )
        }))
        .collect()
}

/// The peaks' frequencies, or why there are none to list.
fn peak_list(peaks: &[satqual::signal::peaks::Peak]) -> String {
    if peaks.is_empty() {
        return "none (no local maximum with 6 dB prominence within 100 dB of the highest line)"
            .into();
    }
    peaks
        .iter()
        .map(|p| format!("{:.2} Hz", p.frequency_hz))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Lowest and highest frequency of a profile's breakpoints.
fn profile_span(profile: &[(f64, f64)]) -> (f64, f64) {
    profile
        .iter()
        .fold((f64::INFINITY, 0.0), |(lo, hi), &(f, _)| {
            (lo.min(f), hi.max(f))
        })
}

/// The human summary: the log, one line per channel, resampling and tolerance.
fn summary(args: &Args, run: &PsdRun, wopts: &WelchOptions) -> Vec<String> {
    let (res, first) = (&run.psd, run.first());
    let mut human = vec![format!(
        "{}: {} channel(s), fs {:.6} Hz, {}",
        args.log.display(),
        res.channels.len(),
        res.fs_hz,
        match res.source {
            PsdSource::UffPsd => "PSD read from UFF58".to_string(),
            PsdSource::TablePsd => format!(
                "PSD read from a table ({} Hz lines)",
                satqual::signal::welch::round_to_micro(first.psd.df)
            ),
            _ => format!(
                "Welch nperseg {} ({} Hz lines), {} window, {} segments",
                wopts.nperseg,
                satqual::signal::welch::round_to_micro(first.psd.df),
                wopts.window.name(),
                first.psd.segments
            ),
        }
    )];
    for (c, peaks) in res.channels.iter().zip(&run.peaks) {
        human.push(format!(
            "  {:<20} {} {:.6} {}  RMS {}  peaks: {}",
            c.name,
            band_rms_name(&c.unit),
            c.grms,
            c.unit,
            c.rms.map_or("-".into(), |r| format!("{r:.6}")),
            peak_list(peaks)
        ));
    }
    if let Some(r) = res.info.as_ref().and_then(|i| i.resampled.as_ref()) {
        let irregular = match r.irregular_rows {
            0 => "uniform steps".to_string(),
            n => format!(
                "{n} irregular step(s) from line {} (largest {:.6e} s)",
                r.first_irregular_line, r.largest_step_s
            ),
        };
        human.push(format!(
            "  resampled: {irregular} -> uniform dt {:.6e} s, {} samples from {} rows{}",
            r.uniform_dt_s,
            r.output_samples,
            r.input_rows,
            if r.anti_alias.is_some() {
                " (anti-aliased)"
            } else {
                ""
            }
        ));
    }
    if let Some((name, t)) = &run.tolerance {
        human.push(format!(
            "  tolerance ({name}): {:?}; {:.2}% of {} lines outside ±{} dB, {:.2}% outside ±{} dB; worst {:+.2} dB at {:.1} Hz; Grms {:.4} vs {:.4} ({:+.2}%)",
            t.status,
            100.0 * t.fraction_outside_alarm,
            t.lines_checked,
            t.spec.alarm_db,
            100.0 * t.fraction_outside_abort,
            t.spec.abort_db,
            t.worst_excursion_db,
            t.worst_frequency_hz,
            t.measured_grms,
            t.reference_grms,
            t.grms_error_pct
        ));
    }
    human
}

/// The `--json` document.
fn document(args: &Args, run: &PsdRun, wopts: &WelchOptions, pass: bool) -> serde_json::Value {
    let (res, first) = (&run.psd, run.first());
    let channels: Vec<_> = res
        .channels
        .iter()
        .zip(&run.peaks)
        .map(|(c, peaks)| json!({
            "name": c.name,
            "unit": c.unit,
            "grms": c.grms,
            "rms": c.rms,
            "samples": c.samples,
            "peaks": peaks.iter().map(|p| json!({"frequency_hz": p.frequency_hz, "value": p.value, "prominence_db": p.prominence_db})).collect::<Vec<_>>(),
        }))
        .collect();
    let info = res.info.as_ref();
    let welch = !res.source.is_read_spectrum();
    json!({
        "file": args.log,
        "source": res.source,
        "fs_hz": res.fs_hz,
        "nperseg": first.psd.nperseg,
        "overlap": welch.then_some(wopts.overlap),
        "window": welch.then(|| wopts.window.name()),
        "detrend": welch.then(|| wopts.detrend.name()),
        "frequency_resolution_hz": first.psd.df,
        "segments": first.psd.segments,
        "time_column": info.and_then(|i| i.time_column.clone()),
        "resampled": info.and_then(|i| i.resampled.clone()),
        "ingest": info.map(|i| &i.ingest),
        "channels": channels,
        "tolerance": run.tolerance.as_ref().map(|(n, t)| json!({"channel": n, "report": t})),
        "pass": pass,
    })
}

fn write_outputs(dir: &std::path::Path, res: &satqual::signal::LogPsd) -> Result<(), Error> {
    let Some(first) = res.channels.first() else {
        return Ok(());
    };
    let f = first.psd.frequencies();
    let mut csv = String::from("frequency_hz");
    for c in &res.channels {
        csv.push_str(&format!(",{} [{}^2/Hz]", c.name, c.unit));
    }
    csv.push('\n');
    for (k, fk) in f.iter().enumerate() {
        csv.push_str(&csv_number(*fk));
        for c in &res.channels {
            csv.push(',');
            csv.push_str(&csv_number(
                c.psd.values.get(k).copied().unwrap_or(f64::NAN),
            ));
        }
        csv.push('\n');
    }
    write_atomic(&dir.join("psd.csv"), csv.as_bytes())?;
    let mut bands = String::from("channel,center_hz,lower_hz,upper_hz,rms\n");
    for (channel, b) in satqual::pipeline::workflows::psd::third_octave_bands(res) {
        bands.push_str(&format!(
            "{},{:.6},{:.6},{:.6},{}\n",
            channel,
            b.center_hz,
            b.lower_hz,
            b.upper_hz,
            csv_number(b.rms)
        ));
    }
    write_atomic(&dir.join("third_octave.csv"), bands.as_bytes())?;
    let pts: Vec<Vec<(f64, f64)>> = res
        .channels
        .iter()
        .map(|c| {
            f.iter()
                .copied()
                .zip(c.psd.values.iter().copied())
                .collect()
        })
        .collect();
    let series: Vec<Series> = res
        .channels
        .iter()
        .zip(&pts)
        .map(|(c, p)| Series {
            label: format!(
                "{} ({} {:.4} {})",
                c.name,
                band_rms_name(&c.unit),
                c.grms,
                c.unit
            ),
            points: p,
        })
        .collect();
    let first = res.channels.first().map_or("", |c| c.unit.as_str());
    let unit = if res.channels.iter().all(|c| c.unit == first) && first != "as-is" {
        format!("{first}²/Hz")
    } else {
        "unit²/Hz".to_string()
    };
    let svg = loglog_svg("PSD", "frequency [Hz]", &format!("PSD [{unit}]"), &series)?;
    write_atomic(&dir.join("psd.svg"), svg.as_bytes())?;
    Ok(())
}

/// Grms names the band RMS of an acceleration in g; values in any other unit get the plain name.
fn band_rms_name(unit: &str) -> &'static str {
    if unit == "g" { "Grms" } else { "band RMS" }
}
