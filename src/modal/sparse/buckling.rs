//! The linear buckling factor of (K + λ·K_G)·φ = 0 on the sparse LDLᵀ, by block Lanczos in
//! the K-inner product.

use super::csc::SymCsc;
use super::factor::Pencil;
use super::lanczos::{BLOCK, Lanczos, MAX_BASIS};
use super::{RESIDUAL_TOL, SparseError};
use crate::error::ModalError;
use faer::{Mat, MatRef, Par};

/// Smallest positive λ of (K + λ·K_G)·φ = 0 with K positive definite; `None` when the
/// prestress destabilises no direction (as in the dense path: no eigenvalue μ = 1/λ of
/// −K_G·φ = μ·K·φ is positive beyond round-off relative to the spectrum).
///
/// Two phases. A short block Lanczos on K⁻¹·(−K_G) in the K-inner product brackets the
/// answer: its top Ritz value θ ≤ max μ, so λ₁ ≤ 1/θ. The wanted μ is, however, an interior
/// cluster next to the large negative μ of the tensioned members, where plain Lanczos crawls
/// (measured: 200 vectors for 6 digits on a 6-satellite stack). So the second phase is the
/// "buckling mode" spectral transformation: with a shift 0 < σ < λ₁, proven by a Sturm count of
/// zero for K + σ·K_G, the operator (K + σ·K_G)⁻¹·K is K-self-adjoint with eigenvalues
/// ν = λ/(λ − σ), and λ₁ becomes the largest ν, well separated.
pub fn buckling_factor(k: &SymCsc, kg: &SymCsc) -> Result<Option<f64>, SparseError> {
    faer::set_global_parallelism(Par::Seq);
    let n = k.n;
    let neg_kg = kg.scaled(-1.0);
    // The pencil (K, −K_G): factor(σ) is K + σ·K_G.
    let pencil = Pencil::new(k, Some(&neg_kg))?;
    let fac = pencil.factor(0.0)?;
    if let Some(index) = fac.first_singular() {
        return Err(SparseError::NotPositiveDefinite { index });
    }
    let op = |v: MatRef<'_, f64>, _bv: MatRef<'_, f64>| {
        let mut w = neg_kg.mul(v);
        fac.solve(w.as_mut());
        w
    };
    let empty = Mat::<f64>::zeros(n, 0);
    let max_basis = (MAX_BASIS.min(n) / BLOCK.min(n)).max(1) * BLOCK.min(n);
    let mut lz = Lanczos::new(n, BLOCK.min(n), max_basis, empty.as_ref(), 7, &mut None);
    lz.start(k);
    let mut bracket = None;
    loop {
        let more = lz.step(&op, k);
        let (theta, res, _) = lz.ritz()?;
        if theta.is_empty() {
            return Ok(None);
        }
        let span = theta.iter().fold(0.0f64, |a, &t| a.max(t.abs()));
        let top = theta.len() - 1;
        let max = theta[top];
        // The top Ritz value is a lower bound of max μ, so "no positive μ" can only be
        // concluded once it has converged.
        if res[top] <= RESIDUAL_TOL * span {
            return Ok(if max > 1e-12 * span {
                Some(1.0 / max)
            } else {
                None
            });
        }
        if max > 1e-12 * span && lz.blocks() >= 4 {
            bracket = Some(1.0 / max);
            break;
        }
        if !more {
            break;
        }
    }
    let Some(upper) = bracket else {
        return Err(ModalError::NoConvergence(format!(
            "buckling: the largest eigenvalue of K⁻¹·(−K_G) did not converge within a {max_basis}-vector Lanczos basis"
        ))
        .into());
    };
    // A shift below λ₁: count 0 for K + σ·K_G. The bracket can be loose by many orders of
    // magnitude (a model with near-rigid joints leaves K ill-conditioned, and the short
    // Lanczos's top Ritz value far below max μ), so the descent goes on down to 1e-15 of it.
    let mut sigma = 0.9 * upper;
    let mut shifted = None;
    while sigma > 1e-15 * upper {
        match pencil.factor(sigma) {
            Ok(f) if f.negative == 0 && f.min_relative_pivot() > 1e-13 => {
                shifted = Some(f);
                break;
            }
            _ => sigma *= 0.7,
        }
    }
    let mut shifted = shifted.ok_or_else(|| {
        ModalError::NoConvergence(format!(
            "buckling: no shift below the first buckling factor found under {upper:e}"
        ))
    })?;
    // When many buckling modes crowd λ₁ (a long stack's identical column segments), a shift
    // far below leaves them all near the top of ν and Lanczos crawls. Each unconverged run
    // still gives an upper bound λ₁ ≤ σ·ν/(ν − 1) (the top Ritz value bounds ν_max from
    // below); the shift moves most of the way up to it, kept below λ₁ by a Sturm count of 0,
    // which spreads the crowd apart (ν = λ/(λ − σ)).
    for run in 0..6u64 {
        let sg = shifted.sigma;
        let op = |_v: MatRef<'_, f64>, bv: MatRef<'_, f64>| {
            let mut w = bv.to_owned();
            shifted.solve(w.as_mut());
            w
        };
        let mut lz = Lanczos::new(
            n,
            BLOCK.min(n),
            max_basis,
            empty.as_ref(),
            11 + run,
            &mut None,
        );
        lz.start(k);
        let estimate = loop {
            let more = lz.step(&op, k);
            let (nu, res, _) = lz.ritz()?;
            let top = nu.len() - 1;
            if res[top] <= RESIDUAL_TOL * nu[top].abs() && nu[top] > 1.0 {
                return Ok(Some(sg * nu[top] / (nu[top] - 1.0)));
            }
            if !more {
                break (nu[top] > 1.0).then(|| sg * nu[top] / (nu[top] - 1.0));
            }
        };
        let Some(est) = estimate else { break };
        let mut next = None;
        let mut t = sg + 0.95 * (est - sg);
        for _ in 0..20 {
            match pencil.factor(t) {
                Ok(f) if f.negative == 0 && f.min_relative_pivot() > 1e-13 => {
                    next = Some(f);
                    break;
                }
                _ => t = sg + 0.5 * (t - sg),
            }
        }
        match next {
            Some(f) if f.sigma > sg => shifted = f,
            _ => break,
        }
    }
    Err(ModalError::NoConvergence(format!(
        "buckling: shift-invert Lanczos near σ = {:e} did not converge within {max_basis} vectors",
        shifted.sigma
    ))
    .into())
}

