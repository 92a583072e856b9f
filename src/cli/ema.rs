//! `satqual ema LOG... --input CH --output CH[,CH...]`: experimental modal analysis of the H1
//! FRFs of one input to one or several outputs. `--method lscf` (default) fits the LSCF poles
//! over model orders 2..=--order-max, picks the stable ones and fits their residues by LSFD;
//! `--method peak` reads resonances and half-power damping off the summed |H|. `--out DIR`
//! writes the stabilization diagram and the measured-against-rebuilt FRFs as SVG;
//! `--export-frf FILE` writes the FRFs as CSV (what a peer tool is run on).

use super::log_args::{LogArgs, WelchArgs};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{self, ema::EmaRequest};
use satqual::report::stabilization_svg::{StabilizationPlot, render};
use satqual::report::svg_plot::{self, Plot, Series};
use satqual::report::write_atomic;
use satqual::signal::PeakOptions;
use satqual::signal::ema::{Criteria, EmaModel, EmaOptions, FrfForm, FrfSet, Method, Stability};
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// One or more CSV logs; their segments are averaged together.
    #[arg(required = true)]
    pub logs: Vec<PathBuf>,
    /// Input (reference) channel: the force or the drive.
    #[arg(long)]
    pub input: String,
    /// Response channels, comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub output: Vec<String>,
    /// Band fitted, Hz (default: every line above 0 Hz).
    #[arg(long)]
    pub fmin: Option<f64>,
    #[arg(long)]
    pub fmax: Option<f64>,
    /// lscf (least-squares complex frequency + LSFD) or peak (half-power peak picking).
    #[arg(long, default_value = "lscf")]
    pub method: String,
    /// Highest LSCF model order (even; orders 2, 4, ... up to it are fitted).
    #[arg(long, default_value_t = 60)]
    pub order_max: usize,
    /// Distinct orders at which a pole must be stable to be selected.
    #[arg(long, default_value_t = 5)]
    pub min_stable: usize,
    /// What the response measures per unit force: accelerance, mobility or receptance.
    #[arg(long, default_value = "accelerance")]
    pub frf_form: String,
    /// Peak method: resonances kept and their smallest prominence on Σ|H|, dB.
    #[arg(long, default_value_t = 10)]
    pub peaks: usize,
    #[arg(long, default_value_t = 6.0)]
    pub min_prominence_db: f64,
    /// Write the FRFs (every line, re and im per output) to this CSV.
    #[arg(long)]
    pub export_frf: Option<PathBuf>,
    /// Folder for stabilization.svg and reconstruction.svg.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the identified damping into this scene's [damping] as a frequency table (every
    /// comment kept, each point annotated with its source).
    #[arg(long)]
    pub write_damping: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub reading: LogArgs,
    #[command(flatten)]
    pub welch: WelchArgs,
}

fn options(args: &Args) -> Result<EmaOptions, Error> {
    let method = match args.method.as_str() {
        "lscf" => Method::Lscf,
        "peak" => Method::Peak,
        m => {
            return Err(Error::Other(format!(
                "--method `{m}`: expected lscf or peak"
            )));
        }
    };
    let form = FrfForm::parse(&args.frf_form).ok_or_else(|| {
        Error::Other(format!(
            "--frf-form `{}`: expected accelerance, mobility or receptance",
            args.frf_form
        ))
    })?;
    if args.min_stable == 0 {
        return Err(Error::Other("--min-stable must be at least 1".into()));
    }
    Ok(EmaOptions {
        f_lo: args.fmin.unwrap_or(0.0),
        f_hi: args.fmax.unwrap_or(f64::MAX),
        method,
        order_max: args.order_max,
        form,
        criteria: Criteria {
            min_orders: args.min_stable,
            ..Criteria::default()
        },
        peaks: PeakOptions {
            min_prominence_db: args.min_prominence_db,
            max_peaks: args.peaks,
            ..PeakOptions::default()
        },
    })
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let wopts = args.welch.options()?;
    let ingest = args.reading.ingest(None)?;
    let opts = options(&args)?;
    let run = workflows::ema::run(&EmaRequest {
        logs: &args.logs,
        input: &args.input,
        outputs: &args.output,
        ingest,
        welch: wopts,
        welch_is_default: args.welch.all_default(),
        options: opts.clone(),
    })?;
    let (m, h) = (&run.model, &run.frfs[0]);
    let mut human = vec![summary_line(&args, m, h.fs, h.segments)];
    for (i, mode) in m.modes.iter().enumerate() {
        human.push(format!(
            "  mode {}: {:10.3} Hz  ζ {:.5}  MPC {:.3}  MPD {:.1}°",
            i + 1,
            mode.frequency_hz,
            mode.damping_ratio,
            mode.mpc,
            mode.mpd
        ));
    }
    human.extend(m.notes.iter().map(|n| format!("  note: {n}")));
    if let Some(path) = &args.export_frf {
        write_atomic(path, frf_csv(&run.set).as_bytes())?;
        human.push(format!("  wrote {}", path.display()));
    }
    if let Some(scene) = &args.write_damping {
        write_damping(scene, m, &args)?;
        human.push(format!(
            "  wrote the damping of {} mode(s) into {} [damping].table",
            m.modes.len(),
            scene.display()
        ));
    }
    if let Some(dir) = &args.out {
        write_figures(dir, m, &args.input)?;
        human.push(format!(
            "  wrote {}/stabilization.svg, reconstruction.svg",
            dir.display()
        ));
    }
    p.human(&human.join("\n"));
    let sources = (h.fs, h.df, m.band_hz(), &m.modes);
    satqual::output_check::check_sources(&sources, "ema JSON output")?;
    p.json(&result_json(&args, &opts, &run))?;
    Ok(Outcome::Pass)
}

