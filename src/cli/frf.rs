//! `satqual frf LOG... --input CH --output CH`: H1, H2 and coherence averaged over every segment
//! of every log given (e.g. one file per hammer hit), resonances with half-power Q; `--out DIR`
//! writes frf.csv and an SVG of |H1| and coherence.

use super::log_args::{LogArgs, WelchArgs, print_notes};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{
    self,
    frf::{FrfRequest, FrfRun, Screen},
};
use satqual::report::plot::{Scale, Series, lines_svg};
use satqual::report::write_atomic;
use satqual::signal::screen::{EXCITATION_DB, MIN_COHERENCE};
use satqual::signal::{Frf, PeakOptions, Resonance};
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// One or more logs (CSV or text, UFF58/58b, LabVIEW .lvm, MATLAB .mat v5, TDMS, WAV); their segments are averaged together.
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
    /// Band searched for resonances, Hz [default: the band the input excites].
    #[arg(long)]
    pub fmin: Option<f64>,
    #[arg(long)]
    pub fmax: Option<f64>,
    #[command(flatten)]
    pub screen: ScreenArgs,
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub reading: LogArgs,
    #[command(flatten)]
    pub welch: WelchArgs,
}

/// Where resonances are searched: the band the input excites and coherent peaks.
#[derive(clap::Args, Debug, Clone)]
pub struct ScreenArgs {
    /// The excited band: where the input autospectrum lies within this many dB of its peak.
    #[arg(long, default_value_t = EXCITATION_DB)]
    pub excitation_db: f64,
    /// Least coherence at a resonance; peaks below it are left out and listed (0: keep all).
    #[arg(long, default_value_t = MIN_COHERENCE)]
    pub min_coherence: f64,
}

impl ScreenArgs {
    pub fn screen(&self, fmin: Option<f64>, fmax: Option<f64>) -> Result<Screen, Error> {
        if !(self.excitation_db > 0.0 && self.excitation_db.is_finite()) {
            return Err(Error::Other(format!(
                "--excitation-db {}: must be a positive number of dB",
                self.excitation_db
            )));
        }
        if !(0.0..=1.0).contains(&self.min_coherence) {
            return Err(Error::Other(format!(
                "--min-coherence {}: must be in [0, 1]",
                self.min_coherence
            )));
        }
        Ok(Screen {
            excitation_db: self.excitation_db,
            min_coherence: self.min_coherence,
            fmin,
            fmax,
        })
    }
}

/// The JSON of how an FRF was made and screened: Welch options used, impact detection, the
/// band searched, the peaks left out, the reader's decisions and the notes.
pub fn run_json(run: &FrfRun) -> serde_json::Value {
    let w = &run.welch;
    json!({
        "nperseg": w.nperseg,
        "window": w.window.name(),
        "detrend": w.detrend.name(),
        "overlap": w.overlap,
        "impact": run.impact.as_ref().map(|p| json!({"detected": true, "pulses": p, "windows": run.impact_windows})),
        "screen": run.screen.as_ref().map(|s| json!({
            "excited_band": s.excited,
            "searched_hz": s.searched_hz,
            "min_coherence": s.min_coherence,
            "screened_out": s.screened_out.iter().map(peak_json).collect::<Vec<_>>(),
        })),
        "ingest": run.ingest.iter().map(|(f, i)| json!({"file": f, "record": i})).collect::<Vec<_>>(),
        "notes": run.notes,
    })
}

/// Prints the reader's notes of each log, then the run's own.
pub fn print_run_notes(run: &FrfRun) {
    for (_, i) in &run.ingest {
        print_notes(&i.notes);
    }
    print_notes(&run.notes);
}

/// The numbers of a run that its JSON is built from (see `check_sources`).
pub fn check_run_sources(run: &FrfRun, what: &str) -> Result<(), Error> {
    let h = &run.frf;
    let screen = run
        .screen
        .as_ref()
        .map(|s| (&s.excited, s.searched_hz, &s.screened_out));
    let sources = (
        h.fs,
        h.df,
        &run.resonances,
        screen,
        (&run.impact, &run.impact_windows),
    );
    satqual::output_check::check_sources(&sources, what)
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
        f_min_hz: 0.0,
        f_max_hz: f64::INFINITY,
        db_per_decade: 20.0,
        ..PeakOptions::default()
    };
    let ingest = args.reading.ingest(None)?;
    let run = workflows::frf::run(&FrfRequest {
        logs: &args.logs,
        input: &args.input,
        output: &args.output,
        ingest,
        welch: wopts,
        welch_is_default: args.welch.all_default(),
        peaks,
        from_first_line: false,
        screen: Some(args.screen.screen(args.fmin, args.fmax)?),
    })?;
    print_run_notes(&run);
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
            "  {:10.2} Hz  |H1| {:.6e} {}  Q {}  coherence {:.4}",
            r.frequency_hz,
            r.magnitude,
            run.h_unit,
            r.q.map_or("-".into(), |q| format!("{q:.1}")),
            r.coherence
        ));
    }
    if run.resonances.is_empty() {
        human.push("  no resonance reported (the notes on stderr say why)".into());
    }
    for r in run.screen.iter().flat_map(|s| &s.screened_out) {
        human.push(format!(
            "  ({:8.2} Hz  |H1| {:.6e}  coherence {:.4}: below {}, left out)",
            r.frequency_hz, r.magnitude, r.coherence, args.screen.min_coherence
        ));
    }
    if let Some(dir) = &args.out {
        write_outputs(dir, h, &args.input, &args.output)?;
        human.push(format!("  wrote {}/frf.csv, frf.svg", dir.display()));
    }
    p.human(&human.join("\n"));
    check_run_sources(&run, "frf JSON output")?;
    let mut doc = json!({
        "files": args.logs,
        "input": args.input,
        "output": args.output,
        "fs_hz": h.fs,
        "segments": h.segments,
        "frequency_resolution_hz": h.df,
        "h_unit": run.h_unit,
        "peaks": run.resonances.iter().map(peak_json).collect::<Vec<_>>(),
    });
    merge(&mut doc, run_json(&run));
    p.json(&doc)?;
    Ok(Outcome::Pass)
}

/// Adds the keys of object `extra` to object `doc`.
pub fn merge(doc: &mut serde_json::Value, extra: serde_json::Value) {
    if let (Some(d), serde_json::Value::Object(e)) = (doc.as_object_mut(), extra) {
        d.extend(e);
    }
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
