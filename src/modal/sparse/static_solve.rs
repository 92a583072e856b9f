//! The prestress static solve K·u = f on the sparse LDLᵀ, with one step of iterative
//! refinement.

use super::SparseError;
use super::csc::SymCsc;
use super::factor::{Factor, Pencil};
use faer::{Mat, Par};

/// Solves K·u = f with K symmetric positive definite (sparse LDLᵀ, one step of iterative
/// refinement). A pivot that is not clearly positive names the unknown where K is singular.
pub fn solve_spd(k: &SymCsc, f: &[f64]) -> Result<Vec<f64>, SparseError> {
    faer::set_global_parallelism(Par::Seq);
    let pencil = Pencil::new(k, None)?;
    let fac = pencil.factor(0.0)?;
    if let Some(index) = fac.first_singular() {
        return Err(SparseError::NotPositiveDefinite { index });
    }
    Ok(solve_refined(k, &fac, f))
}

fn solve_refined(k: &SymCsc, fac: &Factor<'_>, f: &[f64]) -> Vec<f64> {
    let n = f.len();
    let mut x = Mat::<f64>::from_fn(n, 1, |i, _| f[i]);
    fac.solve(x.as_mut());
    let kx = k.mul(x.as_ref());
    let mut r = Mat::<f64>::from_fn(n, 1, |i, _| f[i] - kx[(i, 0)]);
    fac.solve(r.as_mut());
    (0..n).map(|i| x[(i, 0)] + r[(i, 0)]).collect()
}

#[cfg(test)]
mod tests {
    use super::super::testing::csc;
    use super::*;

    /// n springs of stiffness k in a row, anchored at one end, pulled by F at the other:
    /// every spring carries F, so u_i = (i + 1)·F/k. With one step of refinement the
    /// forward error is of order ε·κ(K) (κ ≈ 4n²/π² ≈ 160 for n = 20): 1e-12 relative.
    #[test]
    fn tip_load_on_an_anchored_chain_stretches_it_linearly() {
        let (n, k, f) = (20, 250.0, 3.0);
        let kc = csc(n, |i, j| match i.abs_diff(j) {
            0 if i == n - 1 => k,
            0 => 2.0 * k,
            1 => -k,
            _ => 0.0,
        });
        let mut load = vec![0.0; n];
        load[n - 1] = f;
        let u = solve_spd(&kc, &load).unwrap();
        for (i, ui) in u.iter().enumerate() {
            let want = (i + 1) as f64 * f / k;
            assert!((ui - want).abs() < 1e-12 * want, "{i}: {ui} vs {want}");
        }
    }

    /// Without its anchor the chain is a mechanism: no solve, the unknown is named.
    #[test]
    fn an_unanchored_chain_is_not_positive_definite() {
        let n = 5;
        let kc = csc(n, |i, j| match i.abs_diff(j) {
            0 if i == 0 || i == n - 1 => 1.0,
            0 => 2.0,
            1 => -1.0,
            _ => 0.0,
        });
        let e = solve_spd(&kc, &[1.0, 0.0, 0.0, 0.0, -1.0]).unwrap_err();
        assert!(matches!(e, SparseError::NotPositiveDefinite { index } if index < n));
    }
}
