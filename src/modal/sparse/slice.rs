//! One spectrum slice of the shift-invert block Lanczos.
//!
//! One run cannot hold hundreds of modes (the basis and re-orthogonalisation cost n·m²), so
//! the band is cut into slices, Grimes–Lewis–Simon style, each proven by Sturm counts:
//! 1. σ₀ < 0 below the whole spectrum (count 0; a negative shift also factors free-free models
//!    whose K is singular, and finds their rigid-body modes). It is the first slice's edge a.
//! 2. Above an edge a (count c(a), everything below found), the shift s sits inside the slice,
//!    about half a slice of modes above a (from the previous slice's density, or the band's
//!    for a band's first slice), and is counted too. Lanczos at s, deflated against the
//!    previous slice's vectors, converges eigenvalues on both sides of s.
//! 3. Once all c(s) − c(a) eigenvalues of [a, s) have converged and an unbroken run above s
//!    has too (about [`SLICE_MODES`] in all), the next edge b goes between the run's last
//!    eigenvalue and the next Ritz value, and K − bM is factored: if c(b) − c(a) equals the
//!    number of converged eigenvalues in [a, b), the slice is complete.
//! 4. If some are missing, typically copies of a repeated eigenvalue (the stack's columns
//!    repeat one local mode 4·N times), the run restarts with the converged vectors locked, a
//!    block as large as the number missing (a block of p vectors brings at most p copies of a
//!    multiple eigenvalue into the Krylov space), and the shift moved next to the unconverged
//!    Ritz values, i.e. to where the missing eigenvalues are.
//! 5. With `fmax_hz`, the band ends at (2π·fmax)², whose count was taken first; with `modes`
//!    only, at the first edge whose count reaches the number asked for.
//! 6. A restart that finds many copies missing at one place (more than two blocks) meets a
//!    cluster of repeated local modes: the 60-satellite stack repeats one column-joint mode
//!    289 times at 653 Hz. Two Sturm counts bracket it, and a subspace iteration as wide as
//!    the missing count, shifted just below it, takes it whole ([`cluster_pairs`]); restarted
//!    Lanczos would bring in one block per restart (measured: 1.4 s against 0.4 s).

use super::cluster::cluster_pairs;
use super::csc::SymCsc;
use super::eigen::SparseStats;
use super::factor::{
    Factor, Pencil, accurate_factor, factor_away_from_eigenvalue, factor_in_gap, point_in_gap,
};
use super::lanczos::{BLOCK, Lanczos, MAX_BASIS};
use super::{Pair, RESIDUAL_TOL, SparseError};
use crate::error::ModalError;
use faer::{Mat, MatRef};

/// Eigenvalues aimed for per spectrum slice. The re-orthogonalisation costs n·m² per slice for
/// a basis of m ≈ 4–8× this, so smaller slices are cheaper as long as the basis does not grow
/// relative to them (factorizations cost almost nothing on the stack): on the 60-satellite
/// stack 24 took 4.2 s of CPU against 4.6 s for 48 and 4.2 s for 16 (one thread).
pub const SLICE_MODES: usize = 24;
/// Restarts of one slice: each one locks what converged and aims at the missing eigenvalues
/// (a wide cluster of repeated modes goes to [`cluster_pairs`] instead).
pub const MAX_RESTARTS: usize = 64;

pub(super) struct SliceOut {
    /// The slice's eigenpairs: every eigenvalue in [a, b).
    pub(super) pairs: Vec<(f64, Vec<f64>)>,
    /// Upper edge and its Sturm count.
    pub(super) b: f64,
    pub(super) c_b: usize,
}

