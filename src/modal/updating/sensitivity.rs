//! Eigenvalue sensitivities (Fox & Kapoor 1968): for K·φ = λ·M·φ with φ mass-normalised,
//! dλ/dp = φᵀ·(∂K/∂p − λ·∂M/∂p)·φ. The matrix derivatives come from the model assembled at two
//! values of p (a difference of matrices, cheap and exact for the K and M that are linear in p,
//! such as spring stiffnesses, lumped masses and Young's modulus); no eigen-solve is repeated.

use crate::fem::model::Triplets;
use std::f64::consts::PI;

/// φᵀ·A·φ of a matrix stored as triplets (both triangles, duplicates adding).
pub fn quadratic(a: &Triplets, phi: &[f64]) -> f64 {
    a.iter().map(|&(i, j, v)| phi[i] * v * phi[j]).sum()
}

/// The model's reduced K and M at one value of a parameter.
pub struct Assembled<'a> {
    pub p: f64,
    pub k: &'a Triplets,
    pub m: &'a Triplets,
}

/// dλ/dp of the mode (λ, φ) from the matrices at two values of p (central or one-sided).
pub fn eigenvalue_derivative(lo: &Assembled, hi: &Assembled, lambda: f64, phi: &[f64]) -> f64 {
    let dk = quadratic(hi.k, phi) - quadratic(lo.k, phi);
    let dm = quadratic(hi.m, phi) - quadratic(lo.m, phi);
    (dk - lambda * dm) / (hi.p - lo.p)
}

/// df/dp from dλ/dp: f = √λ/(2π), so df/dλ = 1/(8π²·f).
pub fn frequency_derivative(dlambda_dp: f64, f_hz: f64) -> f64 {
    dlambda_dp / (8.0 * PI * PI * f_hz)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two springs k1 (ground–1), k2 (1–2), masses m1, m2: the sensitivity of each eigenvalue
    /// to k2 against the closed-form eigenvalues differentiated by central difference (1e-6).
    #[test]
    fn two_dof_chain_matches_the_closed_form() {
        let (k1, m1, m2) = (1000.0, 2.0, 1.0);
        let lambdas = |k2: f64| {
            // det(K − λM) = 0 for K = [[k1+k2, −k2], [−k2, k2]], M = diag(m1, m2).
            let a = m1 * m2;
            let b = -((k1 + k2) * m2 + k2 * m1);
            let c = k1 * k2;
            let d = (b * b - 4.0 * a * c).sqrt();
            [(-b - d) / (2.0 * a), (-b + d) / (2.0 * a)]
        };
        let kmat = |k2: f64| vec![(0, 0, k1 + k2), (0, 1, -k2), (1, 0, -k2), (1, 1, k2)];
        let m: Triplets = vec![(0, 0, m1), (1, 1, m2)];
        let k2 = 500.0;
        for (n, lam) in lambdas(k2).into_iter().enumerate() {
            // Mass-normalised φ of (K − λM)φ = 0: φ = (k2, k1 + k2 − λ m1) scaled.
            let v = [k2, k1 + k2 - lam * m1];
            let s = (m1 * v[0] * v[0] + m2 * v[1] * v[1]).sqrt();
            let phi = [v[0] / s, v[1] / s];
            let (klo, khi) = (kmat(k2 - 1.0), kmat(k2 + 1.0));
            let lo = Assembled {
                p: k2 - 1.0,
                k: &klo,
                m: &m,
            };
            let hi = Assembled {
                p: k2 + 1.0,
                k: &khi,
                m: &m,
            };
            let got = eigenvalue_derivative(&lo, &hi, lam, &phi);
            let h = 1e-6 * k2;
            let want = (lambdas(k2 + h)[n] - lambdas(k2 - h)[n]) / (2.0 * h);
            assert!(
                (got - want).abs() < 1e-6 * want.abs(),
                "mode {n}: {got} vs {want}"
            );
        }
    }
}
