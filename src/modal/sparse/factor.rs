//! LDLᵀ of K − σM for any shift σ, and its Sturm count.
//!
//! K − σM is assembled once on the union sparsity pattern of K and M (lower triangle), ordered
//! once with faer's approximate minimum degree (AMD), analysed once (faer picks simplicial or
//! supernodal), and refactorised numerically for every shift σ as LDLᵀ without pivoting
//! (`faer::sparse::linalg::cholesky`, `Par::Seq`). By Sylvester's law of inertia the number of
//! negative pivots of D equals the number of eigenvalues below σ: that **Sturm count** at
//! σ = (2π·fmax)² says exactly how many modes lie below `fmax_hz`, and it is what proves the
//! answer complete ([`super::sturm_check`]). LDLᵀ without pivoting can in principle lose its inertia
//! on an indefinite matrix; a wrong count cannot go unnoticed here, because every count is
//! matched against converged eigenpairs and a mismatch fails loudly.

use super::SparseError;
use super::csc::SymCsc;
use super::eigen::SparseStats;
use super::kernels::simd_dispatch;
use super::layout::{gather_rows, scatter_rows, with_scratch};
use crate::error::ModalError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky, simplicial::SimplicialLdltRef, supernodal::SupernodalLdltRef,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par, Side};

/// A pivot d_i of an SPD factorization with d_i ≤ this × A_ii marks a singular direction:
/// d_i/A_ii is the reciprocal of a condition number, and rounding alone leaves it near 1e-16
/// on an exact mechanism.
pub const SINGULAR_PIVOT: f64 = 1e-12;

/// K − σ·M on one lower-triangular pattern (the union of both), with its symbolic analysis
/// (AMD ordering, elimination tree, supernodes) done once for every shift.
pub struct Pencil {
    pub n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    kv: Vec<f64>,
    mv: Vec<f64>,
    pub(super) diag_k: Vec<f64>,
    pub(super) diag_m: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
}

/// LDLᵀ of K − σM: the values and the pivots (in the elimination order).
pub struct Factor<'a> {
    pencil: &'a Pencil,
    pub sigma: f64,
    values: Vec<f64>,
    /// D in elimination order.
    pivots: Vec<f64>,
    /// Number of negative pivots = number of eigenvalues below σ.
    pub negative: usize,
}

