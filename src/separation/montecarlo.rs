//! Monte Carlo of the release: N runs of the model with the dispersions declared in
//! `[separation.dispersion]` (spring stiffness, lateral CG offset, clearance, friction, release
//! skew), in parallel with rayon.
//!
//! Determinism: run i draws from its own ChaCha8 stream (seed = the user's seed, stream = i),
//! so a run's inputs never depend on which thread ran it or in what order; results are
//! collected in run order and the percentiles are computed from sorted values. The output is
//! therefore identical for any thread count. Normal deviates use Box–Muller on the stream's
//! uniform doubles (rand_distr is not a dependency; two lines do).

use super::order_stats;
use super::params::Model;
use super::sim::{RunOptions, run};
use crate::error::SeparationError;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;

/// One percentile of a sample with its distribution-free confidence interval.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Percentile {
    /// The quantile's probability, e.g. 0.0027 for P0.27.
    pub p: f64,
    /// The sample percentile (linear interpolation between order statistics, as numpy's
    /// default).
    pub value: f64,
    /// Equal-tailed interval of the true quantile from order statistics
    /// (`order_stats::quantile_ci_ranks`); `None` (null) where no sample is far enough out to
    /// bound that side at this confidence.
    pub ci_low: Option<f64>,
    pub ci_high: Option<f64>,
    pub confidence: f64,
    /// Monte Carlo runs behind it.
    pub runs: usize,
    /// Values behind it: the runs, or runs × satellites for a statistic pooled over the
    /// satellites (the satellites of one run share its friction and clearance, so a pooled
    /// interval treats correlated values as independent: read it as indicative; the gates use
    /// one value per run). 0: nothing to take a percentile of (e.g. the clearance of a single
    /// satellite), and then `value` is 0 and both interval ends are null.
    pub samples: usize,
}

/// The percentiles a launcher interface asks for (3σ two-sided, 1%) and the median.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Percentiles {
    /// Lower 99.73% bound (P0.27).
    pub p0_27: Percentile,
    pub p1: Percentile,
    pub p50: Percentile,
    pub p99: Percentile,
    /// Upper 99.73% bound.
    pub p99_73: Percentile,
}

