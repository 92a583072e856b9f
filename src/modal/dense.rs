//! Dense symmetric-definite eigen-solves with faer, for models up to a few thousand DOFs:
//! K·φ = λ·M·φ by shift-invert (K − σM = L·Lᵀ, C = L⁻¹·M·L⁻ᵀ) and the self-adjoint
//! eigen-solver, and the buckling problem (K + λ·K_G)·φ = 0 by the same reduction on K.
//!
//! Everything runs with `Par::Seq`: the dense solves are small, and sequential floating-point
//! order makes the results byte-identical whatever the thread count.

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par, Side};

/// Failure of a dense solve, with the index where it happened.
#[derive(Debug, Clone, PartialEq)]
pub enum DenseError {
    /// The matrix that had to be positive definite has a non-positive pivot at this index.
    NotPositiveDefinite {
        index: usize,
    },
    NoConvergence,
}

/// Cholesky factor L (lower) of a symmetric positive-definite matrix.
pub fn cholesky(a: &Mat<f64>) -> Result<Mat<f64>, DenseError> {
    faer::set_global_parallelism(Par::Seq);
    let llt = a.llt(Side::Lower).map_err(|e| match e {
        faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
            DenseError::NotPositiveDefinite { index }
        }
    })?;
    Ok(llt.L().to_owned())
}

/// Eigen-decomposition of a symmetric matrix, scaled to unit max-norm first: faer 0.24's
/// self-adjoint solver loses relative accuracy on matrices with entries of order 1e13 (we
/// measured residuals of 6e-8·‖A‖ on the NAFEMS FV5 stiffness, against 1e-15 after scaling),
/// which would cost the low modes of L⁻¹KL⁻ᵀ several digits.
fn sym_eigen(a: &Mat<f64>, vectors: bool) -> Result<(Vec<f64>, Option<Mat<f64>>), DenseError> {
    let n = a.nrows();
    let mut scale = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            scale = scale.max(a[(i, j)].abs());
        }
    }
    if scale == 0.0 || !scale.is_finite() {
        scale = 1.0;
    }
    let s = a * faer::Scale(1.0 / scale);
    if vectors {
        let evd = s
            .self_adjoint_eigen(Side::Lower)
            .map_err(|_| DenseError::NoConvergence)?;
        let d = evd.S().column_vector();
        Ok((
            (0..n).map(|i| d[i] * scale).collect(),
            Some(evd.U().to_owned()),
        ))
    } else {
        let d = s
            .self_adjoint_eigenvalues(Side::Lower)
            .map_err(|_| DenseError::NoConvergence)?;
        Ok((d.into_iter().map(|x| x * scale).collect(), None))
    }
}

/// All eigenpairs of a small symmetric matrix (the scaled solver above), for the projected
/// matrices of the sparse Lanczos iteration.
pub(crate) fn sym_eigen_pub(a: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>), DenseError> {
    let (d, u) = sym_eigen(a, true)?;
    Ok((d, u.ok_or(DenseError::NoConvergence)?))
}

/// L⁻¹·A·L⁻ᵀ, symmetrised.
fn congruence(l: &Mat<f64>, a: &Mat<f64>) -> Mat<f64> {
    let mut x = a.clone();
    solve_lower_triangular_in_place(l.as_ref(), x.as_mut(), Par::Seq);
    let mut y = x.transpose().to_owned();
    solve_lower_triangular_in_place(l.as_ref(), y.as_mut(), Par::Seq);
    let n = y.nrows();
    for i in 0..n {
        for j in 0..i {
            let s = 0.5 * (y[(i, j)] + y[(j, i)]);
            y[(i, j)] = s;
            y[(j, i)] = s;
        }
    }
    y
}

/// Every eigenpair of K·φ = λ·M·φ by reduction with the Cholesky factor of M (M = L·Lᵀ,
/// A = L⁻¹·K·L⁻ᵀ), for the direct frequency response, which needs the top of the spectrum as
/// accurately as the bottom: this reduction resolves every λ to round-off of the largest one,
/// shift-invert resolves the lowest ones to their own precision and loses the top. The modal
/// analysis uses [`generalized`].
pub fn generalized_whole_spectrum(
    k: &Mat<f64>,
    m: &Mat<f64>,
) -> Result<(Vec<f64>, Mat<f64>), DenseError> {
    let l = cholesky(m)?;
    let a = congruence(&l, k);
    let (lambda, u) = sym_eigen(&a, true)?;
    let mut phi = u.ok_or(DenseError::NoConvergence)?;
    solve_upper_triangular_in_place(l.transpose(), phi.as_mut(), Par::Seq);
    Ok((lambda, phi))
}