impl Pencil {
    /// `m = None` gives the pencil (K, 0): a plain factorization of K.
    pub fn new(k: &SymCsc, m: Option<&SymCsc>) -> Result<Pencil, SparseError> {
        let n = k.n;
        // Merge the lower triangles column by column (rows sorted in both).
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::new();
        let mut kv = Vec::new();
        let mut mv = Vec::new();
        for j in 0..n {
            let lower = |a: &SymCsc| -> Vec<(usize, f64)> {
                (a.col_ptr[j]..a.col_ptr[j + 1])
                    .filter(|&p| a.row_idx[p] >= j)
                    .map(|p| (a.row_idx[p], a.val[p]))
                    .collect()
            };
            let ka = lower(k);
            let ma = m.map(lower).unwrap_or_default();
            let (mut a, mut b) = (0, 0);
            // The diagonal is always present, so that a shift never meets a missing entry.
            let mut diag_seen = false;
            while a < ka.len() || b < ma.len() {
                let ra = ka.get(a).map(|x| x.0).unwrap_or(usize::MAX);
                let rb = ma.get(b).map(|x| x.0).unwrap_or(usize::MAX);
                let r = ra.min(rb);
                if r > j && !diag_seen {
                    row_idx.push(j);
                    kv.push(0.0);
                    mv.push(0.0);
                    diag_seen = true;
                    continue;
                }
                diag_seen |= r == j;
                let mut vk = 0.0;
                let mut vm = 0.0;
                if ra == r {
                    vk = ka[a].1;
                    a += 1;
                }
                if rb == r {
                    vm = ma[b].1;
                    b += 1;
                }
                row_idx.push(r);
                kv.push(vk);
                mv.push(vm);
            }
            if !diag_seen {
                row_idx.push(j);
                kv.push(0.0);
                mv.push(0.0);
            }
            col_ptr[j + 1] = row_idx.len();
        }
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| {
            SparseError::Modal(ModalError::Invalid(format!(
                "sparse symbolic analysis failed: {e:?}"
            )))
        })?;
        let diag_k = k.diag();
        let diag_m = m.map(|m| m.diag()).unwrap_or_else(|| vec![0.0; n]);
        Ok(Pencil {
            n,
            col_ptr,
            row_idx,
            kv,
            mv,
            diag_k,
            diag_m,
            symbolic,
        })
    }

    /// Original index of the i-th eliminated unknown. faer's supernodal LDLᵀ may report a
    /// zero pivot at the end of its supernode, one past the last unknown: clamped.
    pub(super) fn original(&self, i: usize) -> usize {
        let i = i.min(self.n.saturating_sub(1));
        match self.symbolic.perm() {
            Some(p) => p.arrays().0[i],
            None => i,
        }
    }

    /// Bytes held by the factor's values.
    pub fn factor_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// LDLᵀ of K − σM. An exactly zero pivot is reported with its (input-order) index.
    pub fn factor(&self, sigma: f64) -> Result<Factor<'_>, SparseError> {
        let n = self.n;
        let vals: Vec<f64> = self
            .kv
            .iter()
            .zip(&self.mv)
            .map(|(k, m)| k - sigma * m)
            .collect();
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &vals,
        );
        let mut values = vec![0.0; self.symbolic.len_val()];
        let req = self
            .symbolic
            .factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default());
        let mut mem = MemBuffer::new(req);
        self.symbolic
            .factorize_numeric_ldlt(
                &mut values,
                a,
                Side::Lower,
                LdltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| match e {
                faer::linalg::cholesky::ldlt::factor::LdltError::ZeroPivot { index } => {
                    SparseError::NotPositiveDefinite {
                        index: self.original(index),
                    }
                }
            })?;
        let mut pivots = vec![0.0; n];
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let l = SimplicialLdltRef::new(s, &values);
                let f = s.factor();
                let (cp, ri) = (f.col_ptr(), f.row_idx());
                for j in 0..n {
                    for p in cp[j]..cp[j + 1] {
                        if ri[p] == j {
                            pivots[j] = l.values()[p];
                        }
                    }
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = SupernodalLdltRef::new(s, &values);
                for k in 0..s.n_supernodes() {
                    let sn = l.supernode(k);
                    let start = sn.start();
                    let v = sn.val();
                    for i in 0..v.ncols() {
                        pivots[start + i] = v[(i, i)];
                    }
                }
            }
        }
        let negative = pivots.iter().filter(|&&d| d < 0.0).count();
        if let Some(i) = pivots.iter().position(|d| !d.is_finite()) {
            return Err(SparseError::NotPositiveDefinite {
                index: self.original(i),
            });
        }
        Ok(Factor {
            pencil: self,
            sigma,
            values,
            pivots,
            negative,
        })
    }
}

