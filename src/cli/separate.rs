//! `satqual separate SCENE [--monte-carlo N --seed S] [--out DIR] [--json]`: the in-orbit
//! release of a `[stack]` + `[separation]` scene, and optionally a seeded Monte Carlo.
//! With `--shard I/K` (or `--shards K` and an array-job index in the environment) it computes
//! only shard I's realizations and writes them to the part file `--out`; `satqual merge`
//! joins the parts. With `--sweep` it runs the scene's `[sweep]` instead (`separate_sweep`).

use super::progress::Progress;
use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::fnv1a;
use satqual::pipeline::plan::MonteCarloPlan;
use satqual::pipeline::workflows::{self, separate::SeparateRequest, separate::SeparateRun};
use satqual::report::write_atomic;
use satqual::separation::shard::{self, Campaign, Part, Shard};
use satqual::separation::{self, Model, SeparationResult};
use satqual::spec::Scene;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML) with [stack] and [separation].
    pub scene: PathBuf,
    /// Number of dispersed Monte Carlo runs (dispersions from [separation.dispersion]).
    #[arg(long, requires = "seed", value_parser = at_least_one_run)]
    pub monte_carlo: Option<usize>,
    /// Seed of the Monte Carlo streams.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Write CSV histories of the nominal run to this folder; with a shard, the part file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Compute only shard I of K (0-based) of the Monte Carlo (or of the sweep's units) and
    /// write it to `--out`.
    #[arg(long, value_name = "I/K", requires = "out")]
    pub shard: Option<String>,
    /// Shard count K when the index comes from the environment (SATQUAL_SHARD_INDEX,
    /// SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX or JOB_COMPLETION_INDEX, the first set).
    #[arg(long, value_name = "K", conflicts_with = "shard", requires = "out")]
    pub shards: Option<usize>,
    /// Read the shard index from this environment variable instead.
    #[arg(long, value_name = "VAR", requires = "shards")]
    pub shard_env: Option<String>,
    /// Run the scene's [sweep]: a Monte Carlo per point (runs and seed from --monte-carlo and
    /// --seed, else [separation.dispersion]); `--out` is the report folder (default
    /// reports/<scene>/sweep), or the part file with a shard.
    #[arg(long)]
    pub sweep: bool,
    /// Print the machine-readable result to stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Serialize)]
pub(super) struct Output<'a> {
    pub(super) scene: String,
    #[serde(flatten)]
    pub(super) result: &'a SeparationResult,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) monte_carlo: Option<&'a separation::MonteCarloResult>,
}

