//! `satqual frf LOG... --input CH --output CH`: H1, H2 and coherence averaged over every segment
//! of every log given (e.g. one file per hammer hit), resonances with half-power Q; `--out DIR`
//! writes frf.csv and an SVG of |H1| and coherence.

use super::log_args::{LogArgs, WelchArgs};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{self, frf::FrfRequest};
use satqual::report::plot::{Scale, Series, lines_svg};
use satqual::report::write_atomic;
use satqual::signal::{Frf, PeakOptions, Resonance};
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// One or more CSV logs; their segments are averaged together.
    #[arg(required = true)]
    pub logs: Vec<PathBuf>,
    /// Input (reference) channel, e.g. the force or the drive.
    #[arg(long)]
    pub input: String,
    /// Output (response) channel.
    #[arg(long)]
    pub output: String,
    /// Resonances reported (the strongest, in frequency order).
    #[arg(long, default_value_t = 10)]
    pub peaks: usize,
    /// Smallest prominence of a resonance on |H1|, dB.
    #[arg(long, default_value_t = 6.0)]
    pub min_prominence_db: f64,
    /// Band searched for resonances, Hz.
    #[arg(long)]
    pub fmin: Option<f64>,
    #[arg(long)]
    pub fmax: Option<f64>,
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub reading: LogArgs,
    #[command(flatten)]
    pub welch: WelchArgs,
}

pub fn peak_json(r: &Resonance) -> serde_json::Value {
    json!({"frequency_hz": r.frequency_hz, "magnitude": r.magnitude, "q": r.q, "coherence": r.coherence, "phase_deg": r.phase_deg, "prominence_db": r.prominence_db})
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let wopts = args.welch.options()?;
    let peaks = PeakOptions {
        min_prominence_db: args.min_prominence_db,
        max_peaks: args.peaks,
        f_min_hz: args.fmin.unwrap_or(0.0),
        f_max_hz: args.fmax.unwrap_or(f64::INFINITY),
        db_per_decade: 20.0,
    };
    let ingest = args.reading.ingest(None)?;
    let run = workflows::frf::run(&FrfRequest {
        logs: &args.logs,
        input: &args.input,
        output: &args.output,
        ingest,
        welch: wopts.clone(),
        peaks,
        from_first_line: false,
    })?;
    let h = &run.frf;
    let mut human = vec![format!(
        "{} log(s), fs {:.6} Hz, nperseg {}, {} segments averaged; H1 = {}/{}",
        args.logs.len(),
        h.fs,
        h.nperseg,
        h.segments,
        args.output,
        args.input
    )];
    for r in &run.resonances {
        human.push(format!(
            "  {:10.2} Hz  |H1| {:.6e}  Q {}  coherence {:.4}",
            r.frequency_hz,
            r.magnitude,
            r.q.map_or("-".into(), |q| format!("{q:.1}")),
            r.coherence
        ));
    }
    if let Some(dir) = &args.out {
        write_outputs(dir, h, &args.input, &args.output)?;
        human.push(format!("  wrote {}/frf.csv, frf.svg", dir.display()));
    }
    p.human(&human.join("\n"));
    p.json(&json!({
        "files": args.logs,
        "input": args.input,
        "output": args.output,
        "fs_hz": h.fs,
        "nperseg": h.nperseg,
        "window": wopts.window.name(),
        "detrend": wopts.detrend.name(),
        "overlap": wopts.overlap,
        "segments": h.segments,
        "frequency_resolution_hz": h.df,
        "peaks": run.resonances.iter().map(peak_json).collect::<Vec<_>>(),
    }))?;
    Ok(Outcome::Pass)
}

fn write_outputs(dir: &std::path::Path, h: &Frf, input: &str, output: &str) -> Result<(), Error> {
    let f = h.frequencies();
    let h1 = h.h1();
    let h2 = h.h2();
    let coh = h.coherence();
    let mut csv = String::from("frequency_hz,h1_mag,h1_phase_deg,h2_mag,h2_phase_deg,coherence\n");
    for k in 0..f.len() {
        csv.push_str(&format!(
            "{:.9e},{:.9e},{:.6},{:.9e},{:.6},{:.9}\n",
            f[k],
            h1[k].norm(),
            h1[k].arg().to_degrees(),
            h2[k].norm(),
            h2[k].arg().to_degrees(),
            coh[k]
        ));
    }
    write_atomic(&dir.join("frf.csv"), csv.as_bytes())?;
    let mag: Vec<(f64, f64)> = f
        .iter()
        .zip(&h1)
        .skip(1)
        .map(|(f, z)| (*f, z.norm()))
        .collect();
    let svg = lines_svg(
        &format!("|H1| = {output}/{input}"),
        "frequency [Hz]",
        "|H1|",
        &[Series {
            label: "|H1|".into(),
            points: &mag,
        }],
        Scale::Linear,
        Scale::Log,
    )?;
    write_atomic(&dir.join("frf.svg"), svg.as_bytes())?;
    let c: Vec<(f64, f64)> = f.iter().zip(&coh).skip(1).map(|(f, c)| (*f, *c)).collect();
    let svg = lines_svg(
        "coherence",
        "frequency [Hz]",
        "γ²",
        &[Series {
            label: "coherence".into(),
            points: &c,
        }],
        Scale::Linear,
        Scale::Linear,
    )?;
    write_atomic(&dir.join("coherence.svg"), svg.as_bytes())?;
    Ok(())
}
