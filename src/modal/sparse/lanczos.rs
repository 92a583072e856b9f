//! Block Lanczos for a shift-inverted operator.
//!
//! For a shift σ the operator OP = (K − σM)⁻¹·M is self-adjoint in the M-inner product and
//! maps λ to θ = 1/(λ − σ), so the eigenvalues nearest σ become the largest and converge first.
//! A block Lanczos (block size [`BLOCK`], M-orthonormal basis, full re-orthogonalisation
//! against the basis and the locked vectors, twice: "twice is enough", the second update
//! skipped when it would change nothing above [`REORTH_SKIP`]) builds a projected
//! block-tridiagonal matrix whose eigenpairs are the Ritz pairs. The block copes with the
//! repeated eigenvalues of symmetric structures (a single-vector Lanczos finds one vector per
//! eigenspace), and makes the triangular solves matrix–matrix work.

use super::SparseError;
use super::csc::SymCsc;
use super::orthonormal::{CholQr, chol_qr2, gram};
use crate::error::ModalError;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Block size of the Lanczos iteration: covers the multiplicities of symmetric frames (two
/// bending planes of a round bar, four identical guide bars) and turns the solves into
/// matrix–matrix work.
pub const BLOCK: usize = 8;
/// Largest Lanczos basis of one run.
pub const MAX_BASIS: usize = 200;
/// The recycled basis storage grows in steps of this many columns: the locked count changes
/// from slice to slice, and every reallocation zeroes n × (k + 200) values.
const BASIS_HEADROOM: usize = 64;
/// Second Gram–Schmidt coefficients below this fraction of ‖u‖_B mean the first pass already
/// left u orthogonal to the basis at that level: far below the √ε ≈ 1e-8 at which a Lanczos
/// basis starts to produce spurious copies of converged Ritz values.
pub const REORTH_SKIP: f64 = 1e-12;
/// Columns of the Gaussian sketch [X | V]·G that estimates the second Gram–Schmidt
/// coefficients (see [`Lanczos::orthogonalize_step`]).
const SKETCH: usize = 8;
/// Mixed into a run's seed for its sketch, so that the sketch draws nothing from the start
/// block's generator.
const SKETCH_SEED: u64 = 0x5eed_5ce7_c400_0001;

/// Ritz values θ, their residual norms, and the eigenvectors of the projected matrix.
pub(super) type Ritz = (Vec<f64>, Vec<f64>, Mat<f64>);

/// Block Lanczos with full re-orthogonalisation in the B-inner product, deflated against a
/// locked B-orthonormal set X. `op(V, B·V)` applies the operator to a block.
///
/// B·V is not stored: the Gram products are Vᵀ·(B·u), with one more sparse product B·u per
/// step. That halves the basis storage (8 MB instead of 16 MB per band on the 60-satellite
/// stack), so that two bands running side by side keep their bases in a 32 MB L3 cache.
pub(super) struct Lanczos {
    n: usize,
    p: usize,
    max_basis: usize,
    /// B-orthonormal basis.
    v: Mat<f64>,
    /// B times the newest block of V (the next operator input).
    bv_last: Mat<f64>,
    /// Columns of V filled (including the pending block).
    filled: usize,
    /// Blocks whose diagonal coefficient is in T.
    nb: usize,
    t: Mat<f64>,
    /// Coupling of the last block of T to the pending one (the residual block).
    r: Mat<f64>,
    /// Locked columns X at the front of `v`, so that one product against [X | V] does the
    /// work of two (the X coefficients as Xᵀ·(B·u), with the B·u that V needs anyway).
    k: usize,
    rng: ChaCha8Rng,
    exhausted: bool,
    /// [X | V]·G for an n-column-by-[`SKETCH`] Gaussian G, extended as V grows.
    sketch: Mat<f64>,
    sketch_rng: ChaCha8Rng,
}

impl Lanczos {
    pub(super) fn new(
        n: usize,
        p: usize,
        max_basis: usize,
        x: MatRef<'_, f64>,
        seed: u64,
        bufs: &mut Option<Mat<f64>>,
    ) -> Self {
        // Recycled basis storage: every column is written before it is read (`filled`), so
        // stale values never leak in; a fresh n × 200 basis would cost page faults and
        // zeroing on every slice (measured 8% of the 60-satellite solve).
        let k = x.ncols();
        let mut v = match bufs.take() {
            Some(v) if v.nrows() == n && v.ncols() >= k + max_basis => v,
            // Rounded up, so that a few more locked vectors in the next slice still fit.
            _ => Mat::zeros(n, (k + max_basis).next_multiple_of(BASIS_HEADROOM)),
        };
        v.as_mut().subcols_mut(0, k).copy_from(x);
        let mut lz = Lanczos {
            n,
            p,
            max_basis,
            v,
            bv_last: Mat::zeros(n, p),
            filled: 0,
            nb: 0,
            t: Mat::zeros(max_basis, max_basis),
            r: Mat::zeros(p, p),
            k,
            rng: ChaCha8Rng::seed_from_u64(seed),
            exhausted: false,
            sketch: Mat::zeros(n, SKETCH),
            sketch_rng: ChaCha8Rng::seed_from_u64(seed ^ SKETCH_SEED),
        };
        lz.extend_sketch(0, k);
        lz
    }

    pub(super) fn blocks(&self) -> usize {
        self.nb
    }

    /// Hands the basis storage back for the next run.
    pub(super) fn recycle(self, bufs: &mut Option<Mat<f64>>) {
        *bufs = Some(self.v);
    }

    /// Removes the X and V components of the columns of `u`, twice.
    fn orthogonalize(&self, mut u: MatMut<'_, f64>, upto: usize, b: &SymCsc) -> Mat<f64> {
        let k = self.k;
        let mut coef = Mat::<f64>::zeros(upto, u.ncols());
        if k + upto == 0 {
            return coef;
        }
        let w = self.v.as_ref().subcols(0, k + upto);
        for _ in 0..2 {
            let bu = b.mul(u.as_ref());
            let c = w.transpose() * &bu;
            matmul(u.as_mut(), Accum::Add, w, c.as_ref(), -1.0, Par::Seq);
            coef += c.as_ref().subrows(k, upto);
        }
        coef
    }

    /// Adds the block of columns `from..from + p` of [X | V], just written, to the sketch.
    fn extend_sketch(&mut self, from: usize, p: usize) {
        let g = gaussian(p, &mut self.sketch_rng);
        let block = self.v.as_ref().subcols(from, p);
        matmul(
            self.sketch.as_mut(),
            Accum::Add,
            block,
            g.as_ref(),
            1.0,
            Par::Seq,
        );
    }

    /// The filled basis V (without the locked columns).
    fn basis(&self, from: usize, cols: usize) -> MatRef<'_, f64> {
        self.v.as_ref().subcols(self.k + from, cols)
    }

    /// The Lanczos step's orthogonalisation of `u` against X and the filled basis, and B·u.
    /// Returns the coefficients on V (the new column of T).
    ///
    /// Classical Gram–Schmidt twice ("twice is enough"), except that the second pass is
    /// skipped when its coefficients c = Wᵀ·B·u are below [`REORTH_SKIP`] of ‖u‖_B for every
    /// column: the first pass then already left u orthogonal to that level. On the
    /// 60-satellite stack 92% of block steps qualify. ‖c‖ is estimated from the sketch
    /// (W·G)ᵀ·B·u = Gᵀ·c, whose squared norm is ‖c‖² times a χ² variable of [`SKETCH`]
    /// degrees of freedom over [`SKETCH`]: an n × 8 product instead of a third pass over the
    /// n × m basis (measured: a tenth of the 60-satellite solve). A loss of orthogonality
    /// that matters (c ≥ 1e-10·‖u‖_B, 100× the level) passes for skippable with a probability
    /// below P(χ²₈ < 8e-4) ≈ 1e-15. B·u, needed anyway for the normalisation, gives ‖u‖_B.
    ///
    /// Also returns uᵀ·B·u when the second pass was skipped (u unchanged since): the
    /// normalisation starts from it.
    fn orthogonalize_step(
        &self,
        mut u: MatMut<'_, f64>,
        b: &SymCsc,
    ) -> (Mat<f64>, Mat<f64>, Option<Mat<f64>>) {
        let (k, upto) = (self.k, self.filled);
        // [X | V]: the locked vectors and the filled basis, one product each way.
        let w = self.v.as_ref().subcols(0, k + upto);
        // Both products against W are written with the 8-column block as the left operand
        // (Wᵀ·B·u as (uᵀB·W)ᵀ, u − W·c as uᵀ − cᵀ·Wᵀ): faer then does not pack the n × m
        // basis into its micro-panel layout on every call (measured: 5–8% of the 60-satellite
        // solve, frequencies unchanged).
        let c = (b.mul(u.as_ref()).transpose() * w).transpose().to_owned();
        matmul(
            u.as_mut().transpose_mut(),
            Accum::Add,
            c.transpose(),
            w.transpose(),
            -1.0,
            Par::Seq,
        );
        let mut coef = c.as_ref().subrows(k, upto).to_owned();
        let bu = b.mul(u.as_ref());
        let sketched = bu.transpose() * self.sketch.as_ref();
        let g = (u.ncols() <= 16).then(|| gram(u.as_ref(), bu.as_ref()));
        let needed = (0..u.ncols()).any(|j| {
            let norm2: f64 = match &g {
                Some(g) => g[(j, j)],
                None => (0..self.n).map(|i| u[(i, j)] * bu[(i, j)]).sum(),
            };
            let c2 = (0..SKETCH).map(|l| sketched[(j, l)].powi(2)).sum::<f64>() / SKETCH as f64;
            // NaN asks for the second pass too.
            let small = c2.partial_cmp(&(REORTH_SKIP * REORTH_SKIP * norm2));
            !matches!(
                small,
                Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
            )
        });
        if !needed {
            return (coef, bu, g);
        }
        let cv = (bu.transpose() * w).transpose().to_owned();
        matmul(
            u.as_mut().transpose_mut(),
            Accum::Add,
            cv.transpose(),
            w.transpose(),
            -1.0,
            Par::Seq,
        );
        coef += cv.as_ref().subrows(k, upto);
        (coef, b.mul(u.as_ref()), None)
    }

    /// B-orthonormalises the block `u` (already orthogonal to X and V) in place; returns
    /// R with U_in = U_out·R, the new B·U, and whether the space is exhausted. A column that
    /// vanishes (an invariant subspace) is replaced by a random vector with a zero column in R.
    fn normalize(
        &mut self,
        u: Mat<f64>,
        bu: Option<(Mat<f64>, Option<Mat<f64>>)>,
        b: &SymCsc,
        upto: usize,
    ) -> (Mat<f64>, Mat<f64>, Mat<f64>, bool) {
        let (bu_m, g0) = bu.unwrap_or_else(|| (b.mul(u.as_ref()), None));
        let (u, bu_m, done) = match chol_qr2(u, bu_m, g0) {
            CholQr::Orthonormal { u, bu, r } => return (u, bu, r, false),
            CholQr::Refused { u, bu, done } => (u, bu, done),
        };
        let (u, bu, r, exhausted) = self.gram_schmidt(u, bu_m, b, upto);
        // U_in = U_done·R_done (the CholQR pass made, if any) and U_done = U·R.
        let r = match done {
            Some(r_done) => r * r_done,
            None => r,
        };
        (u, bu, r, exhausted)
    }

    /// The column-by-column fallback of [`Self::normalize`] (modified Gram–Schmidt twice, a
    /// vanishing column replaced by a random direction): returns (U, B·U, R, exhausted).
    fn gram_schmidt(
        &mut self,
        u: Mat<f64>,
        bu_m: Mat<f64>,
        b: &SymCsc,
        upto: usize,
    ) -> (Mat<f64>, Mat<f64>, Mat<f64>, bool) {
        let (n, p) = (self.n, u.ncols());
        let mut r = Mat::<f64>::zeros(p, p);
        let mut uc: Vec<Vec<f64>> = (0..p).map(|c| col_vec(&u, c)).collect();
        let mut bc: Vec<Vec<f64>> = (0..p).map(|c| col_vec(&bu_m, c)).collect();
        let scale = (0..p)
            .map(|c| dot(&uc[c], &bc[c]).max(0.0).sqrt())
            .fold(0.0, f64::max);
        let mut exhausted = false;
        for c in 0..p {
            let (done_u, rest_u) = uc.split_at_mut(c);
            let (done_b, rest_b) = bc.split_at_mut(c);
            let (uc_c, bc_c) = (&mut rest_u[0], &mut rest_b[0]);
            for _ in 0..2 {
                for d in 0..c {
                    let h = dot(&done_b[d], uc_c);
                    axpy(-h, &done_u[d], uc_c);
                    axpy(-h, &done_b[d], bc_c);
                    r[(d, c)] += h;
                }
            }
            let norm = dot(uc_c, bc_c).max(0.0).sqrt();
            if norm > 1e-10 * scale.max(f64::MIN_POSITIVE) && norm > 0.0 {
                r[(c, c)] = norm;
                uc_c.iter_mut().for_each(|x| *x /= norm);
                bc_c.iter_mut().for_each(|x| *x /= norm);
                continue;
            }
            // Breakdown: a fresh random direction, orthogonal to everything so far; r[(c, c)]
            // stays 0, as this column carries no Krylov coupling.
            let mut w = Mat::<f64>::from_fn(n, 1, |_, _| self.rng.random::<f64>() - 0.5);
            let w0 = {
                let bw = b.mul(w.as_ref());
                dot(&col_vec(&w, 0), &col_vec(&bw, 0)).max(0.0).sqrt()
            };
            let _ = self.orthogonalize(w.as_mut(), upto, b);
            let mut wv = col_vec(&w, 0);
            for _ in 0..2 {
                for d in 0..c {
                    let h = dot(&done_b[d], &wv);
                    axpy(-h, &done_u[d], &mut wv);
                }
            }
            let wm = Mat::<f64>::from_fn(n, 1, |i, _| wv[i]);
            let bw = col_vec(&b.mul(wm.as_ref()), 0);
            let norm = dot(&wv, &bw).max(0.0).sqrt();
            // What is left of a random vector is round-off once the space is spanned.
            if norm > 1e-8 * w0 {
                *uc_c = wv.iter().map(|x| x / norm).collect();
                *bc_c = bw.iter().map(|x| x / norm).collect();
            } else {
                exhausted = true;
                uc_c.iter_mut().for_each(|x| *x = 0.0);
                bc_c.iter_mut().for_each(|x| *x = 0.0);
            }
        }
        let u = Mat::<f64>::from_fn(n, p, |i, c| uc[c][i]);
        let bu = Mat::<f64>::from_fn(n, p, |i, c| bc[c][i]);
        (u, bu, r, exhausted)
    }

    /// A random B-orthonormal start block, deflated against X.
    pub(super) fn start(&mut self, b: &SymCsc) {
        let (n, p) = (self.n, self.p);
        let mut u = Mat::<f64>::from_fn(n, p, |_, _| self.rng.random::<f64>() - 0.5);
        let _ = self.orthogonalize(u.as_mut(), 0, b);
        let (u, bu, _, ex) = self.normalize(u, None, b, 0);
        let k = self.k;
        self.v.as_mut().subcols_mut(k, p).copy_from(u.as_ref());
        self.extend_sketch(k, p);
        self.bv_last = bu;
        self.filled = p;
        self.exhausted = ex;
    }

    /// One block step. Returns false when no further step is possible (basis full or the
    /// space exhausted); T and the residual block are valid either way.
    pub(super) fn step(
        &mut self,
        op: &impl Fn(MatRef<'_, f64>, MatRef<'_, f64>) -> Mat<f64>,
        b: &SymCsc,
    ) -> bool {
        let p = self.p;
        let j0 = self.nb * p;
        debug_assert_eq!(self.filled, j0 + p);
        let mut u = op(self.basis(j0, p), self.bv_last.as_ref());
        let (coef, bu, g) = self.orthogonalize_step(u.as_mut(), b);
        // Diagonal block, symmetrised.
        for i in 0..p {
            for c in 0..p {
                self.t[(j0 + i, j0 + c)] = 0.5 * (coef[(j0 + i, c)] + coef[(j0 + c, i)]);
            }
        }
        self.nb += 1;
        let (u, bu, r, ex) = self.normalize(u, Some((bu, g)), b, self.filled);
        self.r = r;
        self.exhausted |= ex;
        let j1 = j0 + p;
        if self.exhausted || j1 + p > self.max_basis {
            return false;
        }
        let k = self.k;
        self.v.as_mut().subcols_mut(k + j1, p).copy_from(u.as_ref());
        self.extend_sketch(k + j1, p);
        self.bv_last = bu;
        self.filled = j1 + p;
        for i in 0..p {
            for c in 0..p {
                self.t[(j1 + i, j0 + c)] = self.r[(i, c)];
                self.t[(j0 + c, j1 + i)] = self.r[(i, c)];
            }
        }
        true
    }

    /// Ritz values θ (ascending) of the current T, their residual norms ‖OP·y − θ·y‖_B, and
    /// the eigenvectors of T.
    pub(super) fn ritz(&self) -> Result<Ritz, SparseError> {
        let (p, m) = (self.p, self.nb * self.p);
        let t = self.t.as_ref().submatrix(0, 0, m, m).to_owned();
        let (theta, s) = crate::modal::dense::sym_eigen_pub(&t)
            .map_err(|_| ModalError::NoConvergence("projected Lanczos matrix".into()))?;
        let res = (0..m)
            .map(|c| {
                let mut acc = 0.0;
                for i in 0..p {
                    let mut x = 0.0;
                    for l in 0..p {
                        x += self.r[(i, l)] * s[(m - p + l, c)];
                    }
                    acc += x * x;
                }
                acc.sqrt()
            })
            .collect();
        Ok((theta, res, s))
    }

    /// Ritz vectors for the chosen columns of S, as (λ = σ + 1/θ, φ).
    pub(super) fn vectors(
        &self,
        s: &Mat<f64>,
        idx: &[usize],
        theta: &[f64],
        sigma: f64,
    ) -> Vec<(f64, Vec<f64>)> {
        let m = self.nb * self.p;
        let sel = Mat::<f64>::from_fn(m, idx.len(), |i, j| s[(i, idx[j])]);
        let mut y = Mat::<f64>::zeros(self.n, idx.len());
        matmul(
            y.as_mut(),
            Accum::Replace,
            self.basis(0, m),
            sel.as_ref(),
            1.0,
            Par::Seq,
        );
        idx.iter()
            .enumerate()
            .map(|(j, &c)| {
                (
                    sigma + 1.0 / theta[c],
                    (0..self.n).map(|i| y[(i, j)]).collect(),
                )
            })
            .collect()
    }
}

