//! Polishing of a cluster of repeated eigenvalues whose vectors came out of the Lanczos runs
//! with a residual above working precision: two steps of inverse iteration with a shift just
//! below the cluster (amplifying the cluster over its nearest neighbours by the ratio of the
//! distances, ~1e3 per step on the stack), then a Rayleigh–Ritz projection within the block,
//! which gives M-orthonormal vectors and their eigenvalues.

use super::csc::SymCsc;
use super::eigen::SparseStats;
use super::factor::{Pencil, accurate_factor, factor_away_from_eigenvalue};
use super::{Pair, SparseError};
use crate::error::ModalError;
use faer::Mat;

/// Relative distance of the shift below the cluster's lowest eigenvalue.
const SHIFT_BELOW: f64 = 1e-5;

/// Replaces `pairs[range]` (one cluster) by its polished pairs.
pub fn polish_cluster(
    pencil: &Pencil,
    k: &SymCsc,
    m: &SymCsc,
    pairs: &mut [Pair],
    range: std::ops::Range<usize>,
    stats: &mut SparseStats,
) -> Result<(), SparseError> {
    let n = k.n;
    let block = &pairs[range.clone()];
    let sigma = block[0].0 * (1.0 - SHIFT_BELOW);
    let fac = factor_away_from_eigenvalue(pencil, sigma, stats)?;
    let fac = accurate_factor(pencil, fac, stats)?;
    let mut y = Mat::<f64>::from_fn(n, block.len(), |i, j| block[j].1[i]);
    for _ in 0..2 {
        let mut my = m.mul(y.as_ref());
        fac.solve(my.as_mut());
        y = my;
    }
    let (ky, my) = (k.mul(y.as_ref()), m.mul(y.as_ref()));
    let kr = y.transpose() * &ky;
    let mr = y.transpose() * &my;
    let sym = |a: &Mat<f64>| {
        Mat::<f64>::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
    };
    let (lambda, q) = crate::modal::dense::generalized_whole_spectrum(&sym(&kr), &sym(&mr))
        .map_err(|e| {
            ModalError::Invalid(format!("polishing a cluster of repeated modes: {e:?}"))
        })?;
    let x = &y * &q;
    for (j, p) in pairs[range].iter_mut().enumerate() {
        p.0 = lambda[j];
        p.1 = (0..n).map(|i| x[(i, j)]).collect();
    }
    Ok(())
}