impl Percentiles {
    /// The percentiles of `values` drawn from `runs` runs, with intervals at `confidence`.
    pub fn of(values: &[f64], runs: usize, confidence: f64) -> Percentiles {
        let mut v: Vec<f64> = values.to_vec();
        v.sort_by(f64::total_cmp);
        let rank = |r: Option<usize>| r.map(|r| v[r - 1]);
        let q = |pct: f64| -> Percentile {
            let p = pct / 100.0;
            let (value, (lo, hi)) = if v.is_empty() {
                (0.0, (None, None))
            } else {
                let x = p * (v.len() - 1) as f64;
                let i = x.floor() as usize;
                let j = (i + 1).min(v.len() - 1);
                let value = v[i] + (x - i as f64) * (v[j] - v[i]);
                (
                    value,
                    order_stats::quantile_ci_ranks(v.len(), p, confidence),
                )
            };
            Percentile {
                p,
                value,
                ci_low: rank(lo),
                ci_high: rank(hi),
                confidence,
                runs,
                samples: v.len(),
            }
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

/// Which tail a bound is of.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    Lower,
    Upper,
}

/// A one-sided tolerance bound from the order statistics of one value per run: the r-th
/// most extreme run bounds the `probability` quantile of the tail with `confidence`.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct TailBound {
    pub side: Side,
    /// The probability asked for ([separation.dispersion] probability).
    pub probability: f64,
    pub confidence: f64,
    pub runs: usize,
    /// Runs the probability needs at this confidence with zero exceedances (Wilks).
    pub runs_needed: usize,
    /// Whether the runs demonstrate the bound at `probability`.
    pub demonstrated: bool,
    /// The probability the bound holds at: `probability` when demonstrated, else the most the
    /// runs support at this confidence, (1 − C)^(1/n), with the extreme run as the bound.
    pub demonstrated_probability: f64,
    /// Rank of the order statistic used, from the extreme (1 = the most extreme run).
    pub rank: usize,
    /// The bound: that order statistic.
    pub value: f64,
}

impl TailBound {
    /// The bound of `values` (one per run) on `side`, at the demand's probability and
    /// confidence. `None` without values.
    pub fn of(values: &[f64], side: Side, demand: Demand) -> Option<TailBound> {
        let n = values.len();
        if n == 0 {
            return None;
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        if side == Side::Upper {
            v.reverse();
        }
        let rank = order_stats::bound_rank(n, demand.probability, demand.confidence);
        Some(TailBound {
            side,
            probability: demand.probability,
            confidence: demand.confidence,
            runs: n,
            runs_needed: order_stats::runs_needed(demand.probability, demand.confidence)
                .unwrap_or(usize::MAX),
            demonstrated: rank.is_some(),
            demonstrated_probability: match rank {
                Some(_) => demand.probability,
                None => order_stats::demonstrated_probability(n, demand.confidence),
            },
            rank: rank.unwrap_or(1),
            value: v[rank.unwrap_or(1) - 1],
        })
    }
}

/// What the Monte Carlo must demonstrate: `[separation.dispersion] probability, confidence`.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Demand {
    pub probability: f64,
    pub confidence: f64,
}

impl Demand {
    pub fn of(model: &Model) -> Demand {
        Demand {
            probability: model.dispersion.probability,
            confidence: model.dispersion.confidence,
        }
    }
}

/// The bounds the separation gates judge, one value per run: the slowest exit of the run,
/// its highest tip-off rate, its smallest inter-satellite clearance.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunBounds {
    pub slowest_exit_speed_m_s: Option<TailBound>,
    pub highest_tip_off_rate_deg_s: Option<TailBound>,
    pub min_clearance_m: Option<TailBound>,
    /// Runs in which at least one satellite wedged in the bars (stalled or never left).
    pub runs_with_wedging: usize,
    /// Of those, runs whose only "wedged" satellites were still sliding when the run ended:
    /// counted as wedged (the run does not show their exit), but the cure is a longer run.
    pub runs_cut_short: usize,
    /// The upper bound of the per-run wedging probability at the demanded confidence
    /// (Clopper–Pearson, [`order_stats::failure_probability_bound`]): what the runs show.
    pub wedging_probability_bound: f64,
    /// Every wedged satellite: run, satellite, and its speed at exit (or at the end).
    pub wedged: Vec<Wedged>,
}

/// A satellite that wedged in one Monte Carlo run.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Wedged {
    pub run: u64,
    pub satellite: usize,
    pub final_speed_m_s: f64,
    /// Still sliding up the bars when the run ended, rather than stalled.
    pub cut_short: bool,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MonteCarloResult {
    pub runs: usize,
    pub seed: u64,
    pub probability: f64,
    pub confidence: f64,
    pub satellites: Vec<SatelliteSpread>,
    /// Over all satellites and runs.
    pub final_speed_m_s: Percentiles,
    pub tip_off_rate_deg_s: Percentiles,
    /// Smallest inter-satellite clearance of each run (0 where a pair still closing at the
    /// end of the run is projected to touch in free flight); null for a single satellite,
    /// which has no pair.
    pub min_clearance_m: Option<Percentiles>,
    /// Tolerance bounds of the per-run worst values, for the gates.
    pub bounds: RunBounds,
    /// Total integrator steps over all runs.
    pub steps: usize,
    /// The samples behind the percentiles (exit speeds and tip-off rates of every satellite
    /// and run, satellite by satellite in run order; minimum clearance per run), for
    /// histograms.
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
    /// Per satellite: it wedged in the bars (stalled while engaged, or never left).
    pub wedged: Vec<bool>,
    /// Per satellite: it was still sliding up the bars when the run ended
    /// ([`SatelliteResult::cut_short`](crate::separation::SatelliteResult::cut_short)); it
    /// is also `wedged`, since the run cannot show its exit.
    pub cut_short: Vec<bool>,
    pub steps: usize,
}

