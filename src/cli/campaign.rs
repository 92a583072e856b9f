//! `satqual campaign SCENE --slurm --shards K [--monte-carlo N --seed S] [--partition P]
//! [--time T] [--cpus C] [--dir DIR]`: writes the Slurm array script of a sharded Monte Carlo
//! (or, for a scene with `[sweep]`, of its sweep) and its merge job, and prints the two
//! commands that submit them.

use super::{Outcome, Printer};
use satqual::Error;
use satqual::campaign::slurm::{self, Plan};
use satqual::report::write_atomic;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with [stack] and [separation].
    pub scene: PathBuf,
    /// Write Slurm scripts (the only scheduler with a script writer; others run
    /// `separate --shards K` with their array index, see docs/campaigns.md).
    #[arg(long, required = true)]
    pub slurm: bool,
    /// Number of shards (array tasks).
    #[arg(long)]
    pub shards: usize,
    /// Number of Monte Carlo runs (per sweep point); default [separation.dispersion] runs.
    #[arg(long)]
    pub monte_carlo: Option<usize>,
    /// Seed of the Monte Carlo streams; default [separation.dispersion] seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Slurm partition.
    #[arg(long)]
    pub partition: Option<String>,
    /// Time limit per task, in Slurm's format (e.g. 00:30:00).
    #[arg(long)]
    pub time: Option<String>,
    /// CPUs per shard (its rayon threads).
    #[arg(long, default_value_t = 1)]
    pub cpus: usize,
    /// Campaign folder for the scripts, parts, logs and result.
    #[arg(long, default_value = "campaign")]
    pub dir: PathBuf,
    /// Print the plan as JSON (scripts and commands).
    #[arg(long)]
    pub json: bool,
}

#[derive(serde::Serialize)]
struct Output {
    shards_script: PathBuf,
    merge_script: PathBuf,
    submit: [String; 2],
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    if args.shards == 0 || args.cpus == 0 {
        return Err(Error::Other(
            "--shards and --cpus must be at least 1".into(),
        ));
    }
    // Fail here, not on the cluster, when the scene does not load.
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let disp = satqual::pipeline::plan::dispersion_monte_carlo(&scene)?;
    let runs = args
        .monte_carlo
        .or(disp.as_ref().map(|m| m.runs))
        .unwrap_or(0);
    if runs == 0 {
        return Err(Error::Other(format!(
            "{}: no Monte Carlo runs: give --monte-carlo N or [separation.dispersion] runs",
            args.scene.display()
        )));
    }
    satqual::pipeline::plan::check_runs(&scene, runs, "--monte-carlo")?;
    let cwd = std::env::current_dir().map_err(|e| Error::io(".", e))?;
    let exe = std::env::current_exe().map_err(|e| Error::io("satqual", e))?;
    let dir = cwd.join(&args.dir);
    let plan = Plan {
        exe,
        workdir: cwd,
        scene: args.scene.display().to_string(),
        runs,
        seed: args
            .seed
            .unwrap_or(satqual::pipeline::plan::dispersion_seed(&scene)),
        shards: args.shards,
        dir: dir.clone(),
        partition: args.partition,
        time: args.time,
        cpus: args.cpus,
        sweep: scene.file.sweep.is_some(),
    };
    for sub in ["parts", "logs"] {
        let d = dir.join(sub);
        std::fs::create_dir_all(&d).map_err(|e| Error::io(&d, e))?;
    }
    let shards = dir.join("shards.sbatch");
    let merge = dir.join("merge.sbatch");
    write(&shards, &slurm::shards_script(&plan))?;
    write(&merge, &slurm::merge_script(&plan))?;
    let submit = slurm::submit_commands(&plan);
    p.human(&format!(
        "wrote {} ({} shards) and {}; submit with:\n{}\n{}",
        shards.display(),
        plan.shards,
        merge.display(),
        submit[0],
        submit[1]
    ));
    p.json(&Output {
        shards_script: shards,
        merge_script: merge,
        submit,
    })?;
    Ok(Outcome::Pass)
}

fn write(path: &Path, text: &str) -> Result<(), Error> {
    write_atomic(path, text.as_bytes())
}
