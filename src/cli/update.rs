//! `satqual update SCENE --out UPDATED.toml`: the scene's `[update]` parameters fitted to its
//! paired test frequencies; prints the parameters, the targets before and after, and the
//! identifiability figures, and writes the updated scene (never over the input).

use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::correlate;
use satqual::pipeline::workflows::update::{self, Update};
use satqual::report::write_atomic;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with [update], [[test_point]] and [test_modes] or [correlation] logs.
    pub scene: PathBuf,
    /// The updated scene to write (must not be the input).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write a report folder: parameters, frequencies and MAC before and after.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    if super::same_file(&args.scene, &args.out) {
        return Err(Error::Other(format!(
            "--out {} is the input scene: update never overwrites its input; name another file",
            args.out.display()
        )));
    }
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let u = update::run(&scene)?;
    let p = Printer::new(args.json);
    p.json(&u)?;
    write_atomic(&args.out, u.updated_text.as_bytes())?;
    let mut human = summary(&args.scene, &u);
    human.push(format!("  wrote {}", args.out.display()));
    if let Some(dir) = &args.report {
        let updated = satqual::spec::Scene::parse(&args.out, &u.updated_text)?;
        let (before, after) = (correlate::run(&scene)?, correlate::run(&updated)?);
        let overlays = update::overlay::overlays(&scene, &updated)?;
        satqual::report::update::write(dir, &u, (&before, &after), &overlays)?;
        human.push(format!("  wrote {}/report.html", dir.display()));
    }
    p.human(&human.join("\n"));
    Ok(if u.converged {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}

fn summary(scene: &Path, u: &Update) -> Vec<String> {
    let mut out = vec![format!("{}: {}", scene.display(), u.headline())];
    out.push(format!(
        "  {:<40} {:>13} {:>13} {:>29} {:>27}",
        "parameter", "start", "updated", "95% interval", "bounds"
    ));
    for p in &u.parameters {
        let ci = match (p.ci_low, p.ci_high) {
            (Some(a), Some(b)) => format!("[{a:.5e}, {b:.5e}]"),
            _ => "undefined".into(),
        };
        let flag = if p.identifiable {
            ""
        } else {
            "  NOT IDENTIFIABLE"
        };
        out.push(format!(
            "  {:<40} {:>13.6e} {:>13.6e} {:>29} [{:.3e}, {:.3e}]{flag}",
            p.path, p.start, p.value, ci, p.lower, p.upper
        ));
    }
    out.push(
        "  test mode  FE mode    test Hz   before Hz    after Hz  error before  error after    MAC"
            .into(),
    );
    for t in &u.targets {
        out.push(format!(
            "  {:>9}  {:>7} {:>10.4} {:>11.4} {:>11.4} {:>+12.3}% {:>+11.3}% {:>6.4}",
            t.test_mode,
            t.fe_mode,
            t.test_hz,
            t.before_hz,
            t.after_hz,
            t.error_before_pct,
            t.error_after_pct,
            t.mac
        ));
    }
    let sv: Vec<String> = u
        .singular_values
        .iter()
        .map(|s| format!("{s:.4e}"))
        .collect();
    out.push(format!(
        "  singular values of the weighted sensitivity matrix: {}",
        sv.join(", ")
    ));
    for (p, row) in u.parameters.iter().zip(&u.correlation) {
        let r: Vec<String> = row.iter().map(|c| format!("{c:+.3}")).collect();
        out.push(format!("  correlation {:<40} {}", p.path, r.join(" ")));
    }
    if !u.damping.is_empty() {
        out.push(
            "  damping from the measured sine peaks: test mode  FE mode  channel      measured g  predicted g   ζ start  ζ identified".into(),
        );
    }
    for d in &u.damping {
        out.push(format!(
            "  {:>47}  {:>7}  {:<10} {:>11.4} {:>12.4} {:>9.5} {:>13.5}",
            d.test_mode, d.fe_mode, d.channel, d.measured_g, d.predicted_g, d.zeta_start, d.zeta
        ));
    }
    out.extend(u.warnings.iter().map(|w| format!("  warning: {w}")));
    out.extend(u.notes.iter().map(|n| format!("  note: {n}")));
    out
}
