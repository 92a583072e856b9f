//! The missing copies of a wide cluster of repeated eigenvalues, taken whole by subspace
//! iteration (spectrum slicing step 6 in [`super::slice`]).

use super::csc::SymCsc;
use super::eigen::SparseStats;
use super::factor::{Pencil, accurate_factor, factor_away_from_eigenvalue};
use super::lanczos::BLOCK;
use super::orthonormal::m_orthonormalize;
use super::{Pair, RESIDUAL_TOL, SparseError, VECTOR_TOL};
use crate::error::ModalError;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative distance of the subspace iteration's shift below the cluster: its smallest pivot
/// is then about 1e-7 relative, six decades above where a factorization is nudged off an
/// eigenvalue, and neighbours a few 1e-4 away fall behind by 1e-3 or more per application.
const SHIFT_BELOW: f64 = 1e-7;

/// The missing copies of a tight cluster of (numerically) repeated eigenvalues near `l`, by
/// subspace iteration with a block exactly as wide as the number missing.
///
/// The cluster's size comes from two Sturm counts at l·(1 ∓ 1e-5) (clipped to the slice). The
/// shift sits [`SHIFT_BELOW`] below l, so that every application of (K − σM)⁻¹M leaves the
/// nearest other modes behind by their distance from the cluster over the shift's: the
/// 60-satellite stack has modes 3.3e-4 from its 257 missing copies, which a shift at the
/// bracket's edge (1e-5) leaves behind by only 3e-2 per application (three rounds, 238 of
/// 257 converged); at 1e-7, by 3e-4. The block starts random and M-orthogonal to the locked
/// vectors (the copies already found), so it converges to exactly the missing part of the
/// eigenspace.
/// Pairs are accepted with the Lanczos criteria ([`RESIDUAL_TOL`], [`VECTOR_TOL`]); whatever
/// does not converge is left to the restarted Lanczos.
#[allow(clippy::too_many_arguments)]
pub(super) fn cluster_pairs(
    m: &SymCsc,
    pencil: &Pencil,
    l: f64,
    (a, upper): (f64, f64),
    (locked, locked_m): (MatRef<'_, f64>, MatRef<'_, f64>),
    found: &[Pair],
    stats: &mut SparseStats,
    seed: u64,
) -> Result<Vec<Pair>, SparseError> {
    let n = m.n;
    // The bracket is clipped to the slice: a restart aims at the slice's upper edge when the
    // cluster sits just below it (its Ritz values over-estimate), and the 60-satellite stack
    // with a 0.55 m pitch has its 287-fold cluster within 1e-9 of such an edge (measured: 8
    // restarts of 40-vector blocks when the bracket had to fit whole).
    let d = 1e-5 * l.abs();
    let (lo, hi) = ((l - d).max(a), (l + d).min(upper));
    if hi <= lo {
        return Ok(Vec::new());
    }
    let lo = factor_away_from_eigenvalue(pencil, lo, stats)?;
    let hi = factor_away_from_eigenvalue(pencil, hi, stats)?;
    let (lo_s, hi_s) = (lo.sigma, hi.sigma);
    let in_bracket = hi.negative.saturating_sub(lo.negative);
    drop((lo, hi));
    let have = found.iter().filter(|x| x.0 >= lo_s && x.0 < hi_s).count();
    let q = in_bracket.saturating_sub(have);
    if q <= 2 * BLOCK || q > n / 2 {
        return Ok(Vec::new());
    }
    let fac = factor_away_from_eigenvalue(pencil, l - SHIFT_BELOW * l.abs(), stats)?;
    let fac = accurate_factor(pencil, fac, stats)?;
    // Twice before a Rayleigh–Ritz, once between applications: a locked component left at
    // round-off there is removed by the next deflation anyway.
    let deflate_n = |x: &mut Mat<f64>, passes: usize| {
        if locked.ncols() == 0 {
            return;
        }
        for _ in 0..passes {
            let c = locked_m.transpose() * x.as_ref();
            matmul(x.as_mut(), Accum::Add, locked, c.as_ref(), -1.0, Par::Seq);
        }
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = Mat::<f64>::from_fn(n, q, |_, _| rng.random::<f64>() - 0.5);
    let deflate = |x: &mut Mat<f64>| deflate_n(x, 2);
    deflate(&mut x);
    for round in 0..3 {
        // Applications without normalising (column scales only), then a Rayleigh–Ritz.
        for _ in 0..(if round == 0 { 4 } else { 2 }) {
            let mut y = m.mul(x.as_ref());
            fac.solve(y.as_mut());
            deflate_n(&mut y, 1);
            for c in 0..q {
                let s = (0..n).map(|i| y[(i, c)].abs()).fold(0.0, f64::max);
                if s > 0.0 {
                    for i in 0..n {
                        y[(i, c)] /= s;
                    }
                }
            }
            x = y;
        }
        let Some((xo, bxo)) = m_orthonormalize(m, x) else {
            return Ok(Vec::new());
        };
        let mut y = bxo.clone();
        fac.solve(y.as_mut());
        deflate(&mut y);
        let h0 = bxo.transpose() * &y;
        let h = Mat::<f64>::from_fn(q, q, |i, j| 0.5 * (h0[(i, j)] + h0[(j, i)]));
        let (theta, sv) = crate::modal::dense::sym_eigen_pub(&h)
            .map_err(|_| ModalError::NoConvergence("cluster Rayleigh–Ritz".into()))?;
        let z = &xo * &sv;
        let ys = &y * &sv;
        let r = Mat::<f64>::from_fn(n, q, |i, j| ys[(i, j)] - theta[j] * z[(i, j)]);
        let mr = m.mul(r.as_ref());
        let mut out = Vec::new();
        for j in 0..q {
            let t = theta[j];
            if t == 0.0 {
                continue;
            }
            let res = (0..n)
                .map(|i| r[(i, j)] * mr[(i, j)])
                .sum::<f64>()
                .max(0.0)
                .sqrt();
            let lam = fac.sigma + 1.0 / t;
            let ok = res / (t * t) <= RESIDUAL_TOL * lam.abs().max(fac.sigma.abs())
                && res <= VECTOR_TOL * t.abs();
            if ok && lam >= lo_s && lam < hi_s {
                out.push((lam, (0..n).map(|i| z[(i, j)]).collect()));
            }
        }
        if out.len() == q || round == 2 {
            return Ok(out);
        }
        x = ys;
    }
    Ok(Vec::new())
}

#[cfg(test)]
mod tests {
    use super::super::testing::{diagonal, identity};
    use super::*;

    /// diag(1.25, 1.75, …) with 20 copies of 5 put in; the nearest others 4.75 and 5.25
    /// (5% away, as the stack's neighbours of its cluster are a percent or more); M = I.
    fn clustered() -> (Vec<f64>, Vec<usize>) {
        let mut d: Vec<f64> = (0..100).map(|i| 1.25 + 0.5 * i as f64).collect();
        let copies: Vec<usize> = (0..20).map(|c| 3 + 4 * c).collect();
        for &i in &copies {
            d[i] = 5.0;
        }
        (d, copies)
    }

    /// Checks the pairs: λ within the acceptance bound RESIDUAL_TOL·|λ| of 5 (first order),
    /// vectors M-orthonormal (1e-12) and inside the eigenspace: outside the copies at most
    /// VECTOR_TOL·θ/(θ − θ_next) ≈ 1e-9 per component, asserted as 1e-8.
    fn check(pairs: &[Pair], copies: &[usize]) {
        for (l, v) in pairs {
            assert!((l - 5.0).abs() <= RESIDUAL_TOL * 5.0, "{l}");
            let outside = (0..v.len())
                .filter(|i| !copies.contains(i))
                .map(|i| v[i].abs())
                .fold(0.0, f64::max);
            assert!(outside < 1e-8, "{outside}");
        }
        for (a, (_, x)) in pairs.iter().enumerate() {
            for (b, (_, y)) in pairs.iter().enumerate() {
                let d: f64 = x.iter().zip(y).map(|(p, q)| p * q).sum();
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((d - want).abs() < 1e-12);
            }
        }
    }

    /// A 20-fold eigenvalue with nothing found yet is taken whole.
    #[test]
    fn a_repeated_eigenvalue_is_taken_whole() {
        let (d, copies) = clustered();
        let (k, m) = (diagonal(&d), identity(d.len()));
        let pencil = Pencil::new(&k, Some(&m)).unwrap();
        let empty = Mat::<f64>::zeros(d.len(), 0);
        let mut stats = SparseStats::default();
        let got = cluster_pairs(
            &m,
            &pencil,
            5.0,
            (4.5, 5.5),
            (empty.as_ref(), empty.as_ref()),
            &[],
            &mut stats,
            1,
        )
        .unwrap();
        assert_eq!(got.len(), 20);
        check(&got, &copies);
    }

    /// With three copies found and locked, the iteration returns exactly the 17 missing,
    /// M-orthogonal to the locked ones.
    #[test]
    fn only_the_missing_copies_are_returned() {
        let (d, copies) = clustered();
        let n = d.len();
        let (k, m) = (diagonal(&d), identity(n));
        let pencil = Pencil::new(&k, Some(&m)).unwrap();
        let found: Vec<Pair> = copies[..3]
            .iter()
            .map(|&c| {
                (
                    5.0,
                    (0..n).map(|i| if i == c { 1.0 } else { 0.0 }).collect(),
                )
            })
            .collect();
        let locked = Mat::<f64>::from_fn(n, 3, |i, j| found[j].1[i]);
        let mut stats = SparseStats::default();
        let got = cluster_pairs(
            &m,
            &pencil,
            5.0,
            (4.5, 5.5),
            (locked.as_ref(), locked.as_ref()),
            &found,
            &mut stats,
            2,
        )
        .unwrap();
        assert_eq!(got.len(), 17);
        check(&got, &copies);
        for (_, v) in &got {
            for &c in &copies[..3] {
                assert!(v[c].abs() < 1e-12);
            }
        }
    }
}
