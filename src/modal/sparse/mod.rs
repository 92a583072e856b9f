//! Sparse solvers for large models: the modes up to `fmax_hz` (or the lowest N) of K·φ = λ·M·φ,
//! the prestress static solve K·u = f and the linear buckling factor of (K + λ·K_G)·φ = 0,
//! without ever forming a dense n×n matrix.
//!
//! Files, one job each: [`csc`] (symmetric CSC storage and products), [`kernels`] (the 8-wide
//! SIMD kernels), [`layout`] (their interleaved row layout and scratch), [`factor`] (the LDLᵀ
//! of K − σM and its Sturm count), [`static_solve`] (K·u = f), [`orthonormal`] (Cholesky QR of
//! blocks), [`lanczos`] (the block Lanczos iteration), [`slice`] (one spectrum slice),
//! [`cluster`] (subspace iteration on a cluster of repeated eigenvalues), [`bands`] (parallel
//! bands of slices), [`eigen`] (the eigen-solve driver) and [`buckling`] (the buckling factor).
//!
//! # Tolerance
//! For a Ritz pair (θ, y) of OP with residual r = ‖OP·y − θ·y‖_M (read off the block
//! tridiagonal matrix), OP being M-self-adjoint gives |δθ| ≤ r, hence an eigenvalue error
//! |δλ| ≤ r/θ² to first order (and ~r²/gap for a separated eigenvalue). A pair is accepted when
//! (a) that bound is at most [`RESIDUAL_TOL`] relative: r/θ² ≤ tol·max(|λ|, |σ|) (the |σ|
//! keeps rigid-body modes, λ ≈ 0, from asking for the impossible), and (b) r ≤ [`VECTOR_TOL`]·|θ|,
//! ARPACK's criterion (the `tol` of `scipy.sparse.linalg.eigsh`), which bounds the backward
//! error of the eigenvector relative to ‖K − σM‖. (a) alone would accept poor vectors of
//! eigenvalues very close to the shift; (b) alone cannot be met far from the shift, where the
//! residual floor is round-off relative to the largest θ. After convergence the true residual
//! ‖K·φ − λ·M·φ‖₂ is measured for every pair and reported as a normwise backward error
//! ‖r‖₂ / ((‖K‖₁ + |λ|·‖M‖₁)·‖φ‖₂) in [`SparseStats`].
//!
//! # Cost
//! The stack's K − σM factors with almost no fill (about 5 values of L per unknown after AMD),
//! so factorizations and solves are cheap and the time goes into re-orthogonalisation and the
//! projected eigen-problems, which grow with (modes below fmax) × (basis size) × n. With the
//! default stack mesh about 45% of all DOFs have modes below 2 kHz, which is what sets the run
//! time of `satqual bench modal`. Measured on the 60-satellite stack (one thread, 2.9 s in
//! all, eigen-solve 2.8 s): the Lanczos step's orthogonalisation 0.9 s (Gram–Schmidt
//! products against [locked | basis], BLAS-3 through faer, with its two products by M), the
//! cluster step 0.55 s, the projected eigen-problems 0.46 s, the LDLᵀ solves 0.19 s
//! (hand-written 8-wide kernels, [`kernels`], built for AVX2/AVX-512 at run time), the
//! block normalisation 0.14 s, then the factorizations and the Ritz vectors. What was cut,
//! with the measured share: recycled basis storage instead of a fresh n × 200 allocation per
//! slice (8%); the second Gram–Schmidt update skipped when the first pass already left the
//! block orthogonal to 1e-12 (92% of steps; 10%), that level estimated from an 8-column
//! Gaussian sketch of the basis rather than a third product with it (5%); the interleaved solve
//! and product kernels (15%), and their transposes done in one pass per row through the
//! inverse permutation with per-thread scratch (13%); B·V not stored, so that two bands keep
//! their bases in the shared L3 cache; the cluster's subspace orthonormalised by triangular
//! solves (6%); a band's first shift moved inside the band (5% fewer Lanczos vectors).
//!
//! # Why hand-written
//! faer 0.24 offers sparse LDLᵀ but no sparse symmetric eigen-solver, and no maintained Rust
//! crate provides a shift-invert Lanczos with inertia checks on a faer factorization; the
//! Lanczos iteration itself is short, the linear algebra underneath is faer's.
//!
//! Determinism: every faer call runs with `Par::Seq` and the start blocks come from a seeded
//! ChaCha generator, so results are byte-identical whatever the thread count.