/// One spectrum slice above the edge a (count c(a), everything below found): Lanczos at a
/// shift s = a + width (counted too), so that eigenvalues on both sides of s converge; the
/// slice is complete when every eigenvalue of [a, s) and an unbroken run above s have
/// converged and the count at the new edge b matches.
#[allow(clippy::too_many_arguments)]
pub(super) fn run_slice(
    m: &SymCsc,
    pencil: &Pencil,
    (a, c_a): (f64, usize),
    width: f64,
    prev: &Mat<f64>,
    top: Option<(f64, usize)>,
    remaining: usize,
    stats: &mut SparseStats,
    seed: &mut u64,
    bufs: &mut Option<Mat<f64>>,
) -> Result<SliceOut, SparseError> {
    let n = m.n;
    let fac_s = slice_shift(pencil, (a, c_a), width, top, stats)?;
    let s = fac_s.sigma;
    let c_s = fac_s.negative;
    if c_s < c_a {
        return Err(mismatch(c_a, c_s, s));
    }
    // The Lanczos operator's factor: the partition point's own unless its solves are
    // inaccurate (then a shift next to it; s stays the counted point).
    let fac_op = accurate_factor(pencil, fac_s, stats)?;
    // Locked vectors: the previous slice's (the nearest below a) plus those converged here
    // before a restart.
    let mut locked = prev.clone();
    // M·locked, extended as vectors get locked rather than recomputed at every restart.
    let mut locked_m = m.mul(locked.as_ref());
    let mut in_slice: Vec<(f64, Vec<f64>)> = Vec::new();
    // The upper edge b once chosen: (b, c(b)).
    let mut edge: Option<(f64, usize)> = None;
    // A block of p random vectors brings at most p copies of a repeated eigenvalue into the
    // Krylov space: after a restart the block grows to the number still missing.
    let mut block = BLOCK;
    // After a restart the Lanczos shift moves next to the eigenvalues still missing (often a
    // cluster of repeated local modes far from s); s stays the counted partition point.
    let mut restart_fac: Option<Factor<'_>> = None;
    for restart in 0..MAX_RESTARTS {
        let cur = restart_fac.as_ref().unwrap_or(&fac_op);
        let sh = cur.sigma;
        let op = |_v: MatRef<'_, f64>, bv: MatRef<'_, f64>| {
            let mut w = bv.to_owned();
            cur.solve(w.as_mut());
            w
        };
        if restart > 0 {
            stats.restarts += 1;
        }
        let room = n.saturating_sub(locked.ncols());
        if room == 0 {
            break;
        }
        // A space no larger than a basis is taken whole, in one block: its Rayleigh–Ritz
        // pairs are exact, where blocks of 8 would stop short of it (a 12-unknown model
        // got one block of 8 per restart, and nothing converged).
        let p = if room <= MAX_BASIS {
            room
        } else {
            block.min(room)
        };
        let max_basis = (MAX_BASIS.min(room) / p).max(1) * p;
        *seed += 1;
        let mut lz = Lanczos::new(n, p, max_basis, locked.as_ref(), *seed, bufs);
        lz.start(m);
        stats.lanczos_vectors += p;
        let check_from = (SLICE_MODES.min(remaining) * 3 / 2).max(2 * p);
        let mut since_check = 0usize;
        loop {
            let more = lz.step(&op, m);
            stats.lanczos_vectors += p;
            since_check += 1;
            if more && (lz.blocks() * p < check_from || since_check < 3) {
                continue;
            }
            since_check = 0;
            let (theta, res, vecs) = lz.ritz()?;
            let ritz = ritz_eigenvalues(&theta, &res, sh, a);
            let conv_below = |lim: f64| -> Vec<usize> {
                ritz.iter()
                    .filter(|x| x.1 && x.0 < lim)
                    .map(|x| x.2)
                    .collect()
            };
            // The whole rest of the band converged?
            if let Some((ts, tc)) = top {
                let idx = conv_below(ts);
                let total = c_a + count_below(&in_slice, ts) + idx.len();
                if total == tc {
                    in_slice.extend(lz.vectors(&vecs, &idx, &theta, sh));
                    lz.recycle(bufs);
                    in_slice.retain(|x| x.0 < ts);
                    in_slice.sort_by(|x, y| x.0.total_cmp(&y.0));
                    return Ok(SliceOut {
                        pairs: in_slice,
                        b: ts,
                        c_b: tc,
                    });
                }
                if total > tc {
                    return Err(mismatch(tc, total, ts));
                }
            }
            let below_have = count_below(&in_slice, s) + conv_below(s).len();
            if below_have > c_s - c_a {
                return Err(mismatch(c_s, c_a + below_have, s));
            }
            if edge.is_none() && below_have == c_s - c_a {
                // Everything in [a, s) converged: extend the slice over the unbroken run
                // of converged eigenvalues above s.
                let above: Vec<(f64, bool, usize)> =
                    ritz.iter().copied().filter(|x| x.0 > s).collect();
                let run_end = unbroken_run(&above);
                let converged = run_end
                    .map(|e| above[..=e].iter().filter(|x| x.1).count())
                    .unwrap_or(0);
                let enough = below_have + converged >= SLICE_MODES.min(remaining);
                if enough || !more {
                    let b = edge_above_run(&above, run_end, s);
                    edge = Some(match top {
                        // The run reaches the band's top: the slice is the rest of the band,
                        // and copies of a cluster missing below the top are looked for like
                        // any others (left without an edge, the restarts would aim at s
                        // forever while the cluster waited above it).
                        Some(t) if b >= t.0 => t,
                        _ if b == s => (s, c_s),
                        _ => {
                            let at_b = point_in_gap(pencil, b, stats)?;
                            match top {
                                Some(t) if at_b.0 >= t.0 => t,
                                _ => at_b,
                            }
                        }
                    });
                }
            }
            if let Some((b, c_b)) = edge {
                let need = c_b.checked_sub(c_a).ok_or_else(|| mismatch(c_b, c_a, b))?;
                let idx = conv_below(b);
                let have = count_below(&in_slice, b) + idx.len();
                if have == need {
                    in_slice.extend(lz.vectors(&vecs, &idx, &theta, sh));
                    lz.recycle(bufs);
                    in_slice.retain(|x| x.0 < b);
                    in_slice.sort_by(|x, y| x.0.total_cmp(&y.0));
                    return Ok(SliceOut {
                        pairs: in_slice,
                        b,
                        c_b,
                    });
                }
                if have > need {
                    return Err(mismatch(c_b, c_a + have, b));
                }
            }
            let upper = edge.map(|e| e.0).unwrap_or(s);
            // A restart aimed at missing copies has done its job once about a block's worth
            // of them converged: lock them and aim again rather than fill the basis.
            let harvested = restart > 0 && conv_below(upper).len() + 2 >= p;
            if more && !harvested {
                continue;
            }
            // Basis full (or harvest done): lock what converged below the edge (or below s)
            // and restart for the missing ones.
            let got = lz.vectors(&vecs, &conv_below(upper), &theta, sh);
            lz.recycle(bufs);
            // The next shift: where the missing eigenvalues are.
            let target = restart_target(&ritz, (theta.as_slice(), res.as_slice()), upper, sh);
            lock(m, &mut locked, &mut locked_m, &got);
            in_slice.extend(got);
            let need = edge.map(|e| e.1).unwrap_or(c_s) - c_a;
            let mut missing = need.saturating_sub(count_below(&in_slice, upper));
            // Many copies missing at one place: a cluster of repeated local modes (the
            // stack's column joints repeat one mode 4·(N + 1) times). Restarted Lanczos brings
            // in a block's worth per restart; a subspace iteration as wide as the cluster
            // takes it whole.
            if missing > 2 * BLOCK
                && let Some(l) = target
            {
                *seed += 1;
                let more = cluster_pairs(
                    m,
                    pencil,
                    l,
                    (a, upper),
                    (locked.as_ref(), locked_m.as_ref()),
                    &in_slice,
                    stats,
                    *seed,
                )?;
                if !more.is_empty() {
                    stats.clusters += 1;
                    lock(m, &mut locked, &mut locked_m, &more);
                    in_slice.extend(more);
                    missing = need.saturating_sub(count_below(&in_slice, upper));
                }
            }
            // At most a fifth of the basis, so that a run still takes five block steps.
            block = (missing + 2).clamp(BLOCK, (MAX_BASIS / 5).max(BLOCK));
            let next = match target {
                Some(l) => {
                    let below = l - 1e-4 * l.abs().max(f64::MIN_POSITIVE);
                    let fac = factor_away_from_eigenvalue(pencil, below, stats)?;
                    Some(accurate_factor(pencil, fac, stats)?)
                }
                None => None,
            };
            restart_fac = next;
            break;
        }
    }
    Err(ModalError::NoConvergence(format!(
        "shift-invert Lanczos at σ = {s:e} rad²/s²: the slice above {a:e} did not complete after {MAX_RESTARTS} restarts"
    ))
    .into())
}

