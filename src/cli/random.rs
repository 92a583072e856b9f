//! `satqual random`: base-driven random-vibration response of a scene's `[random]` profile,
//! per axis: Grms and 3σ of every response point (with Miles' cross-check), joint and
//! guide-bar 3σ loads, and the lock-integrity margins.

use super::progress::Progress;
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::{plan, workflows};
use satqual::response;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with a [random] section.
    pub scene: PathBuf,
    /// Only this axis (x, y or z); default: the scene's `random.axes`.
    #[arg(long)]
    pub axis: Option<String>,
    /// Write CSV curves and SVG plots to this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Serialize)]
struct Output<'a> {
    scene: String,
    damping: String,
    pass: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    environment: Option<&'a satqual::spec::environment::RandomEnvironment>,
    axes: &'a [response::RandomAxis],
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let plan = plan::random_command(&scene, args.axis.as_deref())?;
    let progress = Progress::start(args.quiet, args.json, "random response");
    let run = workflows::response::random(&scene, &plan)?;
    progress.finish();
    let results = &run.axes;
    let pass = results.iter().all(|r| r.margins.iter().all(|m| m.pass));
    let modes_used = results.iter().map(|r| r.modes_used).max().unwrap_or(0);
    let damping = super::sine::damping_text(&run.damping, scene.file.damping.is_some(), modes_used);
    let p = Printer::new(args.json);
    let mut t = String::new();
    let _ = writeln!(t, "{}: random, damping {}", args.scene.display(), damping);
    if let Some(e) = &run.environment {
        let _ = writeln!(t, "input: {}", environment_line(e));
    }
    for r in results {
        let _ = writeln!(
            t,
            "axis {}: input {:.2} Grms, {} modes + residual vector: {}, {} frequencies",
            r.axis, r.input_grms, r.modes_used, r.residual_vector, r.frequency_points
        );
        for x in &r.responses {
            let _ = writeln!(
                t,
                "  {:<12} {:>8.2} Grms  3σ {:>8.2} g  peak {:.4} g²/Hz at {:.1} Hz  (Miles {:.2} Grms)",
                x.name, x.grms, x.three_sigma_g, x.peak_psd_g2_hz, x.peak_psd_hz, x.miles_grms
            );
        }
        super::sine::summarize_margins(&mut t, &r.margins);
    }
    let _ = write!(
        t,
        "lock integrity: {}",
        if pass {
            "PASS"
        } else {
            "FAIL (a margin is negative)"
        }
    );
    p.human(&t);
    p.json(&Output {
        scene: args.scene.display().to_string(),
        damping,
        pass,
        environment: run.environment.as_ref(),
        axes: results,
    })?;
    if let Some(dir) = &args.out {
        for r in results {
            let name = format!("random-{}", r.axis);
            satqual::report::write_atomic(
                &dir.join(format!("{name}.csv")),
                r.curves.to_csv("input_g2_hz").as_bytes(),
            )?;
            satqual::report::write_atomic(
                &dir.join(format!("{name}-interfaces.csv")),
                r.curves
                    .csv_of("input_g2_hz", &r.curves.interfaces)
                    .as_bytes(),
            )?;
            satqual::report::write_atomic(
                &dir.join(format!("{name}-bars.csv")),
                r.curves.csv_of("input_g2_hz", &r.curves.bars).as_bytes(),
            )?;
            let svg = super::sine::plot(
                &r.curves,
                &format!(
                    "Random, axis {}: response PSD ({:.2} Grms input)",
                    r.axis, r.input_grms
                ),
                "PSD [g²/Hz]",
                "input profile [g²/Hz]",
                true,
            );
            satqual::report::write_atomic(&dir.join(format!("{name}.svg")), svg.as_bytes())?;
        }
        satqual::output_check::check_json(results, "random.json")?;
        let json =
            serde_json::to_string_pretty(results).map_err(|e| Error::Other(e.to_string()))?;
        satqual::report::write_atomic(&dir.join("random.json"), json.as_bytes())?;
        p.human(&format!("curves and plots written to {}", dir.display()));
    }
    Ok(if pass {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}

/// One line on the random input as applied: level, reduction, Grms, duration, source.
fn environment_line(e: &satqual::spec::environment::RandomEnvironment) -> String {
    let mut parts = Vec::new();
    if let Some(name) = &e.environment {
        parts.push(name.clone());
    }
    if let Some(l) = e.level {
        parts.push(l.name().to_string());
    }
    if let Some(r) = &e.weight_reduction {
        parts.push(format!(
            "GEVS weight reduction −{:.2} dB for {:.1} kg",
            r.reduction_db, r.mass_kg
        ));
    }
    parts.push(format!("{:.2} Grms", e.grms));
    if let Some(d) = e.duration_s {
        parts.push(format!("{d:.0} s per axis"));
    }
    format!("{} ({})", parts.join(", "), e.source)
}
