//! `satqual ema LOG... --input CH --output CH[,CH...]`: experimental modal analysis of the H1
//! FRFs of one input to one or several outputs. `--method lscf` (default) fits the LSCF poles
//! over model orders 2..=--order-max, picks the stable ones and fits their residues by LSFD;
//! `--method peak` reads resonances and half-power damping off the summed |H|. `--out DIR`
//! writes the stabilization diagram and the measured-against-rebuilt FRFs as SVG;
//! `--export-frf FILE` writes the FRFs as CSV (what a peer tool is run on).

use super::log_args::{LogArgs, WelchArgs};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::{
    self,
    ema::{EmaRequest, FrfSource},
};
use satqual::report::stabilization_svg::{StabilizationPlot, render};
use satqual::report::svg_plot::{self, Plot, Series};
use satqual::report::write_atomic;
use satqual::signal::PeakOptions;
use satqual::signal::ema::measured::Layout;
use satqual::signal::ema::{Criteria, EmaModel, EmaOptions, FrfForm, FrfSet, Method, Stability};

/// LSCF model order fitted up to when --order-max is not given: room for about 30 modes.
const DEFAULT_ORDER_MAX: usize = 60;
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// One or more logs, their segments averaged together; or UFF files of measured FRFs
    /// (function type 4), fitted as they are.
    #[arg(required = true)]
    pub logs: Vec<PathBuf>,
    /// Input (reference) channel: the force or the drive. With measured FRFs, the reference
    /// point (`1:+Z`), needed only when the files hold several.
    #[arg(long)]
    pub input: Option<String>,
    /// Response channels, comma-separated. With measured FRFs, the FRFs to fit (default all).
    #[arg(long, value_delimiter = ',')]
    pub output: Vec<String>,
    /// Band fitted, Hz (default: every line above 0 Hz).
    #[arg(long)]
    pub fmin: Option<f64>,
    #[arg(long)]
    pub fmax: Option<f64>,
    /// lscf (least-squares complex frequency + LSFD) or peak (half-power peak picking).
    #[arg(long, default_value = "lscf")]
    pub method: String,
    /// Highest LSCF model order (even; orders 2, 4, ... up to it are fitted) [default: 60, or
    /// what a narrow band's lines support]
    #[arg(long)]
    pub order_max: Option<usize>,
    /// Distinct orders at which a pole must be stable to be selected.
    #[arg(long, default_value_t = 5)]
    pub min_stable: usize,
    /// What the response measures per unit force: accelerance (default), mobility or
    /// receptance. Measured FRFs that state their form are fitted in it.
    #[arg(long)]
    pub frf_form: Option<String>,
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
    let form_text = args.frf_form.as_deref().unwrap_or("accelerance");
    let form = FrfForm::parse(form_text).ok_or_else(|| {
        Error::Other(format!(
            "--frf-form `{form_text}`: expected accelerance, mobility or receptance"
        ))
    })?;
    if args.min_stable == 0 {
        return Err(Error::Other("--min-stable must be at least 1".into()));
    }
    Ok(EmaOptions {
        f_lo: args.fmin.unwrap_or(0.0),
        f_hi: args.fmax.unwrap_or(f64::MAX),
        method,
        order_max: args.order_max.unwrap_or(DEFAULT_ORDER_MAX),
        order_max_is_default: args.order_max.is_none(),
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
        input: args.input.as_deref(),
        outputs: &args.output,
        ingest,
        welch: wopts,
        welch_is_default: args.welch.all_default(),
        options: opts.clone(),
        form_is_given: args.frf_form.is_some(),
    })?;
    let m = &run.model;
    let mut human = vec![summary_line(&args, &run)];
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
        write_damping(scene, &run, &args)?;
        human.push(format!(
            "  wrote the damping of {} mode(s) into {} [damping].table",
            m.modes.len(),
            scene.display()
        ));
    }
    if let Some(dir) = &args.out {
        write_figures(dir, m, &run.input)?;
        human.push(format!(
            "  wrote {}/stabilization.svg, reconstruction.svg",
            dir.display()
        ));
    }
    p.human(&human.join("\n"));
    // Checked before serde_json turns a NaN into null.
    let sources = (m.band_hz(), &m.modes, line_spacing(&run.set.freqs));
    satqual::output_check::check_sources(&sources, "ema JSON output")?;
    p.json(&result_json(&args, &opts, &run))?;
    Ok(Outcome::Pass)
}

fn summary_line(args: &Args, run: &workflows::ema::EmaRun) -> String {
    let m = &run.model;
    let (lo, hi) = m.band_hz();
    let source = match &run.source {
        FrfSource::Estimated { frfs, .. } => format!(
            "{} log(s), fs {:.6} Hz, {} segments averaged",
            args.logs.len(),
            frfs[0].fs,
            frfs[0].segments
        ),
        FrfSource::Measured(x) => format!(
            "{} measured FRF(s), unit {}, {}",
            x.records.len(),
            x.unit,
            match x.layout {
                Layout::CommonReference => "one reference, roving responses",
                Layout::CommonResponse => "one response, roving reference",
            }
        ),
    };
    format!(
        "{source}; {} output(s) / {}; {} ({}) in {lo:.3}–{hi:.3} Hz: {} mode(s)",
        run.set.channels.len(),
        run.input,
        args.method,
        run.form.name(),
        m.modes.len()
    )
}

fn result_json(args: &Args, opts: &EmaOptions, run: &workflows::ema::EmaRun) -> serde_json::Value {
    let m = &run.model;
    let (lo, hi) = m.band_hz();
    let count = |s: Stability| m.diagram.iter().filter(|p| p.stability == s).count();
    let c = &opts.criteria;
    let mut v = json!({
        "files": args.logs,
        "input": run.input,
        "outputs": run.set.channels,
        "method": m.method,
        "frf_form": run.form,
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
    });
    let extra = match &run.source {
        FrfSource::Estimated {
            frfs,
            welch,
            impact_windows,
        } => json!({
            "fs_hz": frfs[0].fs,
            "nperseg": frfs[0].nperseg,
            "window": welch.window.name(),
            "segments": frfs[0].segments,
            "impact_windows": impact_windows,
            "frequency_resolution_hz": frfs[0].df,
            "measured_frfs": null,
        }),
        FrfSource::Measured(x) => json!({
            "fs_hz": null,
            "nperseg": null,
            "window": null,
            "segments": null,
            "impact_windows": null,
            "frequency_resolution_hz": line_spacing(&run.set.freqs),
            "measured_frfs": {
                "layout": x.layout,
                "common_point": x.common_point,
                "unit": x.unit,
                "records": x.records,
            },
        }),
    };
    if let (Some(o), serde_json::Value::Object(e)) = (v.as_object_mut(), extra) {
        o.extend(e);
    }
    v
}

/// The spacing of the frequency lines (their span over their count).
fn line_spacing(freqs: &[f64]) -> Option<f64> {
    match (freqs.first(), freqs.last()) {
        (Some(a), Some(b)) if freqs.len() > 1 => Some((b - a) / (freqs.len() - 1) as f64),
        _ => None,
    }
}

/// The identified ratios into `scene`'s `[damping]`; the edited scene must load before it
/// replaces the file.
fn write_damping(scene: &Path, run: &workflows::ema::EmaRun, args: &Args) -> Result<(), Error> {
    let m = &run.model;
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
                run.set.channels.join(","),
                run.input,
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