/// A rows × [`SKETCH`] matrix of independent standard normal values (Box–Muller: two uniform
/// draws per value, the sine half unused; rand's distributions crate is not a dependency).
fn gaussian(rows: usize, rng: &mut ChaCha8Rng) -> Mat<f64> {
    Mat::<f64>::from_fn(rows, SKETCH, |_, _| {
        let (u1, u2) = (1.0 - rng.random::<f64>(), rng.random::<f64>());
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    })
}

fn col_vec(m: &Mat<f64>, c: usize) -> Vec<f64> {
    col_vec_ref(m.as_ref(), c)
}

fn col_vec_ref(m: MatRef<'_, f64>, c: usize) -> Vec<f64> {
    (0..m.nrows()).map(|i| m[(i, c)]).collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    y.iter_mut().zip(x).for_each(|(y, x)| *y += alpha * x);
}

#[cfg(test)]
mod tests {
    use super::super::testing::{identity, max_diff};
    use super::*;

    /// Shift-invert at σ = 0 on K = diag(1, …, 60), M = I: OP·v = K⁻¹·v, θ = 1/λ. After
    /// the basis is full (7 blocks of 8) the largest Ritz value is 1 (λ₁ = 1) within its
    /// residual (OP is M-self-adjoint, so |δθ| ≤ r), that residual is below RESIDUAL_TOL
    /// (block Lanczos converges at the rate of the gap to θ₉ = 1/9: 1/T₇(17) ≈ 4e-11), and the
    /// basis is M-orthonormal to O(ε) (1e-12 over 56 vectors).
    #[test]
    fn lanczos_finds_the_top_of_a_diagonal_operator() {
        let n = 60;
        let b = identity(n);
        let op = |_v: MatRef<'_, f64>, bv: MatRef<'_, f64>| {
            Mat::<f64>::from_fn(n, bv.ncols(), |i, j| bv[(i, j)] / (1 + i) as f64)
        };
        let empty = Mat::<f64>::zeros(n, 0);
        let mut lz = Lanczos::new(n, BLOCK, 56, empty.as_ref(), 3, &mut None);
        lz.start(&b);
        while lz.step(&op, &b) {}
        let (theta, res, s) = lz.ritz().unwrap();
        let top = theta.len() - 1;
        assert!(
            (theta[top] - 1.0).abs() <= res[top].max(1e-14),
            "{}",
            theta[top]
        );
        assert!(res[top] < RESIDUAL_TOL_FOR_TEST, "{}", res[top]);
        let v = lz.basis(0, lz.blocks() * BLOCK).to_owned();
        let eye = Mat::<f64>::identity(v.ncols(), v.ncols());
        assert!(max_diff(&(v.transpose() * &v), &eye) < 1e-12);
        // The Ritz vector of λ₁ = σ + 1/θ is ±e₀.
        let pairs = lz.vectors(&s, &[top], &theta, 0.0);
        assert!((pairs[0].0 - 1.0).abs() < 1e-10);
        assert!((pairs[0].1[0].abs() - 1.0).abs() < 1e-10);
    }

