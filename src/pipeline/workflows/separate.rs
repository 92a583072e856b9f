//! The separation workflow: the release model of a scene, its nominal run and, when planned,
//! a seeded Monte Carlo of dispersed runs.

use crate::error::{Error, SeparationError};
use crate::pipeline::Progress;
use crate::pipeline::plan::MonteCarloPlan;
use crate::separation::{self, Model, MonteCarloResult, RunOptions, SeparationResult};
use crate::spec::Scene;
use crate::spec::separation::ShockSpec;

/// What to run besides the nominal release.
#[derive(Debug, Clone, Copy)]
pub struct SeparateRequest {
    /// Keep the time histories (for CSV curves and the report's plots).
    pub record_history: bool,
    /// Compute the release shock even when the scene has no `[separation.shock]` (then with
    /// its default options), e.g. for the CSV of `separate --out`.
    pub release_shock: bool,
    pub monte_carlo: Option<MonteCarloPlan>,
}

pub struct SeparateRun {
    pub model: Model,
    pub result: SeparationResult,
    pub monte_carlo: Option<MonteCarloResult>,
}

pub fn run(
    scene: &Scene,
    req: &SeparateRequest,
    progress: &dyn Progress,
) -> Result<SeparateRun, Error> {
    if let Some(mc) = req.monte_carlo {
        crate::pipeline::plan::check_runs(scene, mc.runs, "--monte-carlo")?;
    }
    progress.stage("separation dynamics");
    let model = Model::from_scene(scene)?;
    let shock_spec = scene
        .file
        .separation
        .as_ref()
        .and_then(|s| s.shock.clone())
        .or_else(|| req.release_shock.then(ShockSpec::default));
    let opts = RunOptions {
        record_history: req.record_history,
        record_acceleration: shock_spec.is_some(),
    };
    // The nominal run and the Monte Carlo are independent: run side by side, the nominal
    // run takes one worker while the other starts on the dispersed runs, instead of the
    // whole pool waiting for it. Errors keep their order: nominal, shock, Monte Carlo.
    if req.monte_carlo.is_some() {
        progress.stage("separation Monte Carlo");
    }
    let (nominal, monte_carlo) = rayon::join(
        || separation::run(&model, &opts),
        || {
            req.monte_carlo
                .map(|mc| {
                    let done = |k: usize| progress.count(k, mc.runs);
                    separation::montecarlo::monte_carlo_reporting(&model, mc.runs, mc.seed, &done)
                })
                .transpose()
        },
    );
    let mut result = nominal.map_err(|e| located(scene, e))?;
    if let Some(spec) = &shock_spec {
        progress.stage("release shock");
        result.shock = Some(separation::shock::release_shock(&model, &result, spec)?);
    }
    let monte_carlo = monte_carlo?;
    Ok(SeparateRun {
        model,
        result,
        monte_carlo,
    })
}

/// A run that ran out of its step budget, or whose step fell to round-off, names the key to
/// change; located in the scene like any scene error (file, line, key).
fn located(scene: &Scene, e: SeparationError) -> Error {
    let key = match &e {
        SeparationError::TooManySteps { .. } => "separation.max_steps",
        SeparationError::StepTooSmall { .. } => "separation.tolerance",
        _ => return e.into(),
    };
    let text = e.to_string();
    let message = text
        .strip_prefix(&format!("key `{key}`: "))
        .unwrap_or(&text);
    Error::Spec(scene.locator().err(key, message))
}