/// A Sturm-count mismatch at λ = `at`, reported in Hz.
fn mismatch(expected: usize, found: usize, at: f64) -> SparseError {
    let hz = |l: f64| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI);
    ModalError::SturmMismatch {
        expected,
        found,
        fmax_hz: hz(at),
    }
    .into()
}

/// The factored Lanczos shift of a slice: a + width (at most the band's top), pulled back
/// toward a while [a, s) holds more than a slice.
fn slice_shift<'a>(
    pencil: &'a Pencil,
    (a, c_a): (f64, usize),
    width: f64,
    top: Option<(f64, usize)>,
    stats: &mut SparseStats,
) -> Result<Factor<'a>, SparseError> {
    let mut s = a + width;
    if let Some((ts, _)) = top {
        s = s.min(ts);
    }
    let mut fac_s = factor_away_from_eigenvalue(pencil, s, stats)?;
    for _ in 0..20 {
        if fac_s.negative <= c_a + SLICE_MODES || fac_s.sigma <= a {
            break;
        }
        s = a + 0.5 * (fac_s.sigma - a);
        fac_s = factor_away_from_eigenvalue(pencil, s, stats)?;
    }
    // The shift partitions the slice too ([a, s) must be found whole): into a gap, but never
    // past the band's top, which is in one already.
    if fac_s.sigma > a {
        let moved = factor_in_gap(pencil, fac_s, stats)?;
        fac_s = match top {
            Some((ts, _)) if moved.sigma >= ts => factor_away_from_eigenvalue(pencil, ts, stats)?,
            _ => moved,
        };
    }
    Ok(fac_s)
}