/// The shift of the dense shift-invert solve, −(2π · 1 Hz)²: below every eigenvalue of a
/// stable model, so K − σM is positive definite even with rigid-body modes, and small against
/// the flexible modes of anything from a launcher stack to a bracket, so λ = σ + 1/θ loses no
/// digits to cancellation. Raised a hundredfold at a time when round-off in a stiff model's
/// null space makes the first factorization fail.
const FIRST_SHIFT: f64 = -39.478_417_604_357_43;
const SHIFT_TRIES: usize = 8;

/// All eigenpairs of K·φ = λ·M·φ by shift-invert, and the factorization's conditioning.
pub struct Generalized {
    /// Ascending.
    pub lambda: Vec<f64>,
    /// Mass-normalised shapes (φᵀMφ = 1), as columns.
    pub phi: Mat<f64>,
    /// The shift σ that was factored.
    pub shift: f64,
    /// B_ii / D_ii of every pivot of B = K − σM = L·D·Lᵀ (D_ii = L_ii² of the Cholesky
    /// factor), the figure Nastran calls MAXRATIO at its largest.
    pub pivot_ratio: Vec<f64>,
}

/// All eigenpairs of K·φ = λ·M·φ, λ ascending, φ mass-normalised (φᵀMφ = 1).
///
/// B = K − σM = L·Lᵀ with σ < 0, then the eigenpairs (θ, u) of C = L⁻¹·M·L⁻ᵀ: θ = 1/(λ − σ)
/// and φ = L⁻ᵀ·u. K enters only through its factor, never through a product with a shape: a
/// 1e20 N/m spring would add a 1e20 term to a 1e4 eigenvalue in a Rayleigh quotient and
/// take all its digits (as reducing by the Cholesky factor of M did). The largest θ are the
/// lowest modes, resolved to the working precision of C.
pub fn generalized(k: &Mat<f64>, m: &Mat<f64>) -> Result<Generalized, DenseError> {
    let (shift, l) = factor_shifted(k, m)?;
    let n = k.nrows();
    let pivot_ratio = (0..n)
        .map(|i| (k[(i, i)] - shift * m[(i, i)]) / (l[(i, i)] * l[(i, i)]))
        .collect();
    let c = congruence(&l, m);
    let (theta, u) = sym_eigen(&c, true)?;
    let mut u = u.ok_or(DenseError::NoConvergence)?;
    solve_upper_triangular_in_place(l.transpose(), u.as_mut(), Par::Seq);
    // θ ascending is λ descending: take the columns in reverse.
    let lambda = theta.iter().rev().map(|&t| shift + 1.0 / t).collect();
    let phi = Mat::<f64>::from_fn(n, n, |r, c| {
        let j = n - 1 - c;
        u[(r, j)] / theta[j].abs().sqrt()
    });
    Ok(Generalized {
        lambda,
        phi,
        shift,
        pivot_ratio,
    })
}

/// The Cholesky factor of K − σM for the first σ of the sequence that makes it positive
/// definite; the last failure when none does.
fn factor_shifted(k: &Mat<f64>, m: &Mat<f64>) -> Result<(f64, Mat<f64>), DenseError> {
    let mut shift = FIRST_SHIFT;
    let mut last = DenseError::NoConvergence;
    for _ in 0..SHIFT_TRIES {
        let b = k - m * faer::Scale(shift);
        match cholesky(&b) {
            Ok(l) => return Ok((shift, l)),
            Err(e) => last = e,
        }
        shift *= 100.0;
    }
    Err(last)
}

/// Smallest positive λ of (K + λ·K_G)·φ = 0, with K positive definite: the eigenvalues μ of
/// L⁻¹·(−K_G)·L⁻ᵀ are 1/λ, so the critical factor is 1/max μ. `None` when no μ is positive
/// (the prestress nowhere destabilises the structure).
pub fn buckling_factor(k: &Mat<f64>, kg: &Mat<f64>) -> Result<Option<f64>, DenseError> {
    let l = cholesky(k)?;
    let neg = -kg;
    let b = congruence(&l, &neg);
    let (mu, _) = sym_eigen(&b, false)?;
    let max = mu.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let span = mu.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    // A μ at round-off level relative to the spectrum is a zero: no buckling direction.
    Ok(if max > 1e-12 * span {
        Some(1.0 / max)
    } else {
        None
    })
}

/// Solves K·u = f for symmetric positive-definite K.
pub fn solve_spd(k: &Mat<f64>, f: &[f64]) -> Result<Vec<f64>, DenseError> {
    let l = cholesky(k)?;
    let mut x = Mat::<f64>::from_fn(f.len(), 1, |i, _| f[i]);
    solve_lower_triangular_in_place(l.as_ref(), x.as_mut(), Par::Seq);
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    Ok((0..f.len()).map(|i| x[(i, 0)]).collect())
}
