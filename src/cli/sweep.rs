//! `satqual sweep LOG --control CH`: sine-sweep tracking. Each response channel's amplitude and
//! phase per unit control, against the instantaneous drive frequency, and its dominant
//! resonance (fn, half-power Q). `--out DIR` writes sweep.csv and a log-log plot of |H|.

use super::log_args::LogArgs;
use super::progress::Progress;
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{
    self,
    sweep::{SweepRequest, SweepRun},
};
use satqual::report::plot::{Series, loglog_svg};
use satqual::report::write_atomic;
use satqual::signal::SweepOptions;
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Sweep log (CSV) holding the control (drive) channel and the responses.
    pub log: PathBuf,
    /// Control (drive) channel: its phase is the tracking reference.
    #[arg(long)]
    pub control: String,
    /// Response channels, comma-separated (default: every other channel).
    #[arg(long, value_delimiter = ',')]
    pub responses: Option<Vec<String>>,
    /// Demodulation block, s.
    #[arg(long, default_value_t = 0.25)]
    pub block_s: f64,
    /// Step between blocks, s.
    #[arg(long, default_value_t = 0.02)]
    pub hop_s: f64,
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
    #[command(flatten)]
    pub reading: LogArgs,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let ingest = args.reading.ingest(None)?;
    let progress = Progress::start(args.quiet, args.json, "sweep tracking");
    let run = workflows::sweep::run(&SweepRequest {
        log: &args.log,
        control: &args.control,
        responses: args.responses.clone(),
        ingest,
        options: SweepOptions {
            block_s: args.block_s,
            hop_s: args.hop_s,
            ..Default::default()
        },
    })?;
    progress.finish();
    super::log_args::print_notes(&run.ingest.notes);
    let (track, names) = (&run.track, &run.responses);
    let mut human = vec![format!(
        "{}: sweep tracked on `{}`, {} blocks, {:.2}–{:.2} Hz",
        args.log.display(),
        args.control,
        track.frequency_hz.len(),
        track.frequency_hz.first().copied().unwrap_or(f64::NAN),
        track.frequency_hz.last().copied().unwrap_or(f64::NAN)
    )];
    let sources = (run.fs_hz, track, &run.resonances);
    let what = format!("sweep JSON output of {}", args.log.display());
    satqual::output_check::check_sources(&sources, &what)?;
    let mut out = Vec::new();
    for (name, res) in names.iter().zip(&run.resonances) {
        match res {
            Some(x) => human.push(format!(
                "  {name}: fn {:.3} Hz  |H| {:.6e}  Q {}  phase {:.1}°  sine fraction {:.4}",
                x.frequency_hz,
                x.magnitude,
                x.q.map_or("-".into(), |q| format!("{q:.2}")),
                x.phase_deg,
                x.coherence
            )),
            None => human.push(format!("  {name}: no resonance inside the tracked band")),
        }
        out.push(json!({
            "name": name,
            "resonance": res.as_ref().map(|x| json!({
                "frequency_hz": x.frequency_hz, "magnitude": x.magnitude, "q": x.q,
                "phase_deg": x.phase_deg, "sine_fraction": x.coherence,
            })),
        }));
    }
    human.extend(run.notes.iter().map(|n| format!("  note: {n}")));
    if let Some(dir) = &args.out {
        write_outputs(dir, &run, &args.control)?;
        human.push(format!("  wrote {}/sweep.csv, sweep.svg", dir.display()));
    }
    p.human(&human.join("\n"));
    p.json(&json!({
        "file": args.log,
        "control": args.control,
        "fs_hz": run.fs_hz,
        "block_s": args.block_s,
        "hop_s": args.hop_s,
        "blocks": track.frequency_hz.len(),
        "frequency_min_hz": track.frequency_hz.first(),
        "frequency_max_hz": track.frequency_hz.last(),
        "responses": out,
        "ingest": run.ingest,
        "notes": run.notes,
    }))?;
    Ok(Outcome::Pass)
}

/// sweep.csv (per block: time, drive frequency and amplitude, then per response |H|, phase
/// and sine fraction) and sweep.svg (|H| against drive frequency, log-log).
fn write_outputs(dir: &Path, run: &SweepRun, control: &str) -> Result<(), Error> {
    let (track, names) = (&run.track, &run.responses);
    let mut csv = String::from("time_s,frequency_hz,drive_amplitude");
    for n in names {
        csv.push_str(&format!(",{n}_mag,{n}_phase_deg,{n}_sine_fraction"));
    }
    csv.push('\n');
    for k in 0..track.frequency_hz.len() {
        csv.push_str(&format!(
            "{:.6},{:.6},{:.9e}",
            track.time_s[k], track.frequency_hz[k], track.drive_amplitude[k]
        ));
        for r in 0..names.len() {
            let h = track.h[r][k];
            csv.push_str(&format!(
                ",{:.9e},{:.4},{:.6}",
                h.norm(),
                h.arg().to_degrees(),
                track.sine_fraction[r][k]
            ));
        }
        csv.push('\n');
    }
    write_atomic(&dir.join("sweep.csv"), csv.as_bytes())?;
    let pts: Vec<Vec<(f64, f64)>> = track
        .h
        .iter()
        .map(|h| {
            track
                .frequency_hz
                .iter()
                .zip(h)
                .map(|(f, z)| (*f, z.norm()))
                .collect()
        })
        .collect();
    let series: Vec<Series> = names
        .iter()
        .zip(&pts)
        .map(|(n, p)| Series {
            label: format!("|{n}/{}|", control),
            points: p,
        })
        .collect();
    let svg = loglog_svg("sweep response", "drive frequency [Hz]", "|H|", &series)?;
    write_atomic(&dir.join("sweep.svg"), svg.as_bytes())?;
    Ok(())
}
