//! The work of a sweep: `points × runs` units, unit `u` being run `u mod runs` of point
//! `⌊u / runs⌋`. [`realize_units`] computes any contiguous block of them (a shard, or all);
//! [`table`] turns every unit's realization, in unit order, into one gated row per point.

use super::{Design, point};
use crate::error::Error;
use crate::gates;
use crate::pipeline::fnv1a;
use crate::results::{SweepPoint, SweepTable};
use crate::separation::montecarlo::{Demand, aggregate, realize};
use crate::separation::{Model, Realization};
use crate::spec::Scene;
use crate::spec::sweep::SweepSpec;
use rayon::prelude::*;
use std::ops::Range;

/// A sweep to run: the scene with its `[sweep]`, the design's points and the Monte Carlo of
/// each point.
pub struct SweepJob<'a> {
    pub base: &'a Scene,
    pub spec: &'a SweepSpec,
    pub design: Design,
    pub runs: usize,
    pub seed: u64,
    /// Satellites of the stack; every point must keep them.
    pub satellites: usize,
}

impl<'a> SweepJob<'a> {
    pub fn new(base: &'a Scene, runs: usize, seed: u64) -> Result<SweepJob<'a>, Error> {
        let spec = base.file.sweep.as_ref().ok_or_else(|| {
            Error::Other(format!(
                "{}: the scene has no [sweep] section",
                base.path.display()
            ))
        })?;
        if runs == 0 {
            return Err(Error::Other(format!(
                "{}: a sweep needs at least 1 Monte Carlo run per point \
                 (--monte-carlo N or [separation.dispersion] runs)",
                base.path.display()
            )));
        }
        crate::pipeline::plan::check_runs(base, runs, "--monte-carlo")?;
        let satellites = Model::from_scene(base)?.n_satellites();
        Ok(SweepJob {
            base,
            spec,
            design: Design::of(spec),
            runs,
            seed,
            satellites,
        })
    }

    pub fn points(&self) -> usize {
        self.design.points.len()
    }

    /// All work units: points × runs.
    pub fn units(&self) -> usize {
        self.points() * self.runs
    }

    /// The release model of point `p`.
    fn model(&self, p: usize) -> Result<Model, Error> {
        let scene = point::scene(self.base, &self.design, p)?;
        let model = Model::from_scene(&scene).map_err(|e| self.at(p, e))?;
        if model.n_satellites() != self.satellites {
            return Err(self.at(
                p,
                format!(
                    "the stack has {} satellites here and {} in the scene; a sweep compares one stack",
                    model.n_satellites(),
                    self.satellites
                ),
            ));
        }
        Ok(model)
    }

    fn at(&self, p: usize, e: impl std::fmt::Display) -> Error {
        Error::Other(format!(
            "{}: sweep point {p} ({}): {e}",
            self.base.path.display(),
            point::describe(&self.design, p)
        ))
    }
}

/// The realizations of units `range` in unit order (index = unit), in parallel.
pub fn realize_units(job: &SweepJob, range: Range<u64>) -> Result<Vec<Realization>, Error> {
    if range.is_empty() {
        return Ok(Vec::new());
    }
    let runs = job.runs as u64;
    let first = (range.start / runs) as usize;
    let last = ((range.end - 1) / runs) as usize;
    let models = in_order(
        (first..=last)
            .into_par_iter()
            .map(|p| job.model(p))
            .collect(),
    )?;
    in_order(
        range
            .into_par_iter()
            .map(|u| {
                let p = (u / runs) as usize;
                let r =
                    realize(&models[p - first], job.seed, u % runs).map_err(|e| job.at(p, e))?;
                Ok(Realization { index: u, ..r })
            })
            .collect(),
    )
}

/// The values, or the error of the first failed item in index order: a parallel collect into
/// a `Result` would return whichever error a thread met first, and the message would depend
/// on the thread count.
fn in_order<T>(items: Vec<Result<T, Error>>) -> Result<Vec<T>, Error> {
    items.into_iter().collect()
}

/// One row per point from the realizations of every unit, in unit order.
pub fn table(job: &SweepJob, realizations: &[Realization]) -> Result<SweepTable, Error> {
    if realizations.len() != job.units() {
        return Err(Error::Other(format!(
            "sweep table: {} realizations for {} units",
            realizations.len(),
            job.units()
        )));
    }
    let points = in_order(
        realizations
            .par_chunks(job.runs)
            .enumerate()
            .map(|(p, chunk)| row(job, p, chunk))
            .collect(),
    )?;
    Ok(SweepTable {
        scene: job.base.path.display().to_string(),
        scene_hash: fnv1a(&job.base.text),
        satqual_version: env!("CARGO_PKG_VERSION").into(),
        sweep: job.spec.clone(),
        keys: job.design.keys.clone(),
        runs: job.runs,
        seed: job.seed,
        points,
    })
}

/// Point `p`: its Monte Carlo percentiles and gates (limits from the point's own `[gates]`).
fn row(job: &SweepJob, p: usize, runs: &[Realization]) -> Result<SweepPoint, Error> {
    let scene = point::scene(job.base, &job.design, p)?;
    let limits = scene.file.gates.clone().unwrap_or_default();
    let demand = Demand::of(&Model::from_scene(&scene)?);
    let mc = aggregate(job.seed, job.satellites, demand, runs);
    let gates = gates::separation::monte_carlo(&mc, &limits);
    Ok(SweepPoint {
        point: p,
        values: job.design.points[p].clone(),
        runs: mc.runs,
        final_speed_m_s: mc.final_speed_m_s,
        tip_off_rate_deg_s: mc.tip_off_rate_deg_s,
        min_clearance_m: mc.min_clearance_m,
        steps: mc.steps,
        pass: gates.iter().all(|g| g.pass),
        gates,
    })
}
