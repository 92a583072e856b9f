//! Bands of the spectrum, each solved slice by slice on its own thread.
//!
//! # Parallel bands
//! With `fmax_hz`, bisection on the Sturm count cuts [0, (2π·fmax)²) into bands of about
//! [`BAND_MODES`] eigenvalues, and each band runs its own slices on its own thread (rayon).
//! Bands do not talk to each other: vectors of different bands are M-orthogonal because
//! their eigenvalues differ, and each band's counts prove it complete. The cuts depend only on
//! the model, so the result is byte-identical with any number of threads.

use super::csc::SymCsc;
use super::eigen::SparseStats;
use super::factor::{Pencil, factor_away_from_eigenvalue, point_in_gap};
use super::slice::{SLICE_MODES, run_slice};
use super::{Pair, SparseError};
use crate::error::ModalError;
use faer::Mat;

/// Modes aimed for per parallel band of the spectrum. A band's first slice starts with
/// nothing locked, yet on the 60-satellite stack bands of 150 cost no more CPU per mode than
/// bands of 400 (1.3–1.6 ms per mode either way, one thread), and the smaller bands balance
/// two threads better: the band holding the 289-fold cluster is the longest at ~0.7 s.
pub const BAND_MODES: usize = 150;

/// Cut points between bands of about [`BAND_MODES`] eigenvalues each: shifts in (low, top)
/// found by bisection on the Sturm count (one factorization per step, cheap next to the
/// eigen-solve), each with its count.
pub(super) fn band_edges(
    pencil: &Pencil,
    (low, c_low): (f64, usize),
    (top, c_top): (f64, usize),
    stats: &mut SparseStats,
) -> Result<Vec<(f64, usize)>, SparseError> {
    let nb = (c_top - c_low).div_ceil(BAND_MODES).max(1);
    // Bisect in frequency (√λ), where the stack's modes are spread more evenly. Each cut is
    // bisected on its own over the whole range, so the cuts run in parallel; each depends
    // only on its goal, never on the thread count.
    let f = |l: f64| l.max(0.0).sqrt();
    let slack = (c_top - c_low) / (4 * nb);
    use rayon::prelude::*;
    // Per cut: the edge found (if the count could be split) and the factorizations spent.
    type Cut = (Option<(f64, usize)>, usize);
    let cuts: Vec<Result<Cut, SparseError>> = (1..nb)
        .into_par_iter()
        .map(|j| {
            let goal = c_low + (c_top - c_low) * j / nb;
            let (mut lo, mut hi) = (f(low), f(top));
            let mut st = SparseStats::default();
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                let fac = factor_away_from_eigenvalue(pencil, mid * mid, &mut st)?;
                let c = fac.negative;
                if c.abs_diff(goal) <= slack {
                    // A cut is a partition point: moved into a gap of the spectrum.
                    let cut = point_in_gap(pencil, fac.sigma, &mut st)?;
                    return Ok((Some(cut), st.factorizations));
                }
                if c < goal {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            Ok((None, st.factorizations))
        })
        .collect();
    let mut edges = vec![(low, c_low)];
    for cut in cuts {
        let (best, factorizations) = cut?;
        stats.factorizations += factorizations;
        // A count that cannot be split (one huge cluster) just merges the bands.
        if let Some((sg, c)) = best
            && c > edges.last().expect("bottom").1
            && c < c_top
        {
            edges.push((sg, c));
        }
    }
    Ok(edges)
}

/// Every eigenpair in [bottom, upper) (or the lowest `target` − c(bottom) above bottom when
/// there is no upper edge), slice by slice from the bottom edge up.
pub(super) fn run_band(
    m: &SymCsc,
    pencil: &Pencil,
    (bottom, c_bottom): (f64, usize),
    top_pair: Option<(f64, usize)>,
    target: usize,
    stats: &mut SparseStats,
    seed0: u64,
) -> Result<Vec<Pair>, SparseError> {
    let n = m.n;
    let (mut a, mut c_a) = (bottom, c_bottom);
    // Later shifts sit inside their slice. The first one too when eigenvalues lie below the
    // band (nothing is locked there yet): a shift on the bottom edge converges them as fast
    // as the band's own and wastes half the basis on them (measured on the 60-satellite
    // stack: 16 of 17 band starts ran the basis full). Half a slice in, by the band's mean
    // density; [`run_slice`] pulls the shift back if that holds more than a slice.
    let mut width = match top_pair {
        Some((ub, c_ub)) if c_bottom > 0 && c_ub > c_bottom => {
            (ub - bottom) * (SLICE_MODES as f64 / 2.0) / (c_ub - c_bottom) as f64
        }
        _ if c_bottom == 0 => first_slice_width(pencil, bottom, top_pair, target, stats)?,
        _ => 0.0,
    };
    let mut accepted: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut prev = Mat::<f64>::zeros(n, 0);
    let mut seed = seed0;
    let mut bufs = None;
    // Each slice accepts at least one mode or widens by up to 4×, so a band needs at most
    // one slice per mode plus the widenings across the whole double range; past that the
    // band has stopped advancing, which is an error, not a hang.
    let budget = target.saturating_sub(c_bottom) + MAX_EMPTY_SLICES;
    for _ in 0..=budget {
        stats.slices += 1;
        let out = run_slice(
            m,
            pencil,
            (a, c_a),
            width,
            &prev,
            top_pair,
            target.saturating_sub(c_a),
            stats,
            &mut seed,
            &mut bufs,
        )?;
        let found = out.pairs.len();
        prev = Mat::<f64>::from_fn(n, found, |i, j| out.pairs[j].1[i]);
        accepted.extend(out.pairs);
        // Aim the next shift at about half a slice of modes above the new edge.
        let ratio = (SLICE_MODES as f64 / found.max(1) as f64).clamp(0.25, 4.0);
        width = 0.5 * (out.b - a).max(0.0) * ratio;
        a = out.b;
        c_a = out.c_b;
        stats.sturm_sigma = out.b;
        stats.sturm_count = out.c_b;
        if c_a >= target || top_pair.is_some_and(|(ts, _)| out.b >= ts) {
            return Ok(accepted);
        }
    }
    Err(ModalError::NoConvergence(format!(
        "shift-invert Lanczos: the band above σ = {bottom:e} rad²/s² did not advance past σ = {a:e} rad²/s² ({c_a} of {target} modes) within {budget} slices"
    ))
    .into())
}

/// Width from the bottom of the spectrum's first band to its first Lanczos shift, chosen where
/// [0, s) holds between min(target, SLICE_MODES/2) and SLICE_MODES eigenvalues.
///
/// The bottom shift only has to lie below the spectrum, and is placed from the median
/// K_ii/M_ii: on a finely meshed beam that is ~1e6× further below the first eigenvalue than
/// the eigenvalue's own size, where 1/(λ − σ) no longer separates the lowest modes and the
/// slices stall (a 1000-element cantilever failed after 522 slices). Bisection on log σ with
/// the Sturm count costs a few factorizations; 0 (shift on the bottom edge) when no probe
/// lands in the window.
fn first_slice_width(
    pencil: &Pencil,
    bottom: f64,
    top_pair: Option<(f64, usize)>,
    target: usize,
    stats: &mut SparseStats,
) -> Result<f64, SparseError> {
    let want = target.clamp(1, SLICE_MODES / 2)..=SLICE_MODES;
    let scale = bottom.abs().max(f64::MIN_POSITIVE);
    let decades = 12.0 * std::f64::consts::LN_10;
    let (mut lo, mut hi) = (scale.ln() - decades, scale.ln() + decades);
    if let Some((ts, _)) = top_pair.filter(|t| t.0 > 0.0) {
        hi = hi.min(ts.ln());
        lo = lo.min(hi - decades);
    }
    let mut best = 0.0;
    let top_probe = hi;
    for _ in 0..FIRST_SHIFT_PROBES {
        let mid = 0.5 * (lo + hi);
        let fac = match factor_away_from_eigenvalue(pencil, mid.exp(), stats) {
            // A probe inside the round-off of rigid-body modes' zero (a band holding only
            // them): the top of the window, if it holds a slice, is a shift clear of it.
            Err(e @ SparseError::SingularNear { .. }) => {
                let fac = factor_away_from_eigenvalue(pencil, top_probe.exp(), stats)?;
                return match want.contains(&fac.negative) {
                    true => Ok(fac.sigma - bottom),
                    false => Err(e),
                };
            }
            other => other?,
        };
        let c = fac.negative;
        if want.contains(&c) {
            return Ok(fac.sigma - bottom);
        }
        if c < *want.start() {
            if c > 0 {
                best = fac.sigma - bottom;
            }
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(best)
}

/// Sturm probes spent placing the first shift: 24 decades bisected 10 times leave a window
/// of 0.02 decades, narrower than the gap between the first and the twelfth mode of any
/// model met so far.
const FIRST_SHIFT_PROBES: usize = 10;

/// Slices without a new mode a band may take: 4× widenings span 2^2046 (the whole double
/// range) in 512 steps.
const MAX_EMPTY_SLICES: usize = 512;

#[cfg(test)]
mod tests {
    use super::super::RESIDUAL_TOL;
    use super::super::testing::{chain, chain_eigenvalues, identity};
    use super::*;

    /// Bisection cuts 400 eigenvalues of a 600-mass chain into bands of about BAND_MODES:
    /// counts increase, each cut is within the slack of its goal, and every count is the
    /// number of analytic eigenvalues below its shift.
    #[test]
    fn band_edges_split_the_count_evenly() {
        let n = 600;
        let (k, m) = (chain(n, 1.0), identity(n));
        let pencil = Pencil::new(&k, Some(&m)).unwrap();
        let exact = chain_eigenvalues(n, 1.0);
        let top = 0.5 * (exact[399] + exact[400]);
        let mut stats = SparseStats::default();
        let edges = band_edges(&pencil, (-1e-6, 0), (top, 400), &mut stats).unwrap();
        let nb = 400usize.div_ceil(BAND_MODES);
        assert_eq!(edges.len(), nb);
        for (j, w) in edges.windows(2).enumerate() {
            assert!(w[1].1 > w[0].1);
            let goal = 400 * (j + 1) / nb;
            assert!(w[1].1.abs_diff(goal) <= 400 / (4 * nb));
        }
        for &(s, c) in &edges {
            assert_eq!(c, exact.iter().filter(|&&l| l < s).count());
        }
    }

    /// A band between two counted edges returns exactly its eigenvalues, each within the
    /// acceptance bound RESIDUAL_TOL·(top edge) of the analytic value.
    #[test]
    fn a_band_returns_exactly_its_eigenvalues() {
        let n = 300;
        let (k, m) = (chain(n, 1.0), identity(n));
        let pencil = Pencil::new(&k, Some(&m)).unwrap();
        let exact = chain_eigenvalues(n, 1.0);
        let (lo, hi) = (0.5 * (exact[29] + exact[30]), 0.5 * (exact[89] + exact[90]));
        let mut stats = SparseStats::default();
        let pairs = run_band(&m, &pencil, (lo, 30), Some((hi, 90)), 90, &mut stats, 1).unwrap();
        assert_eq!(pairs.len(), 60);
        let mut got: Vec<f64> = pairs.iter().map(|p| p.0).collect();
        got.sort_by(f64::total_cmp);
        for (l, want) in got.iter().zip(&exact[30..90]) {
            assert!((l - want).abs() <= RESIDUAL_TOL * hi, "{l} vs {want}");
        }
    }
}
