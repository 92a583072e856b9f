//! The SEREP test-analysis mass matrix (O'Callahan, Avitabile & Riemer, "System Equivalent
//! Reduction Expansion Process", IMAC 1989) and the cross-orthogonality it weights.
//!
//! With Φ the mass-normalised FE modes over all DOFs and Φ_a their rows at the test DOFs
//! (n test DOFs × m modes, n ≥ m, full column rank), the expansion is T = Φ·Φ_a⁺ and the test-
//! analysis mass M_a = Tᵀ·M·T = (Φ_a⁺)ᵀ·(ΦᵀMΦ)·Φ_a⁺ = (Φ_a⁺)ᵀ·Φ_a⁺, since ΦᵀMΦ = I. Then
//! Φ_aᵀ·M_a·Φ_a = (Φ_a⁺Φ_a)ᵀ(Φ_a⁺Φ_a) = I exactly for the m modes kept, whatever test DOFs
//! are chosen: SEREP preserves the modes it is built from, where Guyan reduction is exact only
//! when the omitted DOFs carry no mass.

use nalgebra::DMatrix;

/// Smallest singular value of Φ_a, relative to the largest, for the test DOFs to tell the m
/// modes apart; below it the pseudo-inverse amplifies round-off into the mass matrix.
const MIN_RELATIVE_SINGULAR_VALUE: f64 = 1e-8;

/// M_a (n × n) from the FE shapes at the test DOFs, one `Vec` of n values per mode. An error
/// says why the test DOFs cannot carry the m modes.
pub fn serep_mass(fe_at_test: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, String> {
    let m = fe_at_test.len();
    let n = fe_at_test.first().map_or(0, Vec::len);
    if m == 0 || n < m {
        return Err(format!(
            "SEREP needs at least as many test DOFs as paired modes: {n} test DOF(s), {m} mode(s)"
        ));
    }
    let phi_a = DMatrix::from_fn(n, m, |i, j| fe_at_test[j][i]);
    let svd = phi_a.clone().svd(true, true);
    let s = &svd.singular_values;
    let (smax, smin) = (s.max(), s.min());
    if smin.is_nan() || smin <= MIN_RELATIVE_SINGULAR_VALUE * smax {
        return Err(format!(
            "the test DOFs do not tell the {m} paired FE modes apart (singular values of the shapes at the test DOFs {smin:.3e} … {smax:.3e})"
        ));
    }
    let pinv = svd
        .pseudo_inverse(MIN_RELATIVE_SINGULAR_VALUE * smax)
        .map_err(|e| e.to_string())?;
    let ma = pinv.transpose() * &pinv;
    Ok((0..n)
        .map(|i| (0..n).map(|j| ma[(i, j)]).collect())
        .collect())
}

/// Normalised cross-orthogonality |tᵀ·M_a·f| / √((tᵀM_a t)(fᵀM_a f)) of every test shape (rows)
/// with every FE shape (columns): the mass-weighted counterpart of the MAC, 1 on the
/// diagonal and 0 off it for mass-orthogonal modes. 0 for a shape of zero mass-norm.
pub fn cross_orthogonality(test: &[Vec<f64>], fe: &[Vec<f64>], ma: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let form = |a: &[f64], b: &[f64]| -> f64 {
        ma.iter()
            .enumerate()
            .map(|(i, row)| a[i] * row.iter().zip(b).map(|(m, y)| m * y).sum::<f64>())
            .sum()
    };
    test.iter()
        .map(|t| {
            fe.iter()
                .map(|f| {
                    let (tt, ff) = (form(t, t), form(f, f));
                    if tt <= 0.0 || ff <= 0.0 {
                        return 0.0;
                    }
                    (form(t, f).abs() / (tt * ff).sqrt()).min(1.0)
                })
                .collect()
        })
        .collect()
}
