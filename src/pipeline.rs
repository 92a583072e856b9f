//! `qualify`: plans the analyses a scene asks for, runs each once, and reuses results.
//! The only module that knows the whole order spec -> fem -> modal -> response -> gates -> report.
//! It also maps errors of the numerical layers back to the scene: an FE error that names a
//! scene node gets that node's file, line and column.

use crate::error::{Error, FemError, SpecError};
use crate::fem::FeModel;
use crate::modal::{ModalOptions, ModalSystem};
use crate::spec::Scene;

/// Builds the FE model of a scene and runs the modal analysis (with prestress when the scene
/// has static loads). Command-line overrides take precedence over `[modal]`.
pub fn modal(
    scene: &Scene,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
) -> Result<(FeModel, ModalSystem), Error> {
    modal_with_solver(scene, fmax_hz, modes, None)
}

/// [`modal`] with a solver override (`--solver`) that takes precedence over `[modal] solver`.
pub fn modal_with_solver(
    scene: &Scene,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
    solver: Option<crate::spec::SolverChoice>,
) -> Result<(FeModel, ModalSystem), Error> {
    let model = FeModel::from_scene(&scene.model).map_err(|e| locate(scene, e))?;
    let mut spec = scene.file.modal.clone().unwrap_or_default();
    if let Some(s) = solver {
        spec.solver = s;
    }
    let opts = match (fmax_hz, modes) {
        (None, None) => ModalOptions {
            fmax_hz: spec.fmax_hz,
            modes: spec.modes,
            solver: spec.solver,
        },
        (f, n) => ModalOptions {
            fmax_hz: f,
            modes: n,
            solver: spec.solver,
        },
    };
    let sys = crate::modal::analyze(&model, &opts).map_err(|e| match e {
        Error::Fem(f) => locate(scene, f),
        other => other,
    })?;
    if let (Some(stack), Some(ps)) = (&scene.file.stack, &sys.result.prestress)
        && let Some(lambda) = ps.buckling_factor
        && lambda < 1.0
    {
        return Err(scene
                    .locator()
                    .err(
                        "stack.preload_total_n",
                        format!(
                            "the preload of {:.0} N is above the stack's buckling load of {:.0} N (buckling factor {:.3}): reduce the preload or stiffen the columns",
                            stack.preload_total_n,
                            lambda * stack.preload_total_n,
                            lambda
                        ),
                    )
                    .into());
    }
    Ok((model, sys))
}

/// The FE model of a scene, with FE errors located in the scene.
pub fn fe_model(scene: &Scene) -> Result<FeModel, Error> {
    FeModel::from_scene(&scene.model).map_err(|e| locate(scene, e))
}

/// Attaches the scene location of the node an FE error names, when it is a scene node.
pub fn locate(scene: &Scene, e: FemError) -> Error {
    let node = match &e {
        FemError::MasslessDof { node, .. }
        | FemError::Unconstrained { node, .. }
        | FemError::RigidChain { node } => node.clone(),
        _ => return e.into(),
    };
    let id = node
        .strip_prefix("node ")
        .and_then(|s| s.parse::<i64>().ok());
    let idx = id.and_then(|id| scene.file.node.iter().position(|n| n.id == id));
    match idx {
        Some(i) => {
            let loc = scene.locator();
            let key = format!("node[{i}]");
            let mut se: SpecError = loc.err(&format!("{key}.id"), e.to_string());
            se.key = key;
            se.into()
        }
        None => SpecError {
            file: scene.path.clone(),
            line: 0,
            column: 0,
            key: String::new(),
            message: e.to_string(),
        }
        .into(),
    }
}
