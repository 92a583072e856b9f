//! Transfer functions of every output per 1 g of base acceleration: the modal superposition
//! (the production path) and the direct frequency response (the reference).
//!
//! Direct path: (K − ω²M + iωC)·x = −p solved densely in complex arithmetic (faer partial-pivot
//! LU) at each frequency. Damping model: the modal damping matrix C = M·Φ·diag(2ζ_jω_j)·Φᵀ·M
//! built from ALL the modes of the model with the same ζ(f) as the modal path. With it the
//! direct path is the exact solution of the damped equations that the modal path truncates,
//! so a comparison measures the truncation and residual-vector error alone. (Rayleigh damping
//! C = αM + βK would keep C sparse, but it cannot reproduce a constant Q over 5–2000 Hz, so the
//! two paths would differ by their damping, not by their method.)
//!
//! Units: accelerations in g per g (absolute), forces in N per g, moments in N·m per g.

use super::basis::Basis;
use super::outputs::OutputSet;
use crate::error::{Error, ResponseError};
use crate::fem::model::dense;
use crate::modal::ModalSystem;
use crate::spec::analysis::DampingSpec;
use crate::units::G;
use faer::c64;

/// Something that gives every output's complex amplitude at a frequency.
pub trait Frf: Sync {
    fn n_outputs(&self) -> usize;
    fn eval(&self, f_hz: f64, out: &mut Vec<c64>);
}

/// Modal superposition over a [`Basis`].
pub struct ModalFrf<'a> {
    pub basis: &'a Basis,
    /// a[row][j], row-major.
    pub coeffs: Vec<f64>,
    pub acceleration: Vec<bool>,
    /// Rigid-body part of each acceleration row (1 along the excitation axis).
    pub rigid: Vec<f64>,
}

impl<'a> ModalFrf<'a> {
    /// `rigid[row]`: 1 for an acceleration row along the excitation axis.
    pub fn new(basis: &'a Basis, outputs: &OutputSet, rigid: Vec<f64>) -> ModalFrf<'a> {
        ModalFrf {
            basis,
            coeffs: outputs.modal_coefficients(&basis.shapes),
            acceleration: outputs.rows.iter().map(|r| r.acceleration).collect(),
            rigid,
        }
    }
}

impl ModalFrf<'_> {
    /// One output's transfer function at `f_hz` (per g).
    pub fn eval_row(&self, f_hz: f64, row: usize) -> c64 {
        let mut q = Vec::new();
        self.basis.coordinates(f_hz, &mut q);
        let nb = q.len();
        let a = &self.coeffs[row * nb..(row + 1) * nb];
        let mut s = c64::new(0.0, 0.0);
        for j in 0..nb {
            s += q[j] * a[j];
        }
        if self.acceleration[row] {
            s * (-(2.0 * std::f64::consts::PI * f_hz).powi(2)) + self.rigid[row]
        } else {
            s * G
        }
    }
}

impl ModalFrf<'_> {
    /// Selected outputs' transfer functions at `f_hz` (per g), in the order of `rows`.
    pub fn eval_rows(&self, f_hz: f64, rows: &[usize], out: &mut Vec<c64>) {
        let mut q = Vec::new();
        self.basis.coordinates(f_hz, &mut q);
        let nb = q.len();
        let w2 = (2.0 * std::f64::consts::PI * f_hz).powi(2);
        out.clear();
        for &row in rows {
            let a = &self.coeffs[row * nb..(row + 1) * nb];
            let mut s = c64::new(0.0, 0.0);
            for j in 0..nb {
                s += q[j] * a[j];
            }
            out.push(if self.acceleration[row] {
                s * (-w2) + self.rigid[row]
            } else {
                s * G
            });
        }
    }
}

