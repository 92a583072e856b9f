//! `satqual correlate SCENE`: the scene's FE modes against its test modes (`[test_modes]`, or
//! identified from `[correlation] logs`) at its `[[test_point]]`s: the pairs, their frequency
//! errors, the MAC matrix, the SEREP cross-orthogonality and the gates. `--out DIR` writes the
//! MAC heat map (mac.svg).

use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::workflows::correlate::{self, Correlation};
use satqual::report::write_atomic;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with [[test_point]] and [test_modes] or [correlation] logs.
    pub scene: PathBuf,
    /// Folder for the MAC heat map, mac.svg.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the scene, with the measured damping ratios of the paired test modes as
    /// `[damping] modes` entries of their FE modes, to this file (never the input).
    #[arg(long, value_name = "OUT.toml")]
    pub write_damping: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let c = correlate::run(&scene)?;
    let p = Printer::new(args.json);
    let mut human = summary(&args.scene, &c);
    if let Some(dir) = &args.out {
        write_heatmap(dir, &c)?;
        human.push(format!("  wrote {}/mac.svg", dir.display()));
    }
    if let Some(out) = &args.write_damping {
        let n = write_damping(&scene, &c, out)?;
        human.push(format!(
            "  wrote {} with the damping of {n} paired mode(s)",
            out.display()
        ));
    }
    p.human(&human.join("\n"));
    p.json(&c)?;
    Ok(if c.passed() {
        Outcome::Pass
    } else {
        Outcome::GateFailed
    })
}

fn summary(scene: &Path, c: &Correlation) -> Vec<String> {
    let mut out = vec![format!(
        "{}: {} test mode(s) from {}; {} FE mode(s) at {} test point(s); pairing by {}",
        scene.display(),
        c.test_modes.len(),
        c.test_source,
        c.fe_modes.len(),
        c.channels.len(),
        match c.pairing {
            satqual::modal::correlation::PairingMethod::Mac => "MAC",
            satqual::modal::correlation::PairingMethod::FrequencyAndDirection =>
                "frequency and effective-mass direction",
        }
    )];
    for p in &c.pairs {
        out.push(format!(
            "  test mode {} {:10.4} Hz  FE mode {} {:10.4} Hz  error {:+7.3}%  MAC {:.4}",
            p.test_mode, p.test_hz, p.fe_mode, p.fe_hz, p.error_pct, p.mac
        ));
    }
    out.extend(c.notes.iter().map(|n| format!("  note: {n}")));
    for g in &c.gates {
        out.push(format!(
            "  {} {}: {:.4} (limit {})",
            if g.pass { "PASS" } else { "FAIL" },
            g.name,
            g.value,
            g.limit
        ));
    }
    out
}

/// The scene text with each paired test mode's measured damping ratio on its FE mode, written
/// to `out`; returns how many modes carried one.
fn write_damping(
    scene: &satqual::spec::Scene,
    c: &Correlation,
    out: &Path,
) -> Result<usize, Error> {
    use satqual::spec::damping_edit::{IdentifiedModeDamping, with_mode_damping};
    if super::same_file(&scene.path, out) {
        return Err(Error::Other(format!(
            "--write-damping {} is the input scene: correlate never overwrites its input; name another file",
            out.display()
        )));
    }
    let entries: Vec<IdentifiedModeDamping> = (c.pairs.iter())
        .filter_map(|p| {
            let zeta = c.test_modes[p.test_mode - 1].damping_ratio?;
            let fe = c.fe_modes.iter().find(|m| m.mode == p.fe_mode);
            Some(IdentifiedModeDamping {
                mode: p.fe_mode,
                zeta,
                direction: fe.and_then(|m| m.family).map(str::to_string),
                source: format!(
                    "measured: test mode {} ({:.4} Hz) from {}, paired by satqual correlate (MAC {:.3})",
                    p.test_mode, p.test_hz, c.test_source, p.mac
                ),
            })
        })
        .collect();
    if entries.is_empty() {
        return Err(Error::Other(format!(
            "{}: --write-damping: no paired test mode has a damping ratio",
            scene.path.display()
        )));
    }
    let text = with_mode_damping(&scene.text, &entries)
        .map_err(|e| Error::Other(format!("{}: --write-damping: {e}", scene.path.display())))?;
    satqual::spec::Scene::parse(out, &text)?;
    write_atomic(out, text.as_bytes())?;
    Ok(entries.len())
}

fn write_heatmap(dir: &Path, c: &Correlation) -> Result<(), Error> {
    let title = "MAC: test modes (rows) against FE modes (columns), pairs outlined";
    let svg = satqual::report::mac_heatmap::of_correlation(c, title)?;
    write_atomic(&dir.join("mac.svg"), svg.as_bytes())
}