impl Factor<'_> {
    /// Solves (K − σM)·X = B in place.
    pub fn solve(&self, mut rhs: MatMut<'_, f64>) {
        if let SymbolicCholeskyRaw::Simplicial(s) = self.pencil.symbolic.raw() {
            let f = s.factor();
            let (cp, ri) = (f.col_ptr(), f.row_idx());
            // faer's simplicial LDLᵀ keeps D as the first entry of every column of L.
            if (0..self.pencil.n).all(|j| cp[j] < cp[j + 1] && ri[cp[j]] == j) {
                self.solve_simplicial(cp, ri, rhs);
                return;
            }
        }
        let sym = &self.pencil.symbolic;
        let req = sym.solve_in_place_scratch::<f64>(rhs.ncols(), Par::Seq);
        let mut mem = MemBuffer::new(req);
        LdltRef::new(sym, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }

    /// P·(K − σM)·Pᵀ = L·D·Lᵀ solved for eight right-hand sides at a time, interleaved: every
    /// entry of L then updates eight contiguous values (one SIMD register) instead of eight
    /// strided columns, which faer's column-at-a-time triangular solves do. L of the stack
    /// holds about 5 entries per unknown, so the solve is bound by these memory accesses
    /// (measured: 0.66 s → 0.40 s of the 60-satellite solve, one thread).
    fn solve_simplicial(&self, cp: &[usize], ri: &[usize], mut rhs: MatMut<'_, f64>) {
        const W: usize = 8;
        let n = self.pencil.n;
        let inv = self.pencil.symbolic.perm().map(|p| p.arrays().1);
        let l = &self.values;
        with_scratch(n, |x, _| {
            for c0 in (0..rhs.ncols()).step_by(W) {
                let w = W.min(rhs.ncols() - c0);
                gather_rows(rhs.as_ref(), c0, w, inv, x);
                simd_dispatch!(ldlt_sweeps(cp, ri, l, x));
                scatter_rows(x, c0, w, inv, rhs.as_mut());
            }
        });
    }

    /// The first pivot (in elimination order) that is not clearly positive, relative to the
    /// diagonal of K − σM at that unknown, as an input-order index.
    pub fn first_singular(&self) -> Option<usize> {
        let p = self.pencil;
        (0..p.n).find_map(|i| {
            let o = p.original(i);
            let a = (p.diag_k[o] - self.sigma * p.diag_m[o]).abs();
            (self.pivots[i] <= SINGULAR_PIVOT * a).then_some(o)
        })
    }

    /// A_ii / d_i of every unknown, in input order: the ratio Nastran reports as MAXRATIO at
    /// its largest (the digits of A_ii the elimination lost).
    pub fn pivot_ratios(&self) -> Vec<f64> {
        let p = self.pencil;
        let mut ratio = vec![1.0; p.n];
        for i in 0..p.n {
            let o = p.original(i);
            let a = p.diag_k[o] - self.sigma * p.diag_m[o];
            ratio[o] = a / self.pivots[i];
        }
        ratio
    }

    /// Smallest |d_i| / |A_ii|: how close σ sits to an eigenvalue.
    pub(super) fn min_relative_pivot(&self) -> f64 {
        self.smallest_relative_pivot().0
    }

    /// Componentwise backward error (Oettli–Prager) of one solve with this factor:
    /// max_i |(A·x − b)_i| / (|A|·|x| + |b|)_i for A = K − σM and a fixed right-hand side
    /// with entries of both signs and sizes. Round-off leaves it near 1e-16; a tiny pivot
    /// (σ on an eigenvalue of a leading block of A, not of A itself) leaves the element
    /// growth of the factor in it.
    pub fn backward_error(&self) -> f64 {
        let p = self.pencil;
        let b: Vec<f64> = (0..p.n)
            .map(|i| (1.0 + (i % 17) as f64 / 17.0) * if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let mut x = Mat::<f64>::from_fn(p.n, 1, |i, _| b[i]);
        self.solve(x.as_mut());
        let x = x.col(0);
        let mut residual: Vec<f64> = b.iter().map(|v| -v).collect();
        let mut scale: Vec<f64> = b.iter().map(|v| v.abs()).collect();
        for j in 0..p.n {
            for q in p.col_ptr[j]..p.col_ptr[j + 1] {
                let i = p.row_idx[q];
                let a = p.kv[q] - self.sigma * p.mv[q];
                residual[i] += a * x[j];
                scale[i] += (a * x[j]).abs();
                if i != j {
                    residual[j] += a * x[i];
                    scale[j] += (a * x[i]).abs();
                }
            }
        }
        residual
            .iter()
            .zip(&scale)
            .map(|(r, s)| if *s > 0.0 { r.abs() / s } else { 0.0 })
            .fold(0.0, f64::max)
    }

    /// The smallest |pivot| / |diagonal entry| and its index in the input ordering.
    fn smallest_relative_pivot(&self) -> (f64, usize) {
        let p = self.pencil;
        (0..p.n)
            .map(|i| {
                let o = p.original(i);
                let a = (p.diag_k[o] - self.sigma * p.diag_m[o]).abs();
                let r = if a > 0.0 {
                    self.pivots[i].abs() / a
                } else {
                    f64::INFINITY
                };
                (r, o)
            })
            .fold((f64::INFINITY, 0), |b, x| if x.0 < b.0 { x } else { b })
    }
}

/// Factors K − σM, nudging σ upwards by a tiny relative step while it sits (numerically) on
/// an eigenvalue, so that the count is unambiguous.
pub(super) fn factor_away_from_eigenvalue<'a>(
    pencil: &'a Pencil,
    sigma: f64,
    stats: &mut SparseStats,
) -> Result<Factor<'a>, SparseError> {
    let mut s = sigma;
    let mut worst = (0.0, 0);
    for _ in 0..8 {
        stats.factorizations += 1;
        match pencil.factor(s) {
            Ok(f) if f.min_relative_pivot() > 1e-13 => return Ok(f),
            Ok(f) => worst = f.smallest_relative_pivot(),
            Err(SparseError::NotPositiveDefinite { index }) => worst = (0.0, index),
            Err(e) => return Err(e),
        }
        s += 1e-9 * s.abs().max(f64::MIN_POSITIVE);
    }
    Err(SparseError::SingularNear {
        sigma,
        index: worst.1,
        relative_pivot: worst.0,
    })
}

