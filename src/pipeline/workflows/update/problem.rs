//! The updating problem on a scene: parameter values written into the scene text and loaded
//! again (every check of the loader applies to every iterate), the modes solved and re-paired
//! with the test modes by `correlate`'s pairing (so a mode that switches order is followed),
//! the weighted relative frequency residuals and their Jacobian from eigenvalue sensitivities.

use crate::error::{Error, SpecError};
use crate::fem::model::Triplets;
use crate::modal::updating::sensitivity::{Assembled, eigenvalue_derivative, frequency_derivative};
use crate::modal::{ModalOptions, ModalSystem};
use crate::pipeline::workflows::correlate::{fe_side, pair_modes, test_modes::TestMode};
use crate::spec::Scene;
use crate::spec::update::Scale;
use crate::spec::update_edit::{Written, with_values};
use nalgebra::{DMatrix, DVector};

/// Relative change of a parameter for the difference of its assembled matrices.
const MATRIX_STEP: f64 = 1e-6;

/// One updated scene number and its scaling u(p).
#[derive(Debug, Clone)]
pub struct Param {
    pub path: String,
    pub key: String,
    pub start: f64,
    pub lower: f64,
    pub upper: f64,
    pub scale: Scale,
}

impl Param {
    pub fn to_u(&self, p: f64) -> f64 {
        match self.scale {
            Scale::Log => p.ln(),
            Scale::Linear => p / self.start.abs(),
        }
    }
    pub fn to_p(&self, u: f64) -> f64 {
        match self.scale {
            Scale::Log => u.exp(),
            Scale::Linear => u * self.start.abs(),
        }
    }
    fn dp_du(&self, p: f64) -> f64 {
        match self.scale {
            Scale::Log => p,
            Scale::Linear => self.start.abs(),
        }
    }
}

/// A fitted test mode (0-based index into the test modes) and its weight.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    pub test: usize,
    pub weight: f64,
}

pub struct Problem<'a> {
    pub base: &'a Scene,
    pub params: Vec<Param>,
    pub targets: Vec<Target>,
    pub test: Vec<TestMode>,
    pub opts: ModalOptions,
}

/// The FE mode paired with a target.
#[derive(Debug, Clone)]
pub struct Paired {
    pub fe_mode: usize,
    pub fe_hz: f64,
    pub mac: f64,
    lambda: f64,
    shape: Vec<f64>,
}

/// The model solved at one set of parameter values.
pub struct Solved {
    pub values: Vec<f64>,
    pub paired: Vec<Paired>,
    pub n_red: usize,
    pub prestressed: bool,
}

