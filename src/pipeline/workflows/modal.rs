//! The modal workflow: the FE model of a scene and its modes (with prestress and buckling
//! factor when the scene has static loads). Errors of the numerical layers are mapped back to
//! the scene: an FE error that names a scene node gets that node's file, line and column.

use crate::error::{Error, FemError, ModalError, SpecError};
use crate::fem::FeModel;
use crate::modal::{ModalOptions, ModalSystem, Shapes};
use crate::pipeline::plan::{ModalOverrides, modal_options};
use crate::spec::{Scene, SolverChoice};

/// The modal analysis of a scene, `[modal]` overridden by a frequency cap or a mode count.
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
    solver: Option<SolverChoice>,
) -> Result<(FeModel, ModalSystem), Error> {
    run(scene, &overridden(scene, fmax_hz, modes, solver))
}

/// [`modal_with_solver`] for a caller that reads what the modes sum up (frequencies,
/// effective masses, prestress), never their shapes: `satqual modal`. The shapes are
/// dropped band by band as the sparse solver finishes them.
pub fn modal_summary(
    scene: &Scene,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
    solver: Option<SolverChoice>,
) -> Result<(FeModel, ModalSystem), Error> {
    let opts = ModalOptions {
        shapes: Shapes::Drop,
        ..overridden(scene, fmax_hz, modes, solver)
    };
    run(scene, &opts)
}

/// The scene's `[modal]` options with the command line's overrides.
fn overridden(
    scene: &Scene,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
    solver: Option<SolverChoice>,
) -> ModalOptions {
    let overrides = ModalOverrides {
        fmax_hz,
        modes,
        solver,
    };
    modal_options(scene, &overrides)
}

/// The modal analysis of a scene with resolved options. The buckling factor on the scene's
/// buckling mesh needs nothing from the modes, so it is solved beside them.
pub fn run(scene: &Scene, opts: &ModalOptions) -> Result<(FeModel, ModalSystem), Error> {
    let model = fe_model(scene)?;
    let (sys, fine_factor) = rayon::join(
        || crate::modal::analyze(&model, opts).map_err(|e| locate_modal_error(scene, e)),
        || fine_buckling_factor(scene, opts),
    );
    let mut sys = sys?;
    if let Some(factor) = fine_factor {
        set_fine_buckling(scene, &mut sys, factor?);
    }
    Ok((model, sys))
}

/// The buckling factor retaken on the scene's buckling mesh, when it has one finer than the
/// modes' (`stack.buckling_column_elements`); past buckling there is the same located error
/// as on the modes' model. `None` when the scene has no such mesh.
fn fine_buckling_factor(scene: &Scene, opts: &ModalOptions) -> Option<Result<Option<f64>, Error>> {
    let fine = scene.buckling_model()?;
    let factor = FeModel::from_scene(&fine)
        .map_err(|e| locate(scene, e))
        .and_then(|model| {
            crate::modal::buckling_factor_of(&model)
                .and_then(|f| crate::modal::refuse_beyond_buckling(f, opts).map(|_| f))
                .map_err(|e| locate_modal_error(scene, e))
        });
    Some(factor)
}

/// The prestress summary takes the buckling mesh's factor and says which model it came from.
fn set_fine_buckling(scene: &Scene, sys: &mut ModalSystem, factor: Option<f64>) {
    let (Some(prestress), Some(stack)) = (sys.result.prestress.as_mut(), &scene.file.stack) else {
        return;
    };
    prestress.buckling_factor = factor;
    prestress.buckling_model = Some(format!(
        "the stack with {} elements per half column (stack.buckling_column_elements; the modes' model has {})",
        stack.buckling_column_elements, stack.column_elements
    ));
}

/// The FE model of a scene, with FE errors located in the scene.
pub fn fe_model(scene: &Scene) -> Result<FeModel, Error> {
    FeModel::from_scene(&scene.model).map_err(|e| locate(scene, e))
}

/// An FE error located at its node; a preload beyond buckling located at the stack's preload,
/// with the buckling load it exceeds.
fn locate_modal_error(scene: &Scene, e: Error) -> Error {
    match (e, &scene.file.stack) {
        (Error::Fem(f), _) => locate(scene, f),
        (Error::Modal(ModalError::BeyondBuckling { factor }), Some(stack)) => {
            let preload = stack.preload_total_n;
            let msg = format!(
                "the preload of {preload:.0} N is above the stack's buckling load of {:.0} N (buckling factor {factor:.3}): reduce the preload or stiffen the columns",
                factor * preload
            );
            scene.locator().err("stack.preload_total_n", msg).into()
        }
        (Error::Modal(ModalError::BeyondBuckling { factor }), None)
            if !scene.file.static_load.is_empty() =>
        {
            let msg = format!(
                "the static loads are above the model's buckling load (buckling factor {factor:.3}: buckling at {factor:.3} × the [[static_load]] entries): the structure has no stable modes; reduce the loads or stiffen the model"
            );
            scene.locator().err("static_load[0].node", msg).into()
        }
        // A solver failure is the model's: named with its scene (the message names the DOF).
        (Error::Modal(m @ ModalError::NoConvergence(_)), _) => in_file(scene, m.to_string()),
        (other, _) => other,
    }
}

/// Attaches the scene location of the node an FE error names, when it is a scene node: the
/// node itself, or the support that holds it; a model held everywhere at its first support.
pub fn locate(scene: &Scene, e: FemError) -> Error {
    let node = match &e {
        FemError::MasslessDof { node, .. }
        | FemError::Unconstrained { node, .. }
        | FemError::RigidChain { node } => node.clone(),
        FemError::SupportedSlave { node, .. } => return locate_support(scene, node, e.to_string()),
        FemError::NoFreeDofs if !scene.file.support.is_empty() => {
            return scene.locator().err("support[0].node", e.to_string()).into();
        }
        _ => return e.into(),
    };
    match scene_node_id(&node).and_then(|id| scene.file.node.iter().position(|n| n.id == id)) {
        Some(i) => {
            let key = format!("node[{i}]");
            let mut se: SpecError = scene.locator().err(&format!("{key}.id"), e.to_string());
            se.key = key;
            se.into()
        }
        None => in_file(scene, e.to_string()),
    }
}

/// The `[[support]]` entry of the scene node named `node` ("node 7"), else the file alone.
fn locate_support(scene: &Scene, node: &str, message: String) -> Error {
    let support =
        scene_node_id(node).and_then(|id| scene.file.support.iter().position(|s| s.node == id));
    match support {
        Some(i) => scene
            .locator()
            .err(&format!("support[{i}].node"), message)
            .into(),
        None => in_file(scene, message),
    }
}

/// The scene id of an FE node label ("node 7"); `None` for a generated node
/// ("beam[0] interior node 3").
fn scene_node_id(label: &str) -> Option<i64> {
    label.strip_prefix("node ")?.parse().ok()
}

/// An error of the scene's model that no single key holds: named with the file alone.
fn in_file(scene: &Scene, message: String) -> Error {
    SpecError {
        file: scene.path.clone(),
        line: 0,
        column: 0,
        key: String::new(),
        message,
    }
    .into()
}