/// Largest backward error of a factor whose solves drive an iteration (a Lanczos or subspace
/// shift). The stacks' factors measure 2e-16–1.2e-10 (686 factorizations of the 60-satellite
/// solve, median 1e-14); a shift on a diagonal entry of the spring chain's K − σM, 8e-3.
pub const SOLVE_BACKWARD_TOL: f64 = 1e-9;
/// Relative moves of a shift whose factor does not solve accurately: 1e-8, then ten times
/// more each time.
const ACCURATE_TRIES: usize = 6;

/// `fac`, or a factor of K − σ'M near its σ, whose solves are accurate
/// ([`SOLVE_BACKWARD_TOL`]): LDLᵀ without pivoting grows without bound when a pivot is tiny,
/// which a shift that is not near any eigenvalue of the pencil can still meet (a shift equal
/// to K_ii/M_ii, say). The shift then moves down by 1e-8, 1e-7, … relative (every caller's
/// shift sits just below what it aims at); the Sturm count holds at the σ' returned. If
/// none passes, the least inaccurate factor is returned: the eigenpairs are checked against
/// K and M afterwards, so an iteration on it fails loudly rather than silently.
pub(super) fn accurate_factor<'a>(
    pencil: &'a Pencil,
    fac: Factor<'a>,
    stats: &mut SparseStats,
) -> Result<Factor<'a>, SparseError> {
    let eta = fac.backward_error();
    if eta <= SOLVE_BACKWARD_TOL {
        return Ok(fac);
    }
    let sigma = fac.sigma;
    let mut best = (eta, fac);
    let mut step = 1e-8;
    for _ in 0..ACCURATE_TRIES {
        let s = sigma - step * sigma.abs().max(f64::MIN_POSITIVE);
        let fac = factor_away_from_eigenvalue(pencil, s, stats)?;
        let eta = fac.backward_error();
        if eta <= SOLVE_BACKWARD_TOL {
            return Ok(fac);
        }
        if eta < best.0 {
            best = (eta, fac);
        }
        step *= 10.0;
    }
    Ok(best.1)
}

/// Relative half-width of the gap a partition point of the spectrum keeps from every
/// eigenvalue: 100× the first-order error bound of an accepted Ritz value
/// ([`super::RESIDUAL_TOL`]), so that no eigenvalue counted on one side of the point can be
/// computed on the other.
pub const EDGE_GAP: f64 = 1e-8;
/// Steps of 2·[`EDGE_GAP`] tried before a partition point is used where it is.
const GAP_STEPS: usize = 64;

/// A partition point of the spectrum (the band's top, a band cut, a slice's shift or edge):
/// a point whose count says on which side of it an eigenvalue lies, returned as (σ, count).
/// If an eigenvalue sat within a Ritz value's error of it (a copy of a repeated mode counted
/// below the point but computed just above it), the slice would never complete. So σ moves
/// up by 2·EDGE_GAP·|σ| at a time until the counts at σ·(1 ∓ EDGE_GAP) agree: no eigenvalue
/// is then within EDGE_GAP of σ, a cluster of repeated modes that straddled it lies wholly
/// below, and the count at σ is theirs (Sylvester), so K − σM itself need not be factored.
/// Where the spectrum has no such gap within GAP_STEPS steps, σ itself is factored and used
/// (the count is still exact; the slices' own checks then decide).
pub(super) fn point_in_gap(
    pencil: &Pencil,
    sigma: f64,
    stats: &mut SparseStats,
) -> Result<(f64, usize), SparseError> {
    match gap_at_or_above(pencil, sigma, stats)? {
        Some(point) => Ok(point),
        None => {
            let fac = factor_away_from_eigenvalue(pencil, sigma, stats)?;
            Ok((fac.sigma, fac.negative))
        }
    }
}

