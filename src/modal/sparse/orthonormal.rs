//! B-orthonormalisation of blocks by Cholesky QR (matrix–matrix work), and the Gram matrix
//! of two narrow blocks through the SIMD kernel.

use super::csc::SymCsc;
use super::kernels::simd_dispatch;
use super::layout::{column, columns_mut};
use faer::{Accum, Mat, MatRef, Par, Side};

/// M-orthonormal basis of a wide block (a cluster's subspace) and M times it, by Cholesky
/// QR twice: X ← X·L⁻ᵀ as a triangular solve (half the work of a product with L⁻ᵀ), and
/// M·X recomputed by the sparse product rather than carried through the same transform
/// (measured on the 287-fold cluster of the 60-satellite stack: the transforms of X and M·X
/// were two thirds of the cluster step). `None` when the block is numerically rank deficient.
pub(super) fn m_orthonormalize(m: &SymCsc, mut x: Mat<f64>) -> Option<(Mat<f64>, Mat<f64>)> {
    use faer::linalg::matmul::triangular::{self, BlockStructure};
    use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
    let q = x.ncols();
    let mut mx = m.mul(x.as_ref());
    let mut g = Mat::<f64>::zeros(q, q);
    for _ in 0..2 {
        // The lower triangle of Xᵀ·M·X only (half the product): the Cholesky reads no more.
        triangular::matmul(
            g.as_mut(),
            BlockStructure::TriangularLower,
            Accum::Replace,
            x.transpose(),
            BlockStructure::Rectangular,
            mx.as_ref(),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        let l = g.llt(Side::Lower).ok()?.L().to_owned();
        // NaN fails this too.
        if !(0..q).all(|i| l[(i, i)] * l[(i, i)] > 1e-10 * g[(i, i)]) {
            return None;
        }
        solve_lower_triangular_in_place(l.as_ref(), x.as_mut().transpose_mut(), Par::Seq);
        mx = m.mul(x.as_ref());
    }
    Some((x, mx))
}

/// What CholQR2 made of a block (B·U carried along; U_in = U·R).
pub(super) enum CholQr {
    Orthonormal {
        u: Mat<f64>,
        bu: Mat<f64>,
        r: Mat<f64>,
    },
    /// A pass refused the block: the block as it stood then, and the R of the pass made
    /// before (`None` when the first pass refused it untouched).
    Refused {
        u: Mat<f64>,
        bu: Mat<f64>,
        done: Option<Mat<f64>>,
    },
}

/// B-orthonormalisation of a block by Cholesky QR, twice (CholQR2: matrix–matrix work instead
/// of the column-by-column Gram–Schmidt), in place: returns (U, B·U, R) with U_in = U·R.
/// Refused when the block is too close to rank deficient for it (a relative Cholesky pivot
/// under 1e-10), and the caller falls back on what it gets back. The blocks are taken by value
/// so that the Lanczos step does not copy them (two n × 8 copies per step); the second pass
/// refuses only a block the first left far from orthonormal, which its own pivot test rules
/// out short of NaN.
pub(super) fn chol_qr2(mut u: Mat<f64>, mut bu: Mat<f64>, g0: Option<Mat<f64>>) -> CholQr {
    use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
    let p = u.ncols();
    // Blocks of up to 16 columns go through the SIMD kernels (in place, one pass per
    // product); a restart's wider block (up to 40) through faer.
    let small = p <= 16;
    let mut r = Mat::<f64>::identity(p, p);
    let mut given = g0;
    for pass in 0..2 {
        let g = match given.take() {
            Some(g) => g,
            None if small => gram(u.as_ref(), bu.as_ref()),
            None => {
                let g0 = u.transpose() * &bu;
                Mat::<f64>::from_fn(p, p, |i, j| 0.5 * (g0[(i, j)] + g0[(j, i)]))
            }
        };
        let l = g.llt(Side::Lower).ok().map(|c| c.L().to_owned());
        // NaN fails this too.
        let ok = |l: &Mat<f64>| (0..p).all(|i| l[(i, i)] * l[(i, i)] > 1e-10 * g[(i, i)]);
        let Some(l) = l.filter(ok) else {
            let done = (pass > 0).then_some(r);
            return CholQr::Refused { u, bu, done };
        };
        // U ← U·L⁻ᵀ as one product with the small explicit inverse (p×p), rather than a
        // triangular solve on transposed n×p copies.
        let mut linv = Mat::<f64>::identity(p, p);
        solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), Par::Seq);
        let lit = linv.transpose();
        if small {
            let ut: Vec<f64> = (0..p * p).map(|x| lit[(x / p, x % p)]).collect();
            for m in [&mut u, &mut bu] {
                let mut cols = columns_mut(m.as_mut());
                simd_dispatch!(mul_upper(&mut cols, &ut));
            }
        } else {
            u = &u * lit;
            bu = &bu * lit;
        }
        r = l.transpose() * &r;
    }
    CholQr::Orthonormal { u, bu, r }
}

