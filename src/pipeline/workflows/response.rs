//! The sine and random workflows: modes of the scene, the shared response preparation, then
//! the analysis on each planned axis with the default options.

use crate::error::Error;
use crate::fem::FeModel;
use crate::modal::{ModalOptions, ModalSystem};
use crate::pipeline::plan::AxesPlan;
use crate::response::{
    self, Prepared, RandomAxis, RandomOptions, SceneResponse, SineAxis, SineOptions,
};
use crate::spec::Scene;
use crate::spec::analysis::{DampingSpec, RandomSpec, SineSpec};

/// A response analysis run on its own (`satqual sine` / `satqual random`).
pub struct ResponseRun<A> {
    pub damping: DampingSpec,
    pub axes: Vec<A>,
}

/// `[sine]` on the planned axes, with the scene's modes.
pub fn sine(scene: &Scene, plan: &AxesPlan<SineSpec>) -> Result<ResponseRun<SineAxis>, Error> {
    let (model, sys) = super::modal::run(scene, &default_modal(scene))?;
    refuse_unsupported(scene, &sys)?;
    let prep = Prepared::new(scene, &model, &sys)?;
    Ok(ResponseRun {
        axes: sine_axes(&prep, plan)?,
        damping: prep.damping,
    })
}

/// `[random]` on the planned axes, with the scene's modes.
pub fn random(
    scene: &Scene,
    plan: &AxesPlan<RandomSpec>,
) -> Result<ResponseRun<RandomAxis>, Error> {
    let (model, sys) = super::modal::run(scene, &default_modal(scene))?;
    refuse_unsupported(scene, &sys)?;
    let prep = Prepared::new(scene, &model, &sys)?;
    Ok(ResponseRun {
        axes: random_axes(&prep, plan)?,
        damping: prep.damping,
    })
}

/// Both analyses of a qualification on modes already computed.
pub fn scene_response(
    scene: &Scene,
    model: &FeModel,
    sys: &ModalSystem,
    sine: Option<&AxesPlan<SineSpec>>,
    random: Option<&AxesPlan<RandomSpec>>,
) -> Result<SceneResponse, Error> {
    refuse_unsupported(scene, sys)?;
    let prep = Prepared::new(scene, model, sys)?;
    Ok(SceneResponse {
        sine: sine.map_or(Ok(Vec::new()), |p| sine_axes(&prep, p))?,
        random: random.map_or(Ok(Vec::new()), |p| random_axes(&prep, p))?,
    })
}

/// A base-driven response needs the structure held by its supports in every direction: a
/// rigid-body mode (0 Hz) would move without bound, so it is refused at the scene's supports.
fn refuse_unsupported(scene: &Scene, sys: &ModalSystem) -> Result<(), Error> {
    let r = &sys.result;
    if r.rigid_body_modes == 0 {
        return Ok(());
    }
    let key = if scene.file.support.is_empty() {
        "support"
    } else {
        "support[0]"
    };
    let msg = format!(
        "the model has {} rigid-body mode(s) (0 Hz; {}): a base-driven sine or random response needs the structure held by its supports in every direction; add supports or springs to ground",
        r.rigid_body_modes,
        r.rigid_body_directions.join(", ")
    );
    Err(scene.locator().err(key, msg).into())
}

fn default_modal(scene: &Scene) -> ModalOptions {
    crate::pipeline::plan::modal_options(scene, &Default::default())
}

fn sine_axes(prep: &Prepared, plan: &AxesPlan<SineSpec>) -> Result<Vec<SineAxis>, Error> {
    let opts = SineOptions::default();
    plan.axes
        .iter()
        .map(|&a| response::sine::run(prep, &plan.spec, a, &opts))
        .collect()
}

fn random_axes(prep: &Prepared, plan: &AxesPlan<RandomSpec>) -> Result<Vec<RandomAxis>, Error> {
    let opts = RandomOptions::default();
    plan.axes
        .iter()
        .map(|&a| response::random::run(prep, &plan.spec, a, &opts))
        .collect()
}
