//! Modal constants by least-squares frequency-domain fitting (LSFD): with the poles fixed, each
//! output's FRF is linear in the unknown residues, so
//!
//! H_o(ω) = (jω)^p [ Σ_i ( A_oi/(jω − λ_i) + A_oi*/(jω − λ_i*) ) − LR_o/ω² + UR_o ],
//!
//! with p = 0, 1, 2 for receptance, mobility, accelerance, complex residues A_oi (receptance
//! residues whatever the FRF form), and complex lower (LR, mass-line) and upper (UR, stiffness)
//! residuals for the modes below and above the band. The real and imaginary parts of every
//! line are stacked into one real least-squares problem, solved for all outputs at once by a
//! Householder QR (faer) after each column is scaled to unit norm (the
//! residual columns grow as ω⁻² and ω⁰ against the modal ones). sdypy-EMA's `LSFD` fits the
//! same model.

use crate::error::SignalError;
use faer::Mat;
use faer::linalg::solvers::SolveLstsq;
use realfft::num_complex::Complex64;

/// How the FRF relates response to force.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrfForm {
    Receptance,
    Mobility,
    Accelerance,
}

impl FrfForm {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "receptance" | "displacement" => Some(FrfForm::Receptance),
            "mobility" | "velocity" => Some(FrfForm::Mobility),
            "accelerance" | "acceleration" | "inertance" => Some(FrfForm::Accelerance),
            _ => None,
        }
    }

    /// The form as `--frf-form` spells it.
    pub fn name(self) -> &'static str {
        match self {
            FrfForm::Receptance => "receptance",
            FrfForm::Mobility => "mobility",
            FrfForm::Accelerance => "accelerance",
        }
    }

    fn factor(self, w: f64) -> Complex64 {
        let jw = Complex64::new(0.0, w);
        match self {
            FrfForm::Receptance => Complex64::new(1.0, 0.0),
            FrfForm::Mobility => jw,
            FrfForm::Accelerance => jw * jw,
        }
    }
}

/// Residues, residuals and the FRFs they rebuild.
#[derive(Debug, Clone)]
pub struct LsfdFit {
    /// `residues[i][o]`: receptance residue of mode i at output o.
    pub residues: Vec<Vec<Complex64>>,
    pub lower: Vec<Complex64>,
    pub upper: Vec<Complex64>,
    /// `reconstructed[o][k]` on the fitted lines.
    pub reconstructed: Vec<Vec<Complex64>>,
}

/// The complex basis functions at angular frequency w: two per pole (coefficients Re A, Im A),
/// then two per residual.
fn basis(w: f64, poles: &[Complex64], form: FrfForm) -> Vec<Complex64> {
    let jw = Complex64::new(0.0, w);
    let j = Complex64::new(0.0, 1.0);
    let k = form.factor(w);
    let mut g = Vec::with_capacity(2 * poles.len() + 4);
    for l in poles {
        let (a, b) = (1.0 / (jw - l), 1.0 / (jw - l.conj()));
        g.push(k * (a + b));
        g.push(k * j * (a - b));
    }
    let lr = k * (-1.0 / (w * w));
    g.extend([lr, j * lr, k, j * k]);
    g
}

/// Fits the residues of `poles` to `h[o][k]` on `freqs` (Hz, all > 0).
pub fn fit(
    freqs: &[f64],
    h: &[Vec<Complex64>],
    poles: &[Complex64],
    form: FrfForm,
) -> Result<LsfdFit, SignalError> {
    let nk = freqs.len();
    let rows: Vec<Vec<Complex64>> = freqs
        .iter()
        .map(|f| basis(2.0 * std::f64::consts::PI * f, poles, form))
        .collect();
    let ncol = 2 * poles.len() + 4;
    if 2 * nk < ncol {
        return Err(SignalError::Invalid(format!(
            "LSFD: {nk} lines cannot fit {} modes and the residuals; widen the band",
            poles.len()
        )));
    }
    let mut p = Mat::<f64>::from_fn(2 * nk, ncol, |r, c| {
        let z = rows[r % nk][c];
        if r < nk { z.re } else { z.im }
    });
    let scale: Vec<f64> = (0..ncol)
        .map(|c| {
            let n = (0..2 * nk).map(|r| p[(r, c)].powi(2)).sum::<f64>().sqrt();
            if n > 0.0 { n } else { 1.0 }
        })
        .collect();
    for c in 0..ncol {
        for r in 0..2 * nk {
            p[(r, c)] /= scale[c];
        }
    }
    let y = Mat::<f64>::from_fn(2 * nk, h.len(), |r, o| {
        if r < nk { h[o][r].re } else { h[o][r - nk].im }
    });
    let x = p.qr().solve_lstsq(&y);
    if x.col_iter()
        .flat_map(|c| c.iter().copied())
        .any(|v| !v.is_finite())
    {
        return Err(SignalError::Invalid(
            "LSFD: the least-squares solution is not finite (two selected poles coincide?)".into(),
        ));
    }
    let coef = |o: usize, c: usize| x[(c, o)] / scale[c];
    let m = poles.len();
    let residues = (0..m)
        .map(|i| {
            (0..h.len())
                .map(|o| Complex64::new(coef(o, 2 * i), coef(o, 2 * i + 1)))
                .collect()
        })
        .collect();
    let lower = (0..h.len())
        .map(|o| Complex64::new(coef(o, 2 * m), coef(o, 2 * m + 1)))
        .collect();
    let upper = (0..h.len())
        .map(|o| Complex64::new(coef(o, 2 * m + 2), coef(o, 2 * m + 3)))
        .collect();
    let reconstructed = (0..h.len())
        .map(|o| {
            rows.iter()
                .map(|g| g.iter().enumerate().map(|(c, gc)| gc * coef(o, c)).sum())
                .collect()
        })
        .collect();
    Ok(LsfdFit {
        residues,
        lower,
        upper,
        reconstructed,
    })
}
