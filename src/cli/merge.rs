//! `satqual merge PARTS... [--out FILE] [--json] [--scene SCENE]`: joins the part files of a
//! sharded `separate --monte-carlo` into the result one machine would have printed, byte for
//! byte, after checking that the parts belong together and cover every run once. Parts of a
//! sweep (`separate --sweep --shard`) merge into the sweep's report folder.

use super::separate::{Output, print};
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::fnv1a;
use satqual::pipeline::param_sweep::{SweepJob, table};
use satqual::report::write_atomic;
use satqual::separation::Realization;
use satqual::separation::montecarlo::{Demand, aggregate};
use satqual::separation::shard::{self, Campaign, Part};
use satqual::separation::{self, Model, RunOptions};
use satqual::spec::Scene;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Part files written by `separate --shard` (any order).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Write the merged JSON (the bytes `separate --json` prints) to this file; for a sweep,
    /// the report folder (default reports/<scene>/sweep).
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
    let scene = recorded_scene(&campaign, args.scene.as_deref())?;
    if campaign.sweep.is_some() {
        return merge_sweep(&p, &scene, &campaign, &realizations, args.out.as_deref());
    }
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

/// The scene the parts were computed from: read from `--scene` or the recorded path, checked
/// against the recorded hash, named by the recorded path (as the shards saw it).
fn recorded_scene(campaign: &Campaign, scene: Option<&Path>) -> Result<Scene, Error> {
    let from = scene.map_or_else(|| PathBuf::from(&campaign.scene), Path::to_path_buf);
    let text = std::fs::read_to_string(&from).map_err(|e| Error::io(&from, e))?;
    if fnv1a(&text) != campaign.scene_hash {
        return Err(Error::Other(format!(
            "{}: the scene text changed since the shards ran (hash {}, the parts record {})",
            from.display(),
            fnv1a(&text),
            campaign.scene_hash
        )));
    }
    Ok(Scene::parse(Path::new(&campaign.scene), &text)?)
}

/// The sweep's table from every unit's realization, written as its report folder.
fn merge_sweep(
    p: &Printer,
    scene: &Scene,
    campaign: &Campaign,
    realizations: &[Realization],
    out: Option<&Path>,
) -> Result<Outcome, Error> {
    let job = SweepJob::new(scene, campaign.runs, campaign.seed)?;
    let expected = super::separate_sweep::campaign(&job, campaign.shards)?;
    if expected != *campaign {
        return Err(Error::Other(format!(
            "{}: the scene's [sweep] does not give the sweep the parts record (points, definition \
             or satellites differ)",
            campaign.scene
        )));
    }
    let t = table(&job, realizations)?;
    let dir = out.map_or_else(
        || super::separate_sweep::default_dir(scene),
        Path::to_path_buf,
    );
    super::separate_sweep::finish(p, &t, &dir)
}
