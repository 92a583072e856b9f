//! The least-squares complex-frequency (LSCF) estimator of the poles, single reference, common
//! denominator: every output's FRF is modelled as N_o(z)/A(z) in z = exp(−jωTs) with
//! Ts = 1/(2 f_top), so that the band [0, f_top] maps onto the lower half of the unit circle
//! (Guillaume, Verboven, Vanlanduit, Van der Auweraer, Peeters, "A poly-reference
//! implementation of the least-squares complex frequency-domain estimator", IMAC XXI, 2003;
//! Verboven, PhD thesis, VUB 2002, eq. 5.26). With unity weighting the blocks of the normal
//! equations are Toeplitz:
//!
//! R[r,s] = Σ_k cos((s−r)θ_k), S_o[r,s] = −Re Σ_k H_o,k e^{j(r−s)θ_k}, T_o[r,s] = Σ_k |H_o,k|² cos((s−r)θ_k),
//!
//! and the numerators are eliminated: M = Σ_o (T_o − S_oᵀ R⁻¹ S_o), M α = 0 with α_n = 1.
//! The poles are the roots of A (the eigenvalues of its companion matrix), s = −ln(z)/Ts, so a
//! physical pole is a root outside the unit circle; the estimator's mathematical poles mostly
//! come out unstable and drop out of the diagram, which is why LSCF diagrams read clearly. The
//! numerator N_o(z_i) = Σ_r β_o,r z_i^r with β_o = −R⁻¹ S_o α is, up to a factor common to every
//! output, the residue of output o at pole i: it is the pole's vector for the stabilization
//! diagram's MAC test. sdypy-EMA's `lscf` builds the same normal equations (through an FFT).
//!
//! Linear algebra: the blocks are at most (order_max + 1)² (≤ 401²); the Cholesky factor of R
//! and the LU of M come from nalgebra (small dense matrices), the companion eigenvalues from
//! faer's real Schur decomposition, which returns an error instead of panicking when it does
//! not converge.

use crate::error::SignalError;
use nalgebra::{DMatrix, DVector};
use realfft::num_complex::Complex64;

/// The poles of one model order with their per-output vectors.
#[derive(Debug, Clone)]
pub struct OrderFit {
    pub order: usize,
    /// Continuous-time poles s (rad/s) with Im s > 0 and Re s < 0, ascending in |s|.
    pub poles: Vec<Complex64>,
    /// `vectors[i][o]` = N_o(z_i): the shape of pole i across the outputs.
    pub vectors: Vec<Vec<Complex64>>,
}

/// The Toeplitz sequences of the normal equations for lags 0..=n (R, T) and −n..=n (S).
struct Sums {
    r: Vec<f64>,
    t: Vec<f64>,
    /// `s[o][n + d]` for lag d in −n..=n.
    s: Vec<Vec<f64>>,
}

fn toeplitz_sums(theta: &[f64], h: &[Vec<Complex64>], n: usize) -> Sums {
    let mut r = vec![0.0; n + 1];
    let mut t = vec![0.0; n + 1];
    let mut s = vec![vec![0.0; 2 * n + 1]; h.len()];
    let last = theta.len().saturating_sub(1);
    for (k, &th) in theta.iter().enumerate() {
        // The top line sits at θ = π, the Nyquist point of the z-domain basis: it counts
        // half, as in the FFT form of the sums (Verboven 2002 §5.3.3; sdypy-EMA's `lscf`).
        let wk = if k == last { 0.5 } else { 1.0 };
        let mag2: f64 = wk * h.iter().map(|ho| ho[k].norm_sqr()).sum::<f64>();
        for d in 0..=n {
            let (sin, cos) = (d as f64 * th).sin_cos();
            r[d] += wk * cos;
            t[d] += mag2 * cos;
            let e = Complex64::new(cos, sin);
            for (o, ho) in h.iter().enumerate() {
                let hk = wk * ho[k];
                // lag +d: e^{jdθ}; lag −d: e^{−jdθ}
                s[o][n + d] -= (hk * e).re;
                if d > 0 {
                    s[o][n - d] -= (hk * e.conj()).re;
                }
            }
        }
    }
    Sums { r, t, s }
}