impl Realization {
    /// Satellite `i` (0-based) was still sliding when the run ended (false where a part file
    /// written without this record says nothing).
    pub fn cut_short_at(&self, i: usize) -> bool {
        self.cut_short.get(i).copied().unwrap_or(false)
    }
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
        min_clearance_m: r.projected_min_clearance_m(),
        wedged: r.satellites.iter().map(|s| s.wedged).collect(),
        cut_short: r
            .satellites
            .iter()
            .map(|s| s.cut_short(model.stall_speed_m_s))
            .collect(),
        steps: r.stats.steps,
    })
}

/// The realizations with indices in `range`, in parallel (rayon's current pool), in index order.
pub fn realizations(
    model: &Model,
    seed: u64,
    range: std::ops::Range<u64>,
) -> Result<Vec<Realization>, SeparationError> {
    realizations_reporting(model, seed, range, &|_| {})
}

/// [`realizations`], calling `done(k)` as the k-th run of the range finishes (from the worker
/// that ran it, in completion order), for progress on long Monte Carlos.
pub fn realizations_reporting(
    model: &Model,
    seed: u64,
    range: std::ops::Range<u64>,
    done: &(dyn Fn(usize) + Sync),
) -> Result<Vec<Realization>, SeparationError> {
    let finished = std::sync::atomic::AtomicUsize::new(0);
    range
        .into_par_iter()
        .map(|i| {
            let r = realize(model, seed, i);
            done(finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            r
        })
        // Collected whole first: a failing run is reported by the lowest index, not by
        // whichever thread failed first.
        .collect::<Vec<_>>()
        .into_iter()
        .collect()
}

/// Runs `runs` dispersed releases in parallel (rayon's current pool).
pub fn monte_carlo(
    model: &Model,
    runs: usize,
    seed: u64,
) -> Result<MonteCarloResult, SeparationError> {
    monte_carlo_reporting(model, runs, seed, &|_| {})
}

/// [`monte_carlo`], reporting each finished run as [`realizations_reporting`] does.
pub fn monte_carlo_reporting(
    model: &Model,
    runs: usize,
    seed: u64,
    done: &(dyn Fn(usize) + Sync),
) -> Result<MonteCarloResult, SeparationError> {
    let results = realizations_reporting(model, seed, 0..runs as u64, done)?;
    Ok(aggregate(
        seed,
        model.n_satellites(),
        Demand::of(model),
        &results,
    ))
}

/// Percentiles, bounds and samples of realizations `0..results.len()` given in index order.
/// The sums and sorted order statistics depend only on the values, never on where they were
/// computed.
pub fn aggregate(
    seed: u64,
    n_satellites: usize,
    demand: Demand,
    results: &[Realization],
) -> MonteCarloResult {
    let runs = results.len();
    let c = demand.confidence;
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
                final_speed_m_s: Percentiles::of(&sp, runs, c),
                tip_off_rate_deg_s: Percentiles::of(&rt, runs, c),
            }
        })
        .collect();
    let clear: Vec<f64> = results.iter().filter_map(|r| r.min_clearance_m).collect();
    MonteCarloResult {
        runs,
        seed,
        probability: demand.probability,
        confidence: c,
        satellites,
        final_speed_m_s: Percentiles::of(&all_speed, runs, c),
        tip_off_rate_deg_s: Percentiles::of(&all_rate, runs, c),
        min_clearance_m: (!clear.is_empty()).then(|| Percentiles::of(&clear, runs, c)),
        bounds: run_bounds(demand, results, &clear),
        steps: results.iter().map(|r| r.steps).sum(),
        samples_final_speed_m_s: all_speed,
        samples_tip_off_rate_deg_s: all_rate,
        samples_min_clearance_m: clear,
    }
}

