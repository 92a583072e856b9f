//! What the weighted sensitivity matrix J (targets × scaled parameters) says about the fit:
//! its singular values, the parameter directions the data cannot resolve (right singular
//! vectors of singular values below [`REL_SINGULAR`] of the largest, and every direction beyond
//! the number of targets), the parameter correlation matrix and, from the residual, the
//! standard deviations of the linearised least-squares estimate: cov = s²(JᵀJ)⁻¹ with
//! s² = ‖r‖²/(m − n) (e.g. Bates & Watts, "Nonlinear Regression Analysis", 1988, §2.3).

use nalgebra::{DMatrix, DVector};

/// A singular value below this fraction of the largest is a direction the data do not fix:
/// the relative precision of the frequencies (solver backward error ~1e-12, amplified by the
/// condition number) leaves such a direction determined by round-off alone.
pub const REL_SINGULAR: f64 = 1e-6;
/// A parameter whose component in an unresolved direction reaches this is not identifiable.
pub const COMPONENT: f64 = 0.1;

#[derive(Debug, Clone)]
pub struct Identifiability {
    /// Singular values of J, descending (min(m, n) of them).
    pub singular_values: Vec<f64>,
    /// Unit directions in scaled parameters that the data do not resolve.
    pub unresolved: Vec<Vec<f64>>,
    /// Per parameter: no unresolved direction has a component ≥ [`COMPONENT`] along it.
    pub identifiable: Vec<bool>,
    /// Correlation of the estimates, from (JᵀJ + ρI)⁻¹.
    pub correlation: Vec<Vec<f64>>,
    /// Standard deviation of each scaled parameter; `None` unless m > n, every direction is
    /// resolved and there is no regularization (which biases the estimate).
    pub std_dev: Option<Vec<f64>>,
}

pub fn analyse(j: &DMatrix<f64>, r: &DVector<f64>, regularization: f64) -> Identifiability {
    let (m, n) = j.shape();
    // Zero rows up to n make the SVD return all n right singular vectors.
    let padded = DMatrix::from_fn(m.max(n), n, |i, k| if i < m { j[(i, k)] } else { 0.0 });
    let svd = padded.svd(false, true);
    let vt = svd.v_t.expect("asked for V");
    let mut order: Vec<usize> = (0..n).collect();
    let s = &svd.singular_values;
    order.sort_by(|&a, &b| s[b].total_cmp(&s[a]).then(a.cmp(&b)));
    let smax = s[order[0]];
    let unresolved: Vec<Vec<f64>> = order
        .iter()
        .filter(|&&k| smax <= 0.0 || s[k] < REL_SINGULAR * smax)
        .map(|&k| signed((0..n).map(|c| vt[(k, c)]).collect()))
        .collect();
    let identifiable = (0..n)
        .map(|c| unresolved.iter().all(|v| v[c].abs() < COMPONENT))
        .collect();
    let inverse = inverse_normal(j, regularization);
    let std_dev = (m > n && unresolved.is_empty() && regularization == 0.0).then(|| {
        let s2 = r.norm_squared() / (m - n) as f64;
        (0..n)
            .map(|c| (s2 * inverse[(c, c)]).max(0.0).sqrt())
            .collect()
    });
    Identifiability {
        singular_values: order.iter().take(m.min(n)).map(|&k| s[k]).collect(),
        unresolved,
        identifiable,
        correlation: correlation(&inverse),
        std_dev,
    }
}

/// A direction with its largest component positive, so that the output is deterministic.
fn signed(v: Vec<f64>) -> Vec<f64> {
    let big = v
        .iter()
        .copied()
        .fold(0.0, |a: f64, x| if x.abs() > a.abs() { x } else { a });
    if big < 0.0 {
        v.iter().map(|x| -x).collect()
    } else {
        v
    }
}

/// (JᵀJ + ρI)⁻¹, or its pseudo-inverse when singular.
fn inverse_normal(j: &DMatrix<f64>, regularization: f64) -> DMatrix<f64> {
    let n = j.ncols();
    let a = j.transpose() * j + DMatrix::identity(n, n) * regularization;
    a.clone()
        .try_inverse()
        .filter(|x| x.iter().all(|v| v.is_finite()))
        .unwrap_or_else(|| {
            let eps = REL_SINGULAR * REL_SINGULAR * a.norm();
            a.pseudo_inverse(eps)
                .unwrap_or_else(|_| DMatrix::zeros(n, n))
        })
}

/// C_ij / √(C_ii·C_jj); 0 where a variance is zero.
fn correlation(c: &DMatrix<f64>) -> Vec<Vec<f64>> {
    let n = c.nrows();
    (0..n)
        .map(|i| {
            (0..n)
                .map(|k| {
                    let d = c[(i, i)] * c[(k, k)];
                    if d > 0.0 {
                        (c[(i, k)] / d.sqrt()).clamp(-1.0, 1.0)
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect()
}

/// Two-sided 95% quantile t(0.975, ν) of Student's t: the table of NIST/SEMATECH
/// e-Handbook §1.3.6.7.2 to 30 degrees of freedom, then the Cornish–Fisher expansion about
/// the normal 1.959964 (error below 1e-4 for ν > 30).
pub fn t975(dof: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    if (1..=30).contains(&dof) {
        return TABLE[dof - 1];
    }
    let (z, v): (f64, f64) = (1.959_964, dof.max(1) as f64);
    z + (z.powi(3) + z) / (4.0 * v)
        + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * v * v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two columns that are multiples of each other (parameters entering as a product): one
    /// unresolved direction, (1, −1)/√2 up to sign, and neither parameter identifiable.
    #[test]
    fn a_product_is_not_identifiable() {
        let j = DMatrix::from_row_slice(3, 2, &[0.5, 0.5, 0.2, 0.2, 0.1, 0.1]);
        let id = analyse(&j, &DVector::zeros(3), 0.0);
        assert_eq!(id.unresolved.len(), 1);
        let v = &id.unresolved[0];
        assert!((v[0].abs() - 0.5f64.sqrt()).abs() < 1e-12 && (v[0] + v[1]).abs() < 1e-12);
        assert_eq!(id.identifiable, vec![false, false]);
        assert!(id.std_dev.is_none());
    }

    /// J = I₂ over three rows with r = (1, 1, 1): s² = 3/(3 − 2), std = √3 each, uncorrelated.
    #[test]
    fn independent_columns_give_the_textbook_covariance() {
        let j = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        let id = analyse(&j, &DVector::from_element(3, 1.0), 0.0);
        let sd = id.std_dev.unwrap();
        assert!((sd[0] - 3f64.sqrt()).abs() < 1e-12 && (sd[1] - 3f64.sqrt()).abs() < 1e-12);
        assert_eq!(id.correlation, vec![vec![1.0, 0.0], vec![0.0, 1.0]]);
        assert_eq!(id.identifiable, vec![true, true]);
    }
}