fn summary_line(args: &Args, m: &EmaModel, fs: f64, segments: usize) -> String {
    let (lo, hi) = m.band_hz();
    format!(
        "{} log(s), fs {fs:.6} Hz, {segments} segments averaged; {} output(s) / {}; {} in {lo:.3}–{hi:.3} Hz: {} mode(s)",
        args.logs.len(),
        args.output.len(),
        args.input,
        args.method,
        m.modes.len()
    )
}

fn result_json(args: &Args, opts: &EmaOptions, run: &workflows::ema::EmaRun) -> serde_json::Value {
    let (m, h, w) = (&run.model, &run.frfs[0], &run.welch);
    let (lo, hi) = m.band_hz();
    let count = |s: Stability| m.diagram.iter().filter(|p| p.stability == s).count();
    let c = &opts.criteria;
    json!({
        "files": args.logs,
        "input": args.input,
        "outputs": args.output,
        "fs_hz": h.fs,
        "nperseg": h.nperseg,
        "window": w.window.name(),
        "segments": h.segments,
        "impact_windows": run.impact_windows,
        "frequency_resolution_hz": h.df,
        "method": m.method,
        "frf_form": opts.form,
        "band_hz": [lo, hi],
        "lines": m.freqs.len(),
        "orders": m.orders,
        "criteria": {
            "df_rel": c.df_rel, "dzeta_rel": c.dzeta_rel, "mac_min": c.mac_min,
            "zeta_max": c.zeta_max, "min_stable_orders": c.min_orders,
        },
        "diagram": {
            "poles": m.diagram.len(),
            "stable_vector": count(Stability::Vector),
            "stable_damping": count(Stability::Damping),
            "stable_frequency": count(Stability::Frequency),
        },
        "modes": m.modes,
        "notes": m.notes,
    })
}

/// The identified ratios into `scene`'s `[damping]`; the edited scene must load before it
/// replaces the file.
fn write_damping(scene: &Path, m: &EmaModel, args: &Args) -> Result<(), Error> {
    use satqual::spec::damping_edit::{IdentifiedDamping, with_identified_damping};
    let text = std::fs::read_to_string(scene).map_err(|e| Error::io(scene, e))?;
    let logs: Vec<String> = args
        .logs
        .iter()
        .map(|l| {
            l.file_name().map_or_else(
                || l.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            )
        })
        .collect();
    let points: Vec<IdentifiedDamping> = m
        .modes
        .iter()
        .enumerate()
        .map(|(i, x)| IdentifiedDamping {
            frequency_hz: x.frequency_hz,
            zeta: x.damping_ratio,
            source: format!(
                "satqual ema --method {} ({} / {}, {}): mode {} at {:.4} Hz, zeta {:.6}, MPC {:.3}",
                args.method,
                args.output.join(","),
                args.input,
                logs.join(" "),
                i + 1,
                x.frequency_hz,
                x.damping_ratio,
                x.mpc
            ),
        })
        .collect();
    let edited = with_identified_damping(&text, &points)
        .map_err(|e| Error::Other(format!("{}: --write-damping: {e}", scene.display())))?;
    satqual::spec::Scene::parse(scene, &edited).map_err(|e| {
        Error::Other(format!(
            "{}: --write-damping: the edited scene does not load, left unchanged: {e}",
            scene.display()
        ))
    })?;
    write_atomic(scene, edited.as_bytes())
}

fn frf_csv(set: &FrfSet) -> String {
    let mut s = String::from("frequency_hz");
    for c in &set.channels {
        s.push_str(&format!(",{c}_re,{c}_im"));
    }
    s.push('\n');
    for (k, f) in set.freqs.iter().enumerate() {
        s.push_str(&format!("{f:.17e}"));
        for h in &set.h {
            s.push_str(&format!(",{:.17e},{:.17e}", h[k].re, h[k].im));
        }
        s.push('\n');
    }
    s
}

fn write_figures(dir: &Path, m: &EmaModel, input: &str) -> Result<(), Error> {
    let sum: Vec<(f64, f64)> = (0..m.freqs.len())
        .map(|k| (m.freqs[k], m.measured.iter().map(|h| h[k].norm()).sum()))
        .collect();
    let selected: Vec<f64> = m.modes.iter().map(|x| x.frequency_hz).collect();
    let svg = render(&StabilizationPlot {
        title: &format!("stabilization diagram ({:?})", m.method).to_lowercase(),
        band_hz: m.band_hz(),
        order_max: m.orders.last().copied().unwrap_or(0),
        poles: &m.diagram,
        frf_sum: &sum,
        selected_hz: &selected,
    });
    write_atomic(&dir.join("stabilization.svg"), svg.as_bytes())?;
    let mags: Vec<Vec<f64>> = m
        .measured
        .iter()
        .chain(m.reconstructed.iter().flatten())
        .map(|h| h.iter().map(|z| z.norm()).collect())
        .collect();
    let n = m.measured.len();
    let names: Vec<String> = (0..mags.len())
        .map(|i| {
            if i < n {
                format!("measured {}", i + 1)
            } else {
                format!("LSFD {}", i - n + 1)
            }
        })
        .collect();
    let series: Vec<Series> = mags
        .iter()
        .enumerate()
        .map(|(i, y)| Series {
            name: &names[i],
            x: &m.freqs,
            y,
            dashed: i >= n,
        })
        .collect();
    let svg = svg_plot::render(
        &Plot {
            title: &format!("|H| per output / {input}: measured and rebuilt"),
            x_label: "frequency [Hz]",
            y_label: "|H|",
            log_x: false,
            log_y: true,
        },
        &series,
    );
    write_atomic(&dir.join("reconstruction.svg"), svg.as_bytes())?;
    Ok(())
}