/// The tolerance bounds of each run's worst satellite and of its clearance.
fn run_bounds(demand: Demand, results: &[Realization], clearance: &[f64]) -> RunBounds {
    let worst = |v: &[f64], pick: fn(f64, f64) -> f64| v.iter().copied().reduce(pick);
    let slowest: Vec<f64> = results
        .iter()
        .filter_map(|r| worst(&r.final_speed_m_s, f64::min))
        .collect();
    let fastest_spin: Vec<f64> = results
        .iter()
        .filter_map(|r| worst(&r.tip_off_rate_deg_s, f64::max))
        .collect();
    let runs_with_wedging = results
        .iter()
        .filter(|r| r.wedged.iter().any(|&w| w))
        .count();
    let only_cut_short = |r: &&Realization| {
        let stalled = (0..r.wedged.len()).any(|i| r.wedged[i] && !r.cut_short_at(i));
        !stalled && r.cut_short.iter().any(|&c| c)
    };
    let runs_cut_short = results.iter().filter(only_cut_short).count();
    RunBounds {
        slowest_exit_speed_m_s: TailBound::of(&slowest, Side::Lower, demand),
        highest_tip_off_rate_deg_s: TailBound::of(&fastest_spin, Side::Upper, demand),
        min_clearance_m: TailBound::of(clearance, Side::Lower, demand),
        runs_with_wedging,
        runs_cut_short,
        wedging_probability_bound: order_stats::failure_probability_bound(
            runs_with_wedging,
            results.len(),
            demand.confidence,
        ),
        wedged: results
            .iter()
            .flat_map(|r| {
                (0..r.wedged.len())
                    .filter(|&i| r.wedged[i])
                    .map(|i| Wedged {
                        run: r.index,
                        satellite: i + 1,
                        final_speed_m_s: r.final_speed_m_s[i],
                        cut_short: r.cut_short_at(i),
                    })
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_like_numpy() {
        // numpy.percentile(range(101), [1, 50, 99]) = 1, 50, 99; P0.27 of 0..100 = 0.27.
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        let p = Percentiles::of(&v, 101, 0.95);
        assert_eq!((p.p1.value, p.p50.value, p.p99.value), (1.0, 50.0, 99.0));
        assert!((p.p0_27.value - 0.27).abs() < 1e-12 && (p.p99_73.value - 99.73).abs() < 1e-12);
        // The median's 95% interval of 101 samples: ranks 41 and 61 (binomial(101, ½):
        // F(40) = 0.0230 ≤ 0.025 < F(41) = 0.0364; F(60) = 0.9770 ≥ 0.975 > F(59) = 0.9636,
        // scipy.stats.binom.cdf), i.e. the values 40 and 60.
        assert_eq!((p.p50.ci_low, p.p50.ci_high), (Some(40.0), Some(60.0)));
        // 101 samples cannot bound P0.27 from below (F(0) = 0.9973¹⁰¹ = 0.761 > 0.025).
        assert_eq!(p.p0_27.ci_low, None);
    }

    /// The 59 runs of a 95/95 demand bound with their extreme; 58 do not, and then the bound
    /// reported is the extreme at the probability 58 runs support, 0.05^(1/58) = 0.949661.
    #[test]
    fn tail_bounds_use_the_wilks_rank_or_say_what_is_shown() {
        let demand = Demand {
            probability: 0.95,
            confidence: 0.95,
        };
        let v: Vec<f64> = (1..=59).map(f64::from).collect();
        let b = TailBound::of(&v, Side::Lower, demand).unwrap();
        assert!(b.demonstrated && b.rank == 1 && b.value == 1.0 && b.runs_needed == 59);
        let b = TailBound::of(&v[..58], Side::Upper, demand).unwrap();
        assert!(!b.demonstrated && b.value == 58.0);
        assert!((b.demonstrated_probability - 0.949_661).abs() < 1e-6);
        // 93 runs: the 2nd extreme (Wilks' second order, 95/95).
        let v: Vec<f64> = (1..=93).map(f64::from).collect();
        let b = TailBound::of(&v, Side::Upper, demand).unwrap();
        assert!(b.demonstrated && b.rank == 2 && b.value == 92.0);
    }
}
