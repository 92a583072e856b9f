//! Base-driven sine and random response by modal superposition, load recovery and the
//! lock-integrity margins (gapping, slip and guide-bar strength of the preloaded joints).
//!
//! Inputs: the FE model (`fem`) and its modes and prestress (`modal`); the excitation,
//! damping, output points and margin factors from the scene (`spec::analysis`).
//!
//! Stages (each a file):
//! - [`basis`]: kept modes + residual vector, participation in the enforced base motion;
//! - [`outputs`]: what is recovered (point accelerations, joint forces, bar-station loads);
//! - [`frf`]: transfer functions per g, modal (production) and direct (reference);
//! - [`grid`]: clustered frequency grids and the integration rule;
//! - [`sine`], [`random`]: the two analyses, their peaks, rms values and curves;
//! - [`margins`]: gapping, slip and bar strength margins from the recovered loads.
//!
//! The library never prints; the results are serialisable structs.

pub mod basis;
pub mod frf;
pub mod grid;
pub mod margins;
pub mod outputs;
pub mod random;
pub mod sine;

use crate::error::Error;
use crate::fem::FeModel;
use crate::gates::Verdict;
use crate::modal::ModalSystem;
use crate::spec::Scene;
use crate::spec::analysis::{DampingSpec, MarginsSpec};

pub use basis::Basis;
pub use frf::{DirectFrf, Frf, ModalFrf};
pub use outputs::OutputSet;
pub use random::{RandomAxis, RandomOptions};
pub use sine::{SineAxis, SineOptions};

/// Everything the response analyses of one scene share: the model, its modes, the recovered
/// outputs, damping and margin factors. Built once; each axis and analysis reuses it.
pub struct Prepared<'a> {
    pub scene: &'a Scene,
    pub model: &'a FeModel,
    pub sys: &'a ModalSystem,
    pub outputs: OutputSet,
    pub damping: DampingSpec,
    pub margins: MarginsSpec,
}

impl<'a> Prepared<'a> {
    /// A/Z of a joint face when `[margins] include_face_moment` adds the face bending moment
    /// to the gapping load (as an equivalent axial force), else 0: one place for the option
    /// that both the sine and the random margins apply.
    pub fn face_moment_factor(&self, i: &outputs::InterfaceOut) -> f64 {
        if self.margins.include_face_moment {
            i.face_a_over_z
        } else {
            0.0
        }
    }

    pub fn new(scene: &'a Scene, model: &'a FeModel, sys: &'a ModalSystem) -> Result<Self, Error> {
        let points = crate::spec::analysis::response_points(scene);
        let outputs = OutputSet::build(scene, model, sys, &points)?;
        Ok(Prepared {
            scene,
            model,
            sys,
            outputs,
            damping: scene.file.damping.clone().unwrap_or_default(),
            margins: scene.file.margins.clone().unwrap_or_default(),
        })
    }

    /// Rigid-body part of every row for a unit base acceleration along `axis`.
    pub fn rigid(&self, axis: usize) -> Vec<f64> {
        let mut r = vec![0.0; self.outputs.rows.len()];
        for p in &self.outputs.points {
            r[p.rows[axis]] = 1.0;
        }
        r
    }

    /// The modal basis for `axis`: the first `n_modes` modes (all when `None`) and, when
    /// `residual`, the residual vector.
    pub fn basis(
        &self,
        axis: usize,
        n_modes: Option<usize>,
        residual: bool,
    ) -> Result<Basis, Error> {
        basis::build(self.model, self.sys, axis, &self.damping, n_modes, residual)
    }

    pub fn modal_frf<'b>(&self, basis: &'b Basis) -> ModalFrf<'b> {
        ModalFrf::new(basis, &self.outputs, self.rigid(basis.axis))
    }

    /// The direct (reference) transfer functions for `axis`.
    pub fn direct_frf(&self, axis: usize) -> Result<DirectFrf, Error> {
        let p = basis::influence_load(self.model, self.sys, axis);
        DirectFrf::new(self.sys, p, &self.damping, &self.outputs, self.rigid(axis))
    }
}