/// Ritz values of OP as eigenvalues λ = sh + 1/θ at or above a, ascending, with their
/// convergence flag (the eigenvalue-error bound of the module doc) and column.
fn ritz_eigenvalues(theta: &[f64], res: &[f64], sh: f64, a: f64) -> Vec<(f64, bool, usize)> {
    let mut ritz: Vec<(f64, bool, usize)> = theta
        .iter()
        .enumerate()
        .filter(|(_, t)| **t != 0.0)
        .map(|(i, &t)| {
            let l = sh + 1.0 / t;
            (
                l,
                res[i] / (t * t) <= RESIDUAL_TOL * l.abs().max(sh.abs()),
                i,
            )
        })
        .filter(|x| x.0 >= a)
        .collect();
    ritz.sort_by(|x, y| x.0.total_cmp(&y.0));
    ritz
}

/// The slice's upper edge above the shift s: halfway between the last eigenvalue of the
/// converged run (`run_end` in `above`) and the next distinct Ritz value, or s itself when
/// nothing above it converged.
fn edge_above_run(above: &[(f64, bool, usize)], run_end: Option<usize>, s: f64) -> f64 {
    match run_end {
        None => s,
        Some(e) => {
            let last = above[e].0;
            match above[e + 1..]
                .iter()
                .find(|x| x.0 > last + 1e-8 * last.abs())
            {
                Some(x) => 0.5 * (last + x.0),
                None => last + 0.5 * (last - s).abs().max(1e-9 * last.abs()),
            }
        }
    }
}

/// The next shift after a restart: at the unconverged Ritz value in [a, upper) closest to
/// convergence (relative eigenvalue-error bound), i.e. where the missing ones are.
fn restart_target(
    ritz: &[(f64, bool, usize)],
    (theta, res): (&[f64], &[f64]),
    upper: f64,
    sh: f64,
) -> Option<f64> {
    ritz.iter()
        .filter(|x| !x.1 && x.0 < upper)
        .map(|x| {
            let t = theta[x.2];
            (x.0, res[x.2] / (t * t) / x.0.abs().max(sh.abs()))
        })
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|x| x.0)
        // Ritz values over-estimate: a cluster just below the edge may show all its
        // unconverged values above it. Then aim just below the edge.
        .or(Some(upper))
}