/// [`point_in_gap`] for a point whose factor is needed (a Lanczos shift), starting from the
/// factor already made at `fac.sigma`: it is kept when that point is already in a gap.
pub(super) fn factor_in_gap<'a>(
    pencil: &'a Pencil,
    fac: Factor<'a>,
    stats: &mut SparseStats,
) -> Result<Factor<'a>, SparseError> {
    match gap_at_or_above(pencil, fac.sigma, stats)? {
        Some((s, _)) if s == fac.sigma => Ok(fac),
        Some((s, _)) => factor_away_from_eigenvalue(pencil, s, stats),
        None => Ok(fac),
    }
}

/// The first σ' = σ + 2j·EDGE_GAP·|σ'| (j < GAP_STEPS) with no eigenvalue within
/// EDGE_GAP·|σ'|, and its count; None when the spectrum has no such gap there.
fn gap_at_or_above(
    pencil: &Pencil,
    sigma: f64,
    stats: &mut SparseStats,
) -> Result<Option<(f64, usize)>, SparseError> {
    let mut s = sigma;
    for _ in 0..GAP_STEPS {
        let w = EDGE_GAP * s.abs().max(f64::MIN_POSITIVE);
        let below = factor_away_from_eigenvalue(pencil, s - w, stats)?.negative;
        let above = factor_away_from_eigenvalue(pencil, s + w, stats)?.negative;
        if below == above {
            return Ok(Some((s, below)));
        }
        s += 2.0 * w;
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::super::testing::{chain, chain_eigenvalues, csc, dense, diagonal, identity};
    use super::*;
    use faer::linalg::solvers::Solve;

    /// Sylvester's law of inertia: the negative pivots of K − σM count the eigenvalues below
    /// σ. Reference: the analytic spectrum of the spring chain, σ halfway between eigenvalues.
    #[test]
    fn sturm_count_is_the_number_of_eigenvalues_below_the_shift() {
        let (n, k) = (40, 3.0);
        let (kc, m) = (chain(n, k), identity(n));
        let pencil = Pencil::new(&kc, Some(&m)).unwrap();
        let lambda = chain_eigenvalues(n, k);
        // Counted as the solvers count: a pivot that happens to vanish without pivoting
        // moves the shift by a relative 1e-9, far from any eigenvalue here.
        let mut stats = SparseStats::default();
        let mut count = |sigma: f64| {
            factor_away_from_eigenvalue(&pencil, sigma, &mut stats)
                .unwrap()
                .negative
        };
        assert_eq!(count(-0.1), 0);
        for below in [1, 7, 20, 39] {
            assert_eq!(count(0.5 * (lambda[below - 1] + lambda[below])), below);
        }
        assert_eq!(count(4.0 * k + 1.0), n);
    }

    /// The LDLᵀ of an indefinite K − σM (consistent chain mass, σ between the 5th and 6th
    /// eigenvalues) solves three right-hand sides as faer's dense LU does. ‖A‖·‖A⁻¹‖ stays
    /// below 1e3 here (‖A‖ ≤ 4k + |σ|, the nearest eigenvalue a gap of ~0.1 away), so both
    /// backward-stable solves agree to κ·ε ≈ 1e-13 relative; 1e-11 is asserted.
    #[test]
    fn indefinite_solve_matches_dense_lu() {
        let n = 30;
        let kc = chain(n, 1.0);
        let m = csc(n, |i, j| match i.abs_diff(j) {
            0 => 4.0 / 6.0,
            1 => 1.0 / 6.0,
            _ => 0.0,
        });
        let pencil = Pencil::new(&kc, Some(&m)).unwrap();
        let fac = pencil.factor(0.3).unwrap();
        assert!(fac.negative > 0 && fac.negative < n);
        let a = dense(&kc) - dense(&m) * faer::Scale(0.3);
        let b = Mat::<f64>::from_fn(n, 3, |i, j| ((i * (j + 2)) as f64).cos());
        let want = a.partial_piv_lu().solve(&b);
        let mut x = b.clone();
        fac.solve(x.as_mut());
        let scale = (0..3).map(|j| want.col(j).norm_max()).fold(0.0, f64::max);
        let diff = (&x - &want).norm_max();
        assert!(diff < 1e-11 * scale, "{diff} vs {scale}");
    }

    /// A chain free at both ends (no walls: the end diagonals are k) has the rigid
    /// translation as a zero-energy mode: the factor names a singular unknown. Anchored, none.
    #[test]
    fn first_singular_finds_the_mechanism() {
        let n = 6;
        let free = csc(n, |i, j| match i.abs_diff(j) {
            0 if i == 0 || i == n - 1 => 1.0,
            0 => 2.0,
            1 => -1.0,
            _ => 0.0,
        });
        let singular = match Pencil::new(&free, None).unwrap().factor(0.0) {
            Ok(f) => f.first_singular().is_some(),
            Err(SparseError::NotPositiveDefinite { .. }) => true,
            Err(e) => panic!("{e:?}"),
        };
        assert!(singular);
        let anchored = Pencil::new(&chain(n, 1.0), None).unwrap();
        assert_eq!(anchored.factor(0.0).unwrap().first_singular(), None);
    }

    /// A shift exactly on an eigenvalue (2 of diag(1, 2, 3)) moves up by a relative 1e-9,
    /// and the count then says 2 below.
    #[test]
    fn a_shift_on_an_eigenvalue_is_nudged_off_it() {
        let (kc, m) = (diagonal(&[1.0, 2.0, 3.0]), identity(3));
        let pencil = Pencil::new(&kc, Some(&m)).unwrap();
        let mut stats = SparseStats::default();
        let fac = factor_away_from_eigenvalue(&pencil, 2.0, &mut stats).unwrap();
        assert!(fac.sigma > 2.0 && fac.sigma < 2.0 + 1e-8);
        assert_eq!(fac.negative, 2);
        assert!(stats.factorizations >= 2);
    }

    /// A shift a hair off K_ii/M_ii of a 48-mass chain (σ = 2 + 2e-15, between two
    /// eigenvalues 0.064 apart, where a band's first shift landed) leaves every other pivot
    /// of LDLᵀ without pivoting at 2e-15, each one exact relative to its own diagonal entry,
    /// and the factor solves nothing (backward error ≫ SOLVE_BACKWARD_TOL). The accurate
    /// factor moves below it, solves to the tolerance, and its count is the analytic 24
    /// below 2 (λ_24 = 1.936, λ_25 = 2.064).
    #[test]
    fn a_shift_whose_factor_grows_moves_to_one_that_solves() {
        let n = 48;
        let pencil = Pencil::new(&chain(n, 1.0), Some(&identity(n))).unwrap();
        let mut stats = SparseStats::default();
        let plain = factor_away_from_eigenvalue(&pencil, 2.0 + 2e-15, &mut stats).unwrap();
        assert!(plain.backward_error() > 1e3 * SOLVE_BACKWARD_TOL);
        let fac = accurate_factor(&pencil, plain, &mut stats).unwrap();
        assert!(fac.backward_error() <= SOLVE_BACKWARD_TOL);
        assert!(
            fac.sigma < 2.0 && fac.sigma > 2.0 * (1.0 - 1e-2),
            "{}",
            fac.sigma
        );
        let below = chain_eigenvalues(n, 1.0)
            .iter()
            .filter(|&&l| l < fac.sigma)
            .count();
        assert_eq!((fac.negative, below), (24, 24));
    }

    /// A partition point within EDGE_GAP of an eigenvalue (2 of diag(1, 2, 2 + 1e-9, 3), a
    /// pair closer than EDGE_GAP) moves above both, and its count (three below) is the
    /// count of a factorization made there (Sylvester); a point already in a gap stays, and
    /// a shift's factor is kept as it is.
    #[test]
    fn a_partition_point_moves_into_a_gap_and_keeps_its_count() {
        let (kc, m) = (diagonal(&[1.0, 2.0, 2.0 + 1e-9, 3.0]), identity(4));
        let pencil = Pencil::new(&kc, Some(&m)).unwrap();
        let mut stats = SparseStats::default();
        let (sigma, count) = point_in_gap(&pencil, 2.0, &mut stats).unwrap();
        assert!(sigma > (2.0 + 1e-9) * (1.0 + EDGE_GAP), "{sigma}");
        assert!(
            sigma < 2.0 + 2.0 * GAP_STEPS as f64 * EDGE_GAP * 2.1,
            "{sigma}"
        );
        assert_eq!(count, 3);
        assert_eq!(pencil.factor(sigma).unwrap().negative, count);
        assert_eq!(point_in_gap(&pencil, 2.5, &mut stats).unwrap(), (2.5, 3));
        let before = stats.factorizations;
        let kept = factor_in_gap(&pencil, pencil.factor(2.5).unwrap(), &mut stats).unwrap();
        assert_eq!((kept.sigma, kept.negative), (2.5, 3));
        assert_eq!(stats.factorizations - before, 2, "the two sides only");
    }
}