#[cfg(test)]
mod tests {
    use super::super::testing::diagonal;
    use super::*;

    /// Uncoupled directions: (k_i + λ·g_i)·φ_i = 0 buckles at λ_i = −k_i/g_i where g_i < 0
    /// (compression). Reference: the smallest such ratio. The accepted Ritz value carries a
    /// relative error of at most RESIDUAL_TOL (first order), asserted as 1e-9 on λ.
    #[test]
    fn uncoupled_directions_buckle_at_the_smallest_ratio() {
        let n = 40;
        let k: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let g: Vec<f64> = (0..n)
            .map(|i| {
                if i % 3 == 0 {
                    0.5
                } else {
                    -0.01 * (1 + i % 5) as f64
                }
            })
            .collect();
        let want = (0..n)
            .filter(|&i| g[i] < 0.0)
            .map(|i| -k[i] / g[i])
            .fold(f64::INFINITY, f64::min);
        let got = buckling_factor(&diagonal(&k), &diagonal(&g))
            .unwrap()
            .expect("compressed directions buckle");
        assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    }

    /// Tension everywhere (K_G positive semi-definite) never buckles.
    #[test]
    fn tension_does_not_buckle() {
        let n = 24;
        let k: Vec<f64> = (0..n).map(|i| 2.0 + i as f64).collect();
        let g: Vec<f64> = (0..n).map(|i| 0.1 * (i % 4) as f64).collect();
        assert_eq!(buckling_factor(&diagonal(&k), &diagonal(&g)).unwrap(), None);
    }
}