impl Frf for ModalFrf<'_> {
    fn n_outputs(&self) -> usize {
        self.acceleration.len()
    }
    fn eval(&self, f_hz: f64, out: &mut Vec<c64>) {
        let mut q = Vec::new();
        self.basis.coordinates(f_hz, &mut q);
        let nb = q.len();
        let w2 = (2.0 * std::f64::consts::PI * f_hz).powi(2);
        out.clear();
        for (o, &acc) in self.acceleration.iter().enumerate() {
            let a = &self.coeffs[o * nb..(o + 1) * nb];
            let mut s = c64::new(0.0, 0.0);
            for j in 0..nb {
                s += q[j] * a[j];
            }
            // Unit base acceleration is 1 m/s²: scale to 1 g.
            out.push(if acc {
                s * (-w2) + self.rigid[o]
            } else {
                s * G
            });
        }
    }
}

/// The dense direct frequency response.
pub struct DirectFrf {
    k: faer::Mat<f64>,
    m: faer::Mat<f64>,
    c: faer::Mat<f64>,
    p: Vec<f64>,
    rows: Vec<(Vec<(usize, f64)>, bool)>,
    rigid: Vec<f64>,
}

impl DirectFrf {
    pub fn new(
        sys: &ModalSystem,
        p: Vec<f64>,
        damping: &DampingSpec,
        outputs: &OutputSet,
        rigid: Vec<f64>,
    ) -> Result<DirectFrf, Error> {
        let n = sys.reduction.n_red;
        let k = dense(n, &sys.k);
        let m = dense(n, &sys.m);
        let (lambda, phi) =
            crate::modal::dense::generalized_whole_spectrum(&k, &m).map_err(|_| {
                ResponseError::Invalid("direct response: the full eigen-solve failed".into())
            })?;
        // C = (MΦ)·diag(2ζω)·(MΦ)ᵀ.
        let mphi = &m * &phi;
        let mut scaled = mphi.clone();
        for j in 0..n {
            let w = lambda[j].max(0.0).sqrt();
            // The whole spectrum, ascending like the modal solve: column j is mode j + 1.
            let d = 2.0 * damping.zeta_of_mode(j + 1, w / (2.0 * std::f64::consts::PI)) * w;
            for i in 0..n {
                scaled[(i, j)] *= d;
            }
        }
        let c = &scaled * mphi.transpose();
        Ok(DirectFrf {
            k,
            m,
            c,
            p,
            rows: outputs
                .rows
                .iter()
                .map(|r| (r.functional.clone(), r.acceleration))
                .collect(),
            rigid,
        })
    }

    /// Relative displacement (reduced) per 1 m/s² of base acceleration.
    pub fn solve(&self, f_hz: f64) -> Vec<c64> {
        use faer::linalg::solvers::Solve;
        let n = self.p.len();
        let w = 2.0 * std::f64::consts::PI * f_hz;
        let a = faer::Mat::<c64>::from_fn(n, n, |i, j| {
            c64::new(self.k[(i, j)] - w * w * self.m[(i, j)], w * self.c[(i, j)])
        });
        let lu = a.partial_piv_lu();
        let mut x = faer::Mat::<c64>::from_fn(n, 1, |i, _| c64::new(-self.p[i], 0.0));
        lu.solve_in_place(x.as_mut());
        (0..n).map(|i| x[(i, 0)]).collect()
    }
}

impl Frf for DirectFrf {
    fn n_outputs(&self) -> usize {
        self.rows.len()
    }
    fn eval(&self, f_hz: f64, out: &mut Vec<c64>) {
        let x = self.solve(f_hz);
        let w2 = (2.0 * std::f64::consts::PI * f_hz).powi(2);
        out.clear();
        for (o, (g, acc)) in self.rows.iter().enumerate() {
            let mut s = c64::new(0.0, 0.0);
            for &(i, c) in g {
                s += x[i] * c;
            }
            out.push(if *acc {
                s * (-w2) + self.rigid[o]
            } else {
                s * G
            });
        }
    }
}

/// Evaluates an FRF on a grid: `h[k][row]`. Frequencies run in parallel; each one is computed
/// independently, so the result does not depend on the thread count.
pub fn on_grid(frf: &dyn Frf, grid: &[f64]) -> Vec<Vec<c64>> {
    use rayon::prelude::*;
    grid.par_iter()
        .map(|&f| {
            let mut out = Vec::with_capacity(frf.n_outputs());
            frf.eval(f, &mut out);
            out
        })
        .collect()
}
