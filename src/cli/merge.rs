//! `satqual merge PARTS... [--out FILE] [--json] [--scene SCENE]`: joins the part files of a
//! sharded `separate --monte-carlo` into the result one machine would have printed, byte for
//! byte, after checking that the parts belong together and cover every run once.

use super::separate::{Output, print};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::fnv1a;
use satqual::report::write_atomic;
use satqual::separation::montecarlo::{Demand, aggregate};
use satqual::separation::shard::{self, Part};
use satqual::separation::{self, Model, RunOptions};
use satqual::spec::Scene;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Part files written by `separate --shard` (any order).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Write the merged JSON (the bytes `separate --json` prints) to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Read the scene from here instead of the path recorded in the parts (e.g. on another
    /// machine); its text must still match the recorded hash.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Print the merged JSON to stdout.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let parts = args
        .parts
        .iter()
        .map(|f| Part::read(f).map(|part| (f.clone(), part)))
        .collect::<Result<Vec<_>, _>>()?;
    let (campaign, realizations) = shard::merge(&parts)?;
    let from = args
        .scene
        .clone()
        .unwrap_or_else(|| PathBuf::from(&campaign.scene));
    let text = std::fs::read_to_string(&from).map_err(|e| Error::io(&from, e))?;
    if fnv1a(&text) != campaign.scene_hash {
        return Err(Error::Other(format!(
            "{}: the scene text changed since the shards ran (hash {}, the parts record {})",
            from.display(),
            fnv1a(&text),
            campaign.scene_hash
        )));
    }
    // The recorded path, not `from`: the merged output names the scene as the shards saw it.
    let scene = Scene::parse(Path::new(&campaign.scene), &text)?;
    let model = Model::from_scene(&scene)?;
    let result = separation::run(&model, &RunOptions::default())?;
    let demand = Demand::of(&model);
    let mc = aggregate(campaign.seed, campaign.satellites, demand, &realizations);
    if let Some(out) = &args.out {
        let json = serde_json::to_string_pretty(&Output {
            scene: campaign.scene.clone(),
            result: &result,
            monte_carlo: Some(&mc),
        })
        .map_err(|e| Error::Other(e.to_string()))?;
        write_atomic(out, format!("{json}\n").as_bytes())?;
    }
    print(&p, &scene, &result, Some(&mc))?;
    Ok(Outcome::Pass)
}