/// Poles and vectors of every even model order 2, 4, …, `order_max`, fitted on the lines at
/// angles `theta` (θ_k = π f_k / f_top) with FRFs `h[o][k]`; `ts` = 1/(2 f_top) in seconds.
/// With `stop_early`, an order the lines cannot carry ends the fit at the orders below it
/// (returned with the reason) instead of failing it.
pub fn fit_orders(
    theta: &[f64],
    h: &[Vec<Complex64>],
    ts: f64,
    order_max: usize,
    stop_early: bool,
) -> Result<(Vec<OrderFit>, Option<SignalError>), SignalError> {
    let sums = toeplitz_sums(theta, h, order_max);
    let mut out = Vec::new();
    for n in (2..=order_max).step_by(2) {
        match fit_order(&sums, n, order_max, ts) {
            Ok(fit) => out.push(fit),
            Err(e) if stop_early && !out.is_empty() => return Ok((out, Some(e))),
            Err(e) => return Err(e),
        }
    }
    Ok((out, None))
}

fn fit_order(sums: &Sums, n: usize, nmax: usize, ts: f64) -> Result<OrderFit, SignalError> {
    let dim = n + 1;
    let r = DMatrix::from_fn(dim, dim, |i, j| sums.r[i.abs_diff(j)]);
    let chol = r.cholesky().ok_or_else(|| {
        SignalError::Invalid(format!(
            "LSCF order {n}: the basis matrix is not positive definite (too few lines in the band for this order; lower --order-max)"
        ))
    })?;
    let mut m = DMatrix::from_fn(dim, dim, |i, j| sums.t[i.abs_diff(j)]);
    let mut sos = Vec::with_capacity(sums.s.len());
    for so in &sums.s {
        // S[r, c] depends on the lag r − c, stored from −nmax (nmax + r ≥ c always).
        let s = DMatrix::from_fn(dim, dim, |i, j| so[nmax + i - j]);
        let rs = chol.solve(&s);
        m -= s.transpose() * &rs;
        sos.push(rs);
    }
    let a = m.view((0, 0), (n, n)).clone_owned();
    let b = -m.view((0, n), (n, 1)).clone_owned();
    let alpha_head = a.lu().solve(&b).ok_or_else(|| {
        SignalError::Invalid(format!(
            "LSCF order {n}: singular reduced normal equations (the band holds fewer modes than the order asks; lower --order-max)"
        ))
    })?;
    let mut alpha = DVector::from_element(dim, 1.0);
    alpha.rows_mut(0, n).copy_from(&alpha_head);
    let roots = companion_roots(alpha.as_slice(), n)?;
    let betas: Vec<DVector<f64>> = sos.iter().map(|rs| -(rs * &alpha)).collect();
    let mut fit = OrderFit {
        order: n,
        poles: Vec::new(),
        vectors: Vec::new(),
    };
    let mut found: Vec<(Complex64, Vec<Complex64>)> = roots
        .into_iter()
        .filter(|z| z.norm() > 0.0 && z.im < 0.0)
        .map(|z| {
            let s = -z.ln() / ts;
            let v = betas.iter().map(|b| horner(b.as_slice(), z)).collect();
            (s, v)
        })
        .filter(|(s, _)| s.re < 0.0 && s.re.is_finite() && s.im.is_finite())
        .collect();
    found.sort_by(|a, b| a.0.norm().total_cmp(&b.0.norm()));
    for (s, v) in found {
        fit.poles.push(s);
        fit.vectors.push(v);
    }
    Ok(fit)
}

fn horner(c: &[f64], z: Complex64) -> Complex64 {
    c.iter()
        .rev()
        .fold(Complex64::new(0.0, 0.0), |acc, &a| acc * z + a)
}

/// Roots of the monic polynomial Σ α_r z^r (α_n = 1): eigenvalues of its companion matrix.
fn companion_roots(alpha: &[f64], n: usize) -> Result<Vec<Complex64>, SignalError> {
    let c = faer::Mat::<f64>::from_fn(n, n, |i, j| {
        if i == 0 {
            -alpha[n - 1 - j]
        } else if i == j + 1 {
            1.0
        } else {
            0.0
        }
    });
    let ev = c.eigenvalues().map_err(|e| {
        SignalError::Invalid(format!(
            "LSCF order {n}: the companion eigenvalues did not converge ({e:?})"
        ))
    })?;
    Ok(ev.into_iter().map(|z| Complex64::new(z.re, z.im)).collect())
}
