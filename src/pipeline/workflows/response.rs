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
use crate::spec::environment::{Environments, RandomEnvironment, SineEnvironment};

/// A response analysis run on its own (`satqual sine` / `satqual random`).
pub struct ResponseRun<A> {
    pub damping: DampingSpec,
    pub axes: Vec<A>,
    /// The random input as applied (`satqual random` only).
    pub environment: Option<RandomEnvironment>,
}

/// `[sine]` on the planned axes, with the scene's modes.
pub fn sine(scene: &Scene, plan: &AxesPlan<SineSpec>) -> Result<ResponseRun<SineAxis>, Error> {
    let (model, sys) = super::modal::run(scene, &default_modal(scene))?;
    refuse_unfit(scene, &sys)?;
    let prep = Prepared::new(scene, &model, &sys)?;
    Ok(ResponseRun {
        axes: sine_axes(&prep, plan)?,
        damping: prep.damping,
        environment: None,
    })
}

/// `[random]` on the planned axes, with the scene's modes.
pub fn random(
    scene: &Scene,
    plan: &AxesPlan<RandomSpec>,
) -> Result<ResponseRun<RandomAxis>, Error> {
    let (model, sys) = super::modal::run(scene, &default_modal(scene))?;
    refuse_unfit(scene, &sys)?;
    let prep = Prepared::new(scene, &model, &sys)?;
    let (axes, environment) = random_axes(&prep, plan)?;
    Ok(ResponseRun {
        axes,
        damping: prep.damping,
        environment: Some(environment),
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
    refuse_unfit(scene, sys)?;
    let prep = Prepared::new(scene, model, sys)?;
    let mut environments = Environments {
        sine: sine.map(|p| SineEnvironment::of(&p.spec)),
        random: None,
    };
    let random = match random {
        Some(p) => {
            let (axes, env) = random_axes(&prep, p)?;
            environments.random = Some(env);
            axes
        }
        None => Vec::new(),
    };
    Ok(SceneResponse {
        sine: sine.map_or(Ok(Vec::new()), |p| sine_axes(&prep, p))?,
        random,
        environments,
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

/// What a response analysis refuses before it starts: an unsupported model, damping given to
/// modes that were renumbered.
fn refuse_unfit(scene: &Scene, sys: &ModalSystem) -> Result<(), Error> {
    refuse_unsupported(scene, sys)?;
    refuse_renumbered_damping(scene, sys)
}

/// Modes extracted only below the top of an excitation band would leave the resonances
/// between them out of the response (the residual vector stands for them only
/// quasi-statically), and its peaks and margins would come out low: refused, naming the key
/// that stopped the extraction. A model whose every mode was extracted has nothing missing.
fn refuse_truncated_basis(
    scene: &Scene,
    sys: &ModalSystem,
    what: &str,
    band_top_hz: f64,
) -> Result<(), Error> {
    let modes = &sys.result.modes;
    if modes.len() >= sys.result.dofs {
        return Ok(());
    }
    let opts = default_modal(scene);
    let last = modes.last().map_or(0.0, |m| m.frequency_hz);
    let stopped_by_count = opts.modes.is_some_and(|n| modes.len() >= n);
    let (limit_hz, key) = match opts.fmax_hz {
        Some(f) if !stopped_by_count => (f, "modal.fmax_hz"),
        _ => (last, "modal.modes"),
    };
    if limit_hz >= band_top_hz {
        return Ok(());
    }
    let msg = format!(
        "the modes stop at {limit_hz:.1} Hz but the {what} band reaches {band_top_hz:.1} Hz: \
         resonances between them would be missing from the response (the residual vector \
         stands for them only quasi-statically) and its peaks and margins would come out low; \
         extract the modes to at least {band_top_hz:.1} Hz (`modal.fmax_hz`)"
    );
    Err(scene.locator().err(key, msg).into())
}

/// A `[damping] modes` entry that names its mode's direction must find the mode numbered so
/// with its largest effective-mass fraction in that direction: otherwise the model's modes
/// were renumbered (a mesh or model change) and the ratio would land on another mode.
fn refuse_renumbered_damping(scene: &Scene, sys: &ModalSystem) -> Result<(), Error> {
    let Some(entries) = scene.file.damping.as_ref().and_then(|d| d.modes.as_ref()) else {
        return Ok(());
    };
    let modes = &sys.result.modes;
    for (i, e) in entries.iter().enumerate() {
        if e.mode > sys.result.dofs {
            let msg = format!(
                "mode {} does not exist: the model has {} DOFs, so at most that many modes",
                e.mode, sys.result.dofs
            );
            return Err(scene
                .locator()
                .err(&format!("damping.modes[{i}].mode"), msg)
                .into());
        }
        let Some(want) = e.direction.as_deref() else {
            continue;
        };
        let found = modes.get(e.mode - 1).map(|m| (m.dominant_direction(), m));
        if found.is_some_and(|(d, _)| d == Some(want)) {
            continue;
        }
        let first = modes.iter().find(|m| m.dominant_direction() == Some(want));
        let msg = format!(
            "mode {} is given as a `{want}` mode, but {}; the model's modes were renumbered: {}",
            e.mode,
            match found {
                Some((d, m)) => format!(
                    "its largest effective-mass fraction is in `{}` ({:.3} Hz)",
                    d.unwrap_or("none"),
                    m.frequency_hz
                ),
                None => format!("the model has {} modes", modes.len()),
            },
            match first {
                Some(m) => format!(
                    "the lowest `{want}` mode is mode {} ({:.3} Hz) (`satqual modal` lists them)",
                    m.index, m.frequency_hz
                ),
                None => format!("no mode moves mostly in `{want}` (`satqual modal` lists them)"),
            }
        );
        let key = format!("damping.modes[{i}].direction");
        return Err(scene.locator().err(&key, msg).into());
    }
    Ok(())
}

fn default_modal(scene: &Scene) -> ModalOptions {
    crate::pipeline::plan::modal_options(scene, &Default::default())
}

fn sine_axes(prep: &Prepared, plan: &AxesPlan<SineSpec>) -> Result<Vec<SineAxis>, Error> {
    refuse_truncated_basis(prep.scene, prep.sys, "sine", plan.spec.band().1)?;
    let mut opts = SineOptions::default();
    opts.grid.max_points = prep.scene.file.limits().grid_points;
    plan.axes
        .iter()
        .map(|&a| response::sine::run(prep, &plan.spec, a, &opts))
        .collect()
}

/// The random analysis on every planned axis, with the input applied for the model's mass
/// (a named environment at its level, reduced for weight when asked), and that input.
fn random_axes(
    prep: &Prepared,
    plan: &AxesPlan<RandomSpec>,
) -> Result<(Vec<RandomAxis>, RandomEnvironment), Error> {
    let mut opts = RandomOptions::default();
    opts.grid.max_points = prep.scene.file.limits().grid_points;
    let mass = prep.sys.result.total_mass_kg - prep.scene.file.fixture_mass_kg();
    let (spec, env) = plan
        .spec
        .applied(Some(mass))
        .map_err(|e| prep.scene.locator().err("random", e))?;
    let top = env.profile.iter().map(|p| p[0]).fold(0.0, f64::max);
    refuse_truncated_basis(prep.scene, prep.sys, "random", top)?;
    let axes = plan
        .axes
        .iter()
        .map(|&a| response::random::run(prep, &spec, a, &opts))
        .collect::<Result<_, _>>()?;
    Ok((axes, env))
}