/// Xᵀ·Y for two n × p blocks (p ≤ 16), exactly symmetric (the upper triangle mirrored).
pub(super) fn gram(x: MatRef<'_, f64>, y: MatRef<'_, f64>) -> Mat<f64> {
    let p = x.ncols();
    let xc: Vec<&[f64]> = (0..p).map(|c| column(x, c)).collect();
    let yc: Vec<&[f64]> = (0..p).map(|c| column(y, c)).collect();
    let mut g = vec![0.0; p * p];
    simd_dispatch!(gram_sym(&xc, &yc, &mut g));
    Mat::<f64>::from_fn(p, p, |i, j| g[i * p + j])
}

#[cfg(test)]
mod tests {
    use super::super::testing::{chain, dense, max_diff};
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random(n: usize, p: usize, seed: u64) -> Mat<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Mat::<f64>::from_fn(n, p, |_, _| rng.random::<f64>() - 0.5)
    }

    /// CholQR2 of a well-conditioned block (κ far below ε^(-1/2)) is B-orthonormal to O(ε)
    /// and reproduces the input as U·R (Yamamoto et al. 2015, the CholeskyQR2 bounds):
    /// 1e-13 on both, R upper triangular; the narrow (SIMD) and the wide (faer) paths.
    #[test]
    fn cholesky_qr2_is_b_orthonormal_and_reproduces_the_block() {
        let n = 50;
        let b = chain(n, 1.0);
        for p in [6, 20] {
            let u0 = random(n, p, p as u64);
            let bu0 = b.mul(u0.as_ref());
            let CholQr::Orthonormal { u, bu, r } = chol_qr2(u0.clone(), bu0.clone(), None) else {
                panic!("full rank refused");
            };
            let eye = Mat::<f64>::identity(p, p);
            assert!(max_diff(&(u.transpose() * &bu), &eye) < 1e-13);
            assert!(max_diff(&(&u * &r), &u0) < 1e-13);
            assert!(max_diff(&b.mul(u.as_ref()), &bu) < 1e-13);
            for j in 0..p {
                for i in j + 1..p {
                    assert_eq!(r[(i, j)], 0.0);
                }
            }
        }
    }

    /// A block with two equal columns is refused by the first pass and handed back untouched
    /// (no pass made), for the caller's column-by-column fallback.
    #[test]
    fn cholesky_qr2_hands_back_a_rank_deficient_block_untouched() {
        let n = 40;
        let b = chain(n, 1.0);
        let mut u0 = random(n, 6, 5);
        for i in 0..n {
            u0[(i, 3)] = u0[(i, 1)];
        }
        let bu0 = b.mul(u0.as_ref());
        match chol_qr2(u0.clone(), bu0.clone(), None) {
            CholQr::Refused { u, bu, done } => {
                assert!(done.is_none());
                assert_eq!(max_diff(&u, &u0), 0.0);
                assert_eq!(max_diff(&bu, &bu0), 0.0);
            }
            CholQr::Orthonormal { .. } => panic!("a rank-deficient block was accepted"),
        }
    }

    /// The cluster's orthonormalisation: XᵀMX = I to O(ε) (1e-13), M·X returned with it; a
    /// block with two equal columns is rank deficient and refused.
    #[test]
    fn m_orthonormalize_wide_block_and_refuse_rank_deficiency() {
        let n = 60;
        let m = chain(n, 1.0);
        let (x, mx) = m_orthonormalize(&m, random(n, 24, 9)).expect("full rank");
        assert!(max_diff(&(x.transpose() * &mx), &Mat::<f64>::identity(24, 24)) < 1e-13);
        assert!(max_diff(&(dense(&m) * &x), &mx) < 1e-13);
        let mut y = random(n, 5, 10);
        for i in 0..n {
            y[(i, 4)] = y[(i, 1)];
        }
        assert!(m_orthonormalize(&m, y).is_none());
    }
}