pub mod bands;
pub mod buckling;
pub mod cluster;
pub mod csc;
pub mod eigen;
pub mod factor;
mod kernels;
pub mod lanczos;
mod layout;
pub mod orthonormal;
pub mod polish;
pub mod slice;
pub mod static_solve;
pub mod symmetry;

use crate::error::ModalError;

pub use bands::BAND_MODES;
pub use buckling::buckling_factor;
pub use csc::SymCsc;
pub use eigen::{FinishedBand, SparseStats, eigen, eigen_by_band, sturm_check};
pub use factor::{Factor, Pencil, SINGULAR_PIVOT};
pub use lanczos::{BLOCK, MAX_BASIS, REORTH_SKIP};
pub use slice::{MAX_RESTARTS, SLICE_MODES};
pub use static_solve::solve_spd;

/// Accepted first-order bound on the relative eigenvalue error of a Ritz pair (module doc);
/// frequencies then carry at most half of it.
pub const RESIDUAL_TOL: f64 = 1e-10;
/// Accepted ‖OP·y − θ·y‖_M / |θ| (ARPACK's criterion), which bounds the backward error of the
/// eigenvector (module doc); looser than the eigenvalue criterion because its round-off floor
/// grows with the distance from the shift.
pub const VECTOR_TOL: f64 = 1e-9;

/// Failures of the sparse solvers, with the numerical fact.
#[derive(Debug, Clone, PartialEq)]
pub enum SparseError {
    /// Non-positive (or relatively negligible) pivot of a matrix that had to be positive
    /// definite, at this index of the input (not the permuted) ordering.
    NotPositiveDefinite {
        index: usize,
    },
    /// K − σM stayed singular to working precision near σ: its smallest pivot relative to its
    /// diagonal entry, at this index of the input ordering.
    SingularNear {
        sigma: f64,
        index: usize,
        relative_pivot: f64,
    },
    Modal(ModalError),
}

impl From<ModalError> for SparseError {
    fn from(e: ModalError) -> Self {
        SparseError::Modal(e)
    }
}

/// An eigenpair (λ, φ).
pub type Pair = (f64, Vec<f64>);

/// Small pencils with known spectra for the unit tests of this module's files.
#[cfg(test)]
pub(crate) mod testing {
    use super::SymCsc;
    use crate::fem::model::Triplets;
    use faer::Mat;

    /// The symmetric n × n matrix with entries `a(i, j)` (zeros not stored).
    pub fn csc(n: usize, a: impl Fn(usize, usize) -> f64) -> SymCsc {
        let mut t: Triplets = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = a(i, j);
                if v != 0.0 {
                    t.push((i, j, v));
                }
            }
        }
        SymCsc::from_triplets(n, &t)
    }

    /// Stiffness of n unit masses in a row joined by springs of stiffness k, the two end
    /// springs anchored to walls: 2k on the diagonal, −k beside it.
    pub fn chain(n: usize, k: f64) -> SymCsc {
        csc(n, |i, j| match i.abs_diff(j) {
            0 => 2.0 * k,
            1 => -k,
            _ => 0.0,
        })
    }

    /// Eigenvalues of [`chain`] with unit masses, ascending: λ_j = 4k·sin²(jπ / (2(n + 1))),
    /// j = 1..n (the spectrum of the discrete Dirichlet Laplacian).
    pub fn chain_eigenvalues(n: usize, k: f64) -> Vec<f64> {
        (1..=n)
            .map(|j| {
                let s = (j as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin();
                4.0 * k * s * s
            })
            .collect()
    }

    pub fn diagonal(d: &[f64]) -> SymCsc {
        csc(d.len(), |i, j| if i == j { d[i] } else { 0.0 })
    }

    pub fn identity(n: usize) -> SymCsc {
        diagonal(&vec![1.0; n])
    }

    /// The dense copy of `a` (its product with the identity).
    pub fn dense(a: &SymCsc) -> Mat<f64> {
        a.mul(Mat::<f64>::identity(a.n, a.n).as_ref())
    }

    /// Largest |a_ij − b_ij|.
    pub fn max_diff(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
        let mut d = 0.0f64;
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                d = d.max((a[(i, j)] - b[(i, j)]).abs());
            }
        }
        d
    }
}
