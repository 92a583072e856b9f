//! `satqual modal`: natural frequencies and effective masses of a scene.

use super::Outcome;
use satqual::Error;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Highest frequency to extract, Hz (overrides the scene).
    #[arg(long, conflicts_with = "modes")]
    pub fmax: Option<f64>,
    /// Number of modes to extract (overrides the scene).
    #[arg(long)]
    pub modes: Option<usize>,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    /// Write K, M, K_G (Matrix Market) and the DOF map (CSV) to this folder.
    #[arg(long)]
    pub export_matrices: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let _scene = satqual::spec::Scene::load(&args.scene)?;
    Ok(Outcome::Pass)
}