impl Problem<'_> {
    /// The base text with `values` written in; with `notes`, each value annotated.
    pub fn text_at(
        &self,
        values: &[f64],
        notes: Option<&[Option<String>]>,
    ) -> Result<String, Error> {
        let edits: Vec<Written> = self
            .params
            .iter()
            .zip(values)
            .enumerate()
            .map(|(i, (p, &value))| Written {
                key: p.key.clone(),
                value,
                note: notes.and_then(|n| n[i].clone()),
            })
            .collect();
        with_values(&self.base.text, &edits)
            .map_err(|e| Error::Other(format!("{}: {e}", self.base.path.display())))
    }

    /// The scene at `values`, an error of the loader naming the values.
    pub fn scene_at(&self, values: &[f64]) -> Result<Scene, Error> {
        let text = self.text_at(values, None)?;
        Scene::parse(&self.base.path, &text).map_err(|e| {
            Error::Spec(SpecError {
                message: format!(
                    "{} (at the update values {})",
                    e.message,
                    self.describe(values)
                ),
                ..e
            })
        })
    }

    pub fn describe(&self, values: &[f64]) -> String {
        let parts: Vec<String> = (self.params.iter().zip(values))
            .map(|(p, v)| format!("{} = {v}", p.path))
            .collect();
        parts.join(", ")
    }

    /// Modes at `values`, each target paired with an FE mode or an error saying which is not.
    pub fn solve(&self, values: &[f64]) -> Result<Solved, Error> {
        let scene = self.scene_at(values)?;
        let (model, sys) = super::super::modal::run(&scene, &self.opts)?;
        let rows = fe_side::test_dof_rows(&scene, &model, &sys)?;
        let fe = fe_side::fe_modes(&sys, &rows);
        let (_, mac, pairs) = pair_modes(&scene, &self.test, &fe);
        let mut paired = Vec::new();
        for t in &self.targets {
            let Some(p) = pairs.iter().find(|p| p.test == t.test) else {
                let msg = format!(
                    "test mode {} ({} Hz) has no FE mode to pair with at the update values {}",
                    t.test + 1,
                    self.test[t.test].frequency_hz,
                    self.describe(values)
                );
                return Err(self.base.locator().err("update", msg).into());
            };
            paired.push(paired_mode(&sys, &fe[p.fe], mac[p.test][p.fe]));
        }
        Ok(Solved {
            values: values.to_vec(),
            paired,
            n_red: sys.reduction.n_red,
            prestressed: sys.result.prestress.is_some(),
        })
    }

    /// r_i = w_i·(f_FE − f_test)/f_test.
    pub fn residuals(&self, s: &Solved) -> DVector<f64> {
        DVector::from_iterator(
            self.targets.len(),
            self.targets.iter().zip(&s.paired).map(|(t, p)| {
                let f = self.test[t.test].frequency_hz;
                t.weight * (p.fe_hz - f) / f
            }),
        )
    }

    /// ∂r_i/∂u_j from dλ/dp (the matrices assembled at p ± δ, no eigen-solve) times dp/du.
    pub fn jacobian(&self, s: &Solved) -> Result<DMatrix<f64>, Error> {
        let mut j = DMatrix::zeros(self.targets.len(), self.params.len());
        for (c, param) in self.params.iter().enumerate() {
            let p = s.values[c];
            let d = MATRIX_STEP * p.abs().max(MATRIX_STEP * param.start.abs());
            let (plo, phi) = ((p - d).max(param.lower), (p + d).min(param.upper));
            let lo = self.matrices(s, c, plo)?;
            let hi = self.matrices(s, c, phi)?;
            if lo.2 != hi.2 {
                return Err(self.prestress_parameter(c));
            }
            let (lo, hi) = (
                Assembled {
                    p: plo,
                    k: &lo.0,
                    m: &lo.1,
                },
                Assembled {
                    p: phi,
                    k: &hi.0,
                    m: &hi.1,
                },
            );
            for (i, (t, m)) in self.targets.iter().zip(&s.paired).enumerate() {
                let dl = eigenvalue_derivative(&lo, &hi, m.lambda, &m.shape);
                let df = frequency_derivative(dl, m.fe_hz);
                let ft = self.test[t.test].frequency_hz;
                j[(i, c)] = t.weight / ft * df * param.dp_du(p);
            }
        }
        Ok(j)
    }

    /// The error for a parameter that moves the static loads (a preload): the prestress
    /// stiffness K_G it changes is not in the sensitivities, whose column would read zero.
    fn prestress_parameter(&self, c: usize) -> Error {
        let msg = format!(
            "`{}` changes the static loads (the preload): the sensitivities carry K and M, not the prestress stiffness it changes, so it cannot be updated; fix it at its measured value",
            self.params[c].path
        );
        self.base
            .locator()
            .err(&format!("update.parameter[{c}].path"), msg)
            .into()
    }

    /// Reduced K and M with parameter `c` at `p`, the others at `s.values`, and the model's
    /// static load vector there.
    fn matrices(
        &self,
        s: &Solved,
        c: usize,
        p: f64,
    ) -> Result<(Triplets, Triplets, Vec<f64>), Error> {
        let mut values = s.values.clone();
        values[c] = p;
        let scene = self.scene_at(&values)?;
        let model = crate::pipeline::fe_model(&scene)?;
        let red = model.reduction()?;
        if red.n_red != s.n_red {
            let msg = format!(
                "`{}` changes the model's degrees of freedom ({} to {}): only values that keep its topology can be updated",
                self.params[c].path, s.n_red, red.n_red
            );
            return Err(self
                .base
                .locator()
                .err(&format!("update.parameter[{c}].path"), msg)
                .into());
        }
        Ok((
            red.reduce(&model.stiffness()),
            red.reduce(&model.mass()),
            model.load_vector(),
        ))
    }
}

fn paired_mode(sys: &ModalSystem, fe: &fe_side::FeModeAtTest, mac: f64) -> Paired {
    let mode = sys
        .result
        .modes
        .iter()
        .find(|m| m.index == fe.mode)
        .expect("the FE modes at the test points are modes of the system");
    Paired {
        fe_mode: fe.mode,
        fe_hz: fe.frequency_hz,
        mac,
        lambda: mode.eigenvalue,
        shape: mode.shape.clone(),
    }
}