/// The response analyses a scene asks for (`[sine]`, `[random]`), each on its own axes, with
/// the default options: what `qualify` runs. An analysis the scene does not ask for is skipped.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SceneResponse {
    pub sine: Vec<SineAxis>,
    pub random: Vec<RandomAxis>,
    /// The inputs as applied; written at the top of a qualification's results, not here.
    #[serde(skip)]
    pub environments: crate::spec::environment::Environments,
}

impl SceneResponse {
    /// Every margin of every analysis and axis.
    pub fn margins(&self) -> impl Iterator<Item = &Verdict> {
        self.sine
            .iter()
            .flat_map(|a| a.margins.iter())
            .chain(self.random.iter().flat_map(|a| a.margins.iter()))
    }

    /// The smallest margin for each checked item (name and kind) over all load cases.
    pub fn governing_margins(&self) -> Vec<Verdict> {
        margins::worst_per_item(self.margins().cloned().collect())
    }

    /// True when every margin is positive.
    pub fn pass(&self) -> bool {
        self.margins().all(|m| m.pass)
    }
}

/// Runs the scene's `[sine]` and `[random]` analyses on their axes.
pub fn run_scene(prep: &Prepared) -> Result<SceneResponse, Error> {
    let axes = |names: &[String]| -> Vec<usize> {
        names
            .iter()
            .filter_map(|a| crate::spec::analysis::axis_index(a))
            .collect()
    };
    let mut out = SceneResponse::default();
    if let Some(s) = &prep.scene.file.sine {
        out.environments.sine = Some(crate::spec::environment::SineEnvironment::of(s));
        for a in axes(&s.axes) {
            out.sine
                .push(sine::run(prep, s, a, &SineOptions::default())?);
        }
    }
    if let Some(r) = &prep.scene.file.random {
        let (spec, env) = r
            .applied(Some(
                prep.sys.result.total_mass_kg - prep.scene.file.fixture_mass_kg(),
            ))
            .map_err(|e| prep.scene.locator().err("random", e))?;
        for a in axes(&spec.axes) {
            out.random
                .push(random::run(prep, &spec, a, &RandomOptions::default())?);
        }
        out.environments.random = Some(env);
    }
    Ok(out)
}

/// Axis index to name.
pub fn axis_name(a: usize) -> &'static str {
    ["x", "y", "z"][a.min(2)]
}

/// A set of curves against frequency (for CSV and plots): not serialised into JSON.
#[derive(Debug, Clone, Default)]
pub struct Curves {
    pub frequency_hz: Vec<f64>,
    /// The input level (g for sine, g²/Hz for random).
    pub input: Vec<f64>,
    /// Response points on the same grid.
    pub series: Vec<(String, Vec<f64>)>,
    /// Joint loads (force and moment components and resultants).
    pub interfaces: Vec<(String, Vec<f64>)>,
    /// Guide-bar stations (bending moment, normal stress).
    pub bars: Vec<(String, Vec<f64>)>,
}

impl Curves {
    /// CSV text of the response points: frequency, input, then one column per point.
    pub fn to_csv(&self, input_name: &str) -> String {
        self.csv_of(input_name, &self.series)
    }

    /// CSV text of any group of series on this grid (frequency, input, then the series).
    pub fn csv_of(&self, input_name: &str, series: &[(String, Vec<f64>)]) -> String {
        use std::fmt::Write as _;
        let mut s = String::from("frequency_hz,");
        s.push_str(input_name);
        for (n, _) in series {
            let _ = write!(s, ",\"{n}\"");
        }
        s.push('\n');
        for (k, f) in self.frequency_hz.iter().enumerate() {
            let _ = write!(s, "{f:.6e},{:.6e}", self.input[k]);
            for (_, v) in series {
                let _ = write!(s, ",{:.6e}", v[k]);
            }
            s.push('\n');
        }
        s
    }
}