/// Appends converged vectors to the locked set, and their M-products to M·locked (only the
/// new columns are multiplied).
pub(super) fn lock(m: &SymCsc, locked: &mut Mat<f64>, locked_m: &mut Mat<f64>, pairs: &[Pair]) {
    let (n, k) = (m.n, pairs.len());
    let g = Mat::<f64>::from_fn(n, k, |i, j| pairs[j].1[i]);
    let gm = m.mul(g.as_ref());
    for (dst, new) in [(locked, g), (locked_m, gm)] {
        let q0 = dst.ncols();
        let mut out = Mat::<f64>::zeros(n, q0 + k);
        out.as_mut().subcols_mut(0, q0).copy_from(dst.as_ref());
        out.as_mut().subcols_mut(q0, k).copy_from(new.as_ref());
        *dst = out;
    }
}

pub(super) fn count_below(pairs: &[(f64, Vec<f64>)], lim: f64) -> usize {
    pairs.iter().filter(|x| x.0 < lim).count()
}

/// Index (into `above`, sorted by λ) of the last converged Ritz value of the unbroken run of
/// converged values from the bottom. An unconverged value that repeats a converged one to
/// 1e-8 (a further copy of a multiple eigenvalue entering the basis) does not break the run:
/// the Sturm count at the edge will say whether copies are missing.
pub(super) fn unbroken_run(above: &[(f64, bool, usize)]) -> Option<usize> {
    let mut end = None;
    for (i, x) in above.iter().enumerate() {
        if x.1 {
            end = Some(i);
            continue;
        }
        let near = |y: &&(f64, bool, usize)| (y.0 - x.0).abs() <= 1e-8 * x.0.abs();
        let dup = above[..i].iter().rev().take_while(near).any(|y| y.1)
            || above[i + 1..].iter().take_while(near).any(|y| y.1);
        if !dup {
            break;
        }
    }
    end
}

#[cfg(test)]
mod tests {
    use super::super::testing::{chain, chain_eigenvalues, identity};
    use super::*;

    #[test]
    fn unbroken_run_skips_unconverged_copies_only() {
        // (λ, converged, column): a further unconverged copy of 2.0 does not break the run;
        // the unconverged 3.0 does.
        let above = [
            (1.0, true, 0),
            (2.0, true, 1),
            (2.0 + 1e-12, false, 2),
            (2.5, true, 3),
            (3.0, false, 4),
            (4.0, true, 5),
        ];
        assert_eq!(unbroken_run(&above), Some(3));
        assert_eq!(unbroken_run(&above[4..]), None);
        let pairs = vec![(1.0, vec![]), (2.0, vec![]), (3.0, vec![])];
        assert_eq!(count_below(&pairs, 2.5), 2);
    }

    /// One slice from below the spectrum of a 200-mass chain: the pairs are exactly the
    /// eigenvalues below the new edge (count matched), each within the acceptance bound
    /// RESIDUAL_TOL·max(λ, σ) of the analytic value (σ ≤ the edge b).
    #[test]
    fn a_slice_holds_every_eigenvalue_below_its_edge() {
        let n = 200;
        let (k, m) = (chain(n, 1.0), identity(n));
        let pencil = Pencil::new(&k, Some(&m)).unwrap();
        let exact = chain_eigenvalues(n, 1.0);
        let mut stats = SparseStats::default();
        let (mut seed, mut bufs) = (1, None);
        let prev = Mat::<f64>::zeros(n, 0);
        let a = -1e-6;
        let width = 0.5 * exact[SLICE_MODES / 2];
        let out = run_slice(
            &m,
            &pencil,
            (a, 0),
            width,
            &prev,
            None,
            SLICE_MODES,
            &mut stats,
            &mut seed,
            &mut bufs,
        )
        .unwrap();
        let below = exact.iter().filter(|&&l| l < out.b).count();
        assert_eq!(out.c_b, below);
        assert_eq!(out.pairs.len(), below);
        assert!(below >= SLICE_MODES / 2);
        for ((l, _), want) in out.pairs.iter().zip(&exact) {
            assert!((l - want).abs() <= RESIDUAL_TOL * out.b, "{l} vs {want}");
        }
    }
}
