//! `satqual separate SCENE --sweep [--monte-carlo N --seed S] [--out DIR | --shard I/K --out PART]`:
//! the scene's `[sweep]`, one Monte Carlo per point, written as a report folder; with a shard,
//! only that shard's work units, as a part file that `satqual merge` joins into the same folder.

use super::{Outcome, Printer};
use satqual::Error;
use satqual::pipeline::fnv1a;
use satqual::pipeline::param_sweep::{SweepJob, realize_units, table};
use satqual::report::write_atomic;
use satqual::results::SweepTable;
use satqual::separation::shard::{Campaign, Part, Shard, SweepTag};
use satqual::spec::Scene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

pub fn run(
    args: &super::separate::Args,
    p: &Printer,
    scene: &Scene,
    shard: Option<Shard>,
) -> Result<Outcome, Error> {
    let disp = satqual::pipeline::plan::dispersion_monte_carlo(scene)?;
    let runs = args
        .monte_carlo
        .or(disp.as_ref().map(|m| m.runs))
        .unwrap_or(0);
    let seed = args
        .seed
        .unwrap_or(satqual::pipeline::plan::dispersion_seed(scene));
    let job = SweepJob::new(scene, runs, seed)?;
    if let Some(shard) = shard {
        let out = args.out.as_deref().unwrap_or(Path::new("part.json"));
        return run_shard(p, &job, shard, out);
    }
    let all = realize_units(&job, 0..job.units() as u64)?;
    let t = table(&job, &all)?;
    let dir = args.out.clone().unwrap_or_else(|| default_dir(scene));
    finish(p, &t, &dir)
}

/// `reports/<scene>/sweep`.
pub fn default_dir(scene: &Scene) -> PathBuf {
    Path::new("reports").join(scene.name()).join("sweep")
}

/// What identifies this sweep in its part files.
pub fn campaign(job: &SweepJob, shards: usize) -> Result<Campaign, Error> {
    let definition = toml::to_string(job.spec).map_err(|e| Error::Other(e.to_string()))?;
    Ok(Campaign {
        scene: job.base.path.display().to_string(),
        scene_hash: fnv1a(&job.base.text),
        seed: job.seed,
        runs: job.runs,
        shards,
        satellites: job.satellites,
        sweep: Some(SweepTag {
            points: job.points(),
            definition,
        }),
    })
}

fn run_shard(p: &Printer, job: &SweepJob, shard: Shard, out: &Path) -> Result<Outcome, Error> {
    let range = shard.range(job.units());
    let results = realize_units(job, range.clone())?;
    let part = Part::new(campaign(job, shard.count)?, shard, &results);
    let text = serde_json::to_string(&part).map_err(|e| Error::Other(e.to_string()))?;
    write_atomic(out, format!("{text}\n").as_bytes())?;
    p.human(&format!(
        "sweep shard {}/{} of {}: units {}..{} of {} points × {} runs (seed {}) written to {}",
        shard.index,
        shard.count,
        job.base.name(),
        range.start,
        range.end,
        job.points(),
        job.runs,
        job.seed,
        out.display()
    ));
    p.json(&part)?;
    Ok(Outcome::Pass)
}

/// Writes the report folder and prints the summary; `merge` ends here too, so a merged sweep
/// prints and writes what one machine would. A sweep maps where the gates pass: it ends with
/// `Pass` once written, whatever its points' verdicts.
pub fn finish(p: &Printer, t: &SweepTable, dir: &Path) -> Result<Outcome, Error> {
    satqual::report::sweep::write(dir, t)?;
    let failed = t.points.iter().filter(|q| !q.pass).count();
    let mut s = format!(
        "sweep of {}: {} points × {} runs (seed {}); {failed} points fail a gate\n  point  {}  speed P0.27  rate P99.73  verdict\n",
        t.scene,
        t.points.len(),
        t.runs,
        t.seed,
        t.keys.join("  ")
    );
    for q in &t.points {
        let values: Vec<String> = q.values.iter().map(|v| format!("{v}")).collect();
        let _ = writeln!(
            s,
            "  {:>5}  {}  {:>11.4}  {:>11.3}  {}",
            q.point,
            values.join("  "),
            q.final_speed_m_s.p0_27.value,
            q.tip_off_rate_deg_s.p99_73.value,
            if q.pass { "pass" } else { "FAIL" }
        );
    }
    let _ = write!(s, "report: {}", dir.join("report.html").display());
    p.human(&s);
    p.json(t)?;
    Ok(Outcome::Pass)
}