/// `--monte-carlo 0` would print percentiles of no sample.
fn at_least_one_run(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("a Monte Carlo needs at least 1 run".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}

pub fn run(args: Args) -> Result<Outcome, Error> {
    let p = Printer::new(args.json);
    let scene = satqual::spec::Scene::load(&args.scene)?;
    let shard = shard::resolve(
        args.shard.as_deref(),
        args.shards,
        args.shard_env.as_deref(),
        |n| std::env::var(n).ok(),
    )?;
    if args.sweep {
        return super::separate_sweep::run(&args, &p, &scene, shard);
    }
    if let Some(shard) = shard {
        let (Some(runs), Some(out)) = (args.monte_carlo, &args.out) else {
            return Err(Error::Other(
                "a shard needs --monte-carlo N --seed S and --out PART (or --sweep)".into(),
            ));
        };
        return run_shard(&p, &scene, shard, runs, args.seed.unwrap_or(0), out);
    }
    let req = SeparateRequest {
        record_history: args.out.is_some(),
        release_shock: args.out.is_some(),
        monte_carlo: args.monte_carlo.map(|runs| MonteCarloPlan {
            runs,
            seed: args.seed.unwrap_or(0),
        }),
    };
    let SeparateRun {
        result,
        monte_carlo: mc,
        ..
    } = {
        let progress = Progress::start(args.quiet, args.json, "separation");
        workflows::separate::run(&scene, &req, &progress)?
    };
    if let (Some(dir), Some(h)) = (&args.out, &result.history) {
        write_histories(dir, h)?;
    }
    if let (Some(dir), Some(shock)) = (&args.out, &result.shock) {
        super::separate_shock::write_csv(dir, shock)?;
    }
    print(&p, &scene, &result, mc.as_ref())?;
    Ok(Outcome::Pass)
}

/// Shard `shard` of an `runs`-run Monte Carlo: its realizations, written as a part file.
fn run_shard(
    p: &Printer,
    scene: &Scene,
    shard: Shard,
    runs: usize,
    seed: u64,
    out: &Path,
) -> Result<Outcome, Error> {
    satqual::pipeline::plan::check_runs(scene, runs, "--monte-carlo")?;
    let model = Model::from_scene(scene)?;
    let range = shard.range(runs);
    let results = separation::montecarlo::realizations(&model, seed, range.clone())?;
    let campaign = Campaign {
        scene: scene.path.display().to_string(),
        scene_hash: fnv1a(&scene.text),
        seed,
        runs,
        shards: shard.count,
        satellites: model.n_satellites(),
        sweep: None,
    };
    let part = Part::new(campaign, shard, &results);
    let text = serde_json::to_string(&part).map_err(|e| Error::Other(e.to_string()))?;
    write_atomic(out, format!("{text}\n").as_bytes())?;
    p.human(&format!(
        "shard {}/{} of {}: runs {}..{} (seed {seed}) written to {}",
        shard.index,
        shard.count,
        scene.name(),
        range.start,
        range.end,
        out.display()
    ));
    p.json(&part)?;
    Ok(Outcome::Pass)
}

/// The human summary and the JSON of a separation run; `merge` prints through it too, so a
/// merged campaign's output is the single-machine output byte for byte.
pub(super) fn print(
    p: &Printer,
    scene: &Scene,
    result: &SeparationResult,
    mc: Option<&separation::MonteCarloResult>,
) -> Result<(), Error> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "separation of {} ({} satellites)",
        scene.name(),
        result.satellites.len()
    );
    let _ = writeln!(
        s,
        "  sat  release_s  max_speed  final_speed  final_rate  exit_time_s  contacts"
    );
    for r in &result.satellites {
        let _ = writeln!(
            s,
            "  {:>3}  {:>9}  {:>9.4}  {:>11.4}  {:>10.3}  {:>11}  {:>8}",
            r.index,
            r.release_time_s
                .map_or("never".into(), |t| format!("{t:.3}")),
            r.max_speed_m_s,
            r.final_speed_m_s,
            r.final_rate_deg_s,
            r.exit_time_s
                .map_or("on bars".into(), |t| format!("{t:.3}")),
            r.contacts
        );
    }
    let _ = writeln!(s, "  speeds in m/s, rates in deg/s at bar exit");
    // A wedged satellite's "final" speed is the one it had when the run ended on the bars.
    for r in result.satellites.iter().filter(|r| r.wedged) {
        let _ = match &r.stall {
            Some(st) => writeln!(
                s,
                "  satellite {} wedged in the bars: {}",
                r.index,
                st.describe()
            ),
            None => writeln!(
                s,
                "  satellite {} has not left the bars when the run ends (speed {:.4} m/s)",
                r.index, r.final_speed_m_s
            ),
        };
    }
    let _ = writeln!(
        s,
        "  energy residual {:.3e} of the spring energy (max over the run {:.3e}); {} steps, {} RHS evaluations",
        result.energy.relative_residual,
        result.energy.max_relative_residual,
        result.stats.steps,
        result.stats.rhs_evals
    );
    if let Some(c) = result.min_clearance_m {
        let _ = writeln!(s, "  minimum inter-satellite clearance {c:.4} m");
    }
    // The clearance gate projects a pair still closing at the end to touch in free flight.
    for p in result
        .pair_clearances
        .iter()
        .filter(|p| p.apart_time_s.is_none() && p.closing_speed_m_s > 0.0)
    {
        let _ = writeln!(
            s,
            "  satellites {} and {} still closing at {:.1} mm/s at the end ({:.4} m apart): they meet in free flight about {:.0} s later",
            p.upper,
            p.upper + 1,
            p.closing_speed_m_s * 1e3,
            p.final_gap_m,
            p.final_gap_m.max(0.0) / p.closing_speed_m_s
        );
    }
    if let Some(shock) = &result.shock {
        super::separate_shock::summary(&mut s, shock);
    }
    if let Some(mc) = mc {
        let _ = writeln!(
            s,
            "  Monte Carlo {} runs (seed {}): final speed P1 {:.4} P50 {:.4} P99 {:.4} P99.73 {:.4} m/s; tip-off rate P99.73 {:.3} deg/s; min clearance P0.27 {}",
            mc.runs,
            mc.seed,
            mc.final_speed_m_s.p1.value,
            mc.final_speed_m_s.p50.value,
            mc.final_speed_m_s.p99.value,
            mc.final_speed_m_s.p99_73.value,
            mc.tip_off_rate_deg_s.p99_73.value,
            mc.min_clearance_m.as_ref().map_or_else(
                || "n/a (one satellite, no pair)".to_string(),
                |c| format!("{:.4} m", c.p0_27.value)
            )
        );
        bounds_line(&mut s, mc);
    }
    p.human(s.trim_end());
    for w in &result.warnings {
        eprintln!("warning: {}: {w}", scene.path.display());
    }
    p.json(&Output {
        scene: scene.path.display().to_string(),
        result,
        monte_carlo: mc,
    })
}

