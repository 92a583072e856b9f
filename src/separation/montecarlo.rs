//! Monte Carlo of the release: N runs of the model with the dispersions declared in
//! `[separation.dispersion]` (spring stiffness, lateral CG offset, clearance, friction, release
//! skew), in parallel with rayon.
//!
//! Determinism: run i draws from its own ChaCha8 stream (seed = the user's seed, stream = i),
//! so a run's inputs never depend on which thread ran it or in what order; results are
//! collected in run order and the percentiles are computed from sorted values. The output is
//! therefore identical for any thread count. Normal deviates use Box–Muller on the stream's
//! uniform doubles (rand_distr is not a dependency; two lines do).

use super::params::Model;
use super::sim::{RunOptions, run};
use crate::error::SeparationError;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;

/// Percentiles (linear interpolation between order statistics, as numpy's default).
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Percentiles {
    /// Lower 99.73% bound (P0.27).
    pub p0_27: f64,
    pub p1: f64,
    pub p50: f64,
    pub p99: f64,
    /// Upper 99.73% bound.
    pub p99_73: f64,
}

impl Percentiles {
    pub fn of(values: &[f64]) -> Percentiles {
        let mut v: Vec<f64> = values.to_vec();
        v.sort_by(f64::total_cmp);
        let q = |p: f64| -> f64 {
            if v.is_empty() {
                return f64::NAN;
            }
            let x = p / 100.0 * (v.len() - 1) as f64;
            let i = x.floor() as usize;
            let j = (i + 1).min(v.len() - 1);
            v[i] + (x - i as f64) * (v[j] - v[i])
        };
        Percentiles {
            p0_27: q(0.27),
            p1: q(1.0),
            p50: q(50.0),
            p99: q(99.0),
            p99_73: q(99.73),
        }
    }
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SatelliteSpread {
    pub index: usize,
    pub final_speed_m_s: Percentiles,
    pub tip_off_rate_deg_s: Percentiles,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MonteCarloResult {
    pub runs: usize,
    pub seed: u64,
    pub satellites: Vec<SatelliteSpread>,
    /// Over all satellites and runs.
    pub final_speed_m_s: Percentiles,
    pub tip_off_rate_deg_s: Percentiles,
    /// Smallest inter-satellite clearance of each run.
    pub min_clearance_m: Percentiles,
    /// Total integrator steps over all runs.
    pub steps: usize,
    /// The samples behind the percentiles (exit speeds and tip-off rates of every satellite
    /// and run, in run order; minimum clearance per run), for histograms.
    pub samples_final_speed_m_s: Vec<f64>,
    pub samples_tip_off_rate_deg_s: Vec<f64>,
    pub samples_min_clearance_m: Vec<f64>,
}

struct Draw {
    rng: ChaCha8Rng,
}

impl Draw {
    fn new(seed: u64, run: u64) -> Draw {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(run);
        Draw { rng }
    }
    /// Uniform in [0, 1) from the top 53 bits.
    fn uniform(&mut self) -> f64 {
        (self.rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

/// The model of run `i`: the nominal model with every dispersion drawn from stream `i`.
pub fn dispersed(model: &Model, seed: u64, i: u64) -> Model {
    let mut m = model.clone();
    let d = model.dispersion.clone();
    let mut r = Draw::new(seed, i);
    // Draw in a fixed order whatever is enabled, so enabling one dispersion never shifts
    // another's numbers.
    for s in m.springs.iter_mut() {
        let z = r.normal();
        s.stiffness_n_m *= (1.0 + d.spring_stiffness_sigma * z).max(0.05);
    }
    for s in m.satellites.iter_mut() {
        let (zx, zy) = (r.normal(), r.normal());
        s.cg_offset_m[0] += d.cg_offset_sigma_m * zx;
        s.cg_offset_m[1] += d.cg_offset_sigma_m * zy;
    }
    let u = r.uniform();
    if let Some([a, b]) = d.clearance_range_m {
        m.clearance_m = a + (b - a) * u;
    }
    let u = r.uniform();
    if let Some([a, b]) = d.friction_range {
        m.contact.friction = a + (b - a) * u;
    }
    for t in m.release_times_s.iter_mut() {
        let z = r.normal();
        if let Some(t) = t.as_mut() {
            *t = (*t + d.release_skew_sigma_s * z).max(model.unlock_time_s);
        }
    }
    m
}

/// What one dispersed run contributes to the Monte Carlo: per-satellite exit speed and tip-off
/// rate, the run's minimum clearance and its step count. Shards exchange these, so a merge
/// rebuilds exactly the sample a single machine would have.
#[derive(Debug, Clone, PartialEq)]
pub struct Realization {
    pub index: u64,
    pub final_speed_m_s: Vec<f64>,
    pub tip_off_rate_deg_s: Vec<f64>,
    pub min_clearance_m: Option<f64>,
    pub steps: usize,
}

/// Run `i` of the Monte Carlo: its random stream depends only on (`seed`, `i`), so any machine
/// computes the same realization.
pub fn realize(model: &Model, seed: u64, i: u64) -> Result<Realization, SeparationError> {
    let r = run(&dispersed(model, seed, i), &RunOptions::default()).map_err(|e| match e {
        SeparationError::NonFinite { time_s, body } => SeparationError::NonFinite {
            time_s,
            body: format!("{body} (Monte Carlo run {i}, seed {seed})"),
        },
        other => SeparationError::Invalid(format!("Monte Carlo run {i} (seed {seed}): {other}")),
    })?;
    Ok(Realization {
        index: i,
        final_speed_m_s: r.satellites.iter().map(|s| s.final_speed_m_s).collect(),
        tip_off_rate_deg_s: r.satellites.iter().map(|s| s.final_rate_deg_s).collect(),
        min_clearance_m: r.min_clearance_m,
        steps: r.stats.steps,
    })
}

/// The realizations with indices in `range`, in parallel (rayon's current pool), in index order.
pub fn realizations(
    model: &Model,
    seed: u64,
    range: std::ops::Range<u64>,
) -> Result<Vec<Realization>, SeparationError> {
    range
        .into_par_iter()
        .map(|i| realize(model, seed, i))
        .collect()
}

/// Runs `runs` dispersed releases in parallel (rayon's current pool).
pub fn monte_carlo(
    model: &Model,
    runs: usize,
    seed: u64,
) -> Result<MonteCarloResult, SeparationError> {
    let results = realizations(model, seed, 0..runs as u64)?;
    Ok(aggregate(seed, model.n_satellites(), &results))
}

/// Percentiles and samples of realizations `0..results.len()` given in index order. The sums and
/// sorted order statistics depend only on the values, never on where they were computed.
pub fn aggregate(seed: u64, n_satellites: usize, results: &[Realization]) -> MonteCarloResult {
    let mut all_speed = Vec::new();
    let mut all_rate = Vec::new();
    let satellites = (0..n_satellites)
        .map(|i| {
            let sp: Vec<f64> = results.iter().map(|r| r.final_speed_m_s[i]).collect();
            let rt: Vec<f64> = results.iter().map(|r| r.tip_off_rate_deg_s[i]).collect();
            all_speed.extend_from_slice(&sp);
            all_rate.extend_from_slice(&rt);
            SatelliteSpread {
                index: i + 1,
                final_speed_m_s: Percentiles::of(&sp),
                tip_off_rate_deg_s: Percentiles::of(&rt),
            }
        })
        .collect();
    let clear: Vec<f64> = results.iter().filter_map(|r| r.min_clearance_m).collect();
    MonteCarloResult {
        runs: results.len(),
        seed,
        satellites,
        final_speed_m_s: Percentiles::of(&all_speed),
        tip_off_rate_deg_s: Percentiles::of(&all_rate),
        min_clearance_m: Percentiles::of(&clear),
        steps: results.iter().map(|r| r.steps).sum(),
        samples_final_speed_m_s: all_speed,
        samples_tip_off_rate_deg_s: all_rate,
        samples_min_clearance_m: clear,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_like_numpy() {
        // numpy.percentile(range(101), [1, 50, 99]) = 1, 50, 99; P0.27 of 0..100 = 0.27.
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        let p = Percentiles::of(&v);
        assert_eq!((p.p1, p.p50, p.p99), (1.0, 50.0, 99.0));
        assert!((p.p0_27 - 0.27).abs() < 1e-12 && (p.p99_73 - 99.73).abs() < 1e-12);
    }
}