    /// The fallback of the block normalisation: a block with a repeated column (CholQR2
    /// refuses it) still comes out B-orthonormal (1e-12) with U_in = U·R (1e-12), the repeated
    /// column replaced by a fresh direction with a zero column in R.
    #[test]
    fn a_rank_deficient_block_is_normalised_by_the_fallback() {
        let n = 30;
        let b = identity(n);
        let empty = Mat::<f64>::zeros(n, 0);
        let mut lz = Lanczos::new(n, 4, 24, empty.as_ref(), 7, &mut None);
        let mut u0 = Mat::<f64>::from_fn(n, 4, |i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
        for i in 0..n {
            u0[(i, 2)] = u0[(i, 0)];
        }
        let (u, bu, r, exhausted) = lz.normalize(u0.clone(), None, &b, 0);
        assert!(!exhausted);
        assert!(max_diff(&(u.transpose() * &bu), &Mat::<f64>::identity(4, 4)) < 1e-12);
        assert!(max_diff(&(&u * &r), &u0) < 1e-12);
        assert_eq!(r[(2, 2)], 0.0);
    }

    /// Locked vectors are deflated: with e₀ locked the top Ritz value is 1/2 (λ₂ = 2).
    #[test]
    fn locked_vectors_are_deflated() {
        let n = 60;
        let b = identity(n);
        let op = |_v: MatRef<'_, f64>, bv: MatRef<'_, f64>| {
            Mat::<f64>::from_fn(n, bv.ncols(), |i, j| bv[(i, j)] / (1 + i) as f64)
        };
        let locked = Mat::<f64>::from_fn(n, 1, |i, _| if i == 0 { 1.0 } else { 0.0 });
        let mut lz = Lanczos::new(n, BLOCK, 48, locked.as_ref(), 4, &mut None);
        lz.start(&b);
        while lz.step(&op, &b) {}
        let (theta, res, _) = lz.ritz().unwrap();
        let top = theta.len() - 1;
        assert!(
            (theta[top] - 0.5).abs() <= res[top].max(1e-14),
            "{}",
            theta[top]
        );
    }

    /// The acceptance level of the solvers' Ritz residuals (module doc of `sparse`).
    const RESIDUAL_TOL_FOR_TEST: f64 = super::super::RESIDUAL_TOL;
}