/// What the runs demonstrate: the per-run bounds at the scene's probability and confidence.
fn bounds_line(s: &mut String, mc: &separation::MonteCarloResult) {
    let b = &mc.bounds;
    let Some(speed) = &b.slowest_exit_speed_m_s else {
        return;
    };
    let shown = if speed.demonstrated {
        "demonstrated".to_string()
    } else {
        format!(
            "NOT demonstrated: {} runs support at most {:.4}; need {}",
            speed.runs, speed.demonstrated_probability, speed.runs_needed
        )
    };
    let value = |t: &Option<separation::montecarlo::TailBound>| {
        t.map_or("–".to_string(), |t| format!("{:.4}", t.value))
    };
    let _ = writeln!(
        s,
        "  bounds at probability {} / confidence {} ({shown}): slowest exit {:.4} m/s, highest tip-off {} deg/s, smallest clearance {} m; {} runs with a wedged satellite (per-run wedging probability below {:.3}% at that confidence)",
        mc.probability,
        mc.confidence,
        speed.value,
        value(&b.highest_tip_off_rate_deg_s),
        value(&b.min_clearance_m),
        b.runs_with_wedging,
        100.0 * b.wedging_probability_bound
    );
    if b.runs_cut_short > 0 {
        let _ = writeln!(
            s,
            "  {} of them only because the run ended with a satellite still sliding on the bars: raise separation.max_time_s",
            b.runs_cut_short
        );
    }
}

fn write_histories(dir: &Path, h: &separation::History) -> Result<(), Error> {
    for (i, rows) in h.satellites.iter().enumerate() {
        let mut s = String::from(
            "time_s,x_m,y_m,z_m,vx_m_s,vy_m_s,vz_m_s,speed_m_s,wx_deg_s,wy_deg_s,wz_deg_s,rate_deg_s\n",
        );
        for (t, r) in h.times_s.iter().zip(rows) {
            let _ = write!(s, "{t}");
            for v in r {
                let _ = write!(s, ",{v}");
            }
            s.push('\n');
        }
        write_atomic(&dir.join(format!("satellite-{}.csv", i + 1)), s.as_bytes())?;
    }
    let mut s = String::from(
        "time_s,spring_work_j,kinetic_j,bar_j,contact_elastic_j,losses_j,residual_j\n",
    );
    for (t, r) in h.times_s.iter().zip(&h.energy) {
        let _ = write!(s, "{t}");
        for v in r {
            let _ = write!(s, ",{v}");
        }
        s.push('\n');
    }
    write_atomic(&dir.join("energy.csv"), s.as_bytes())
}
