//! The separation workflow: the release model of a scene, its nominal run and, when planned,
//! a seeded Monte Carlo of dispersed runs.

use crate::error::Error;
use crate::pipeline::Progress;
use crate::pipeline::plan::MonteCarloPlan;
use crate::separation::{self, Model, MonteCarloResult, RunOptions, SeparationResult};
use crate::spec::Scene;

/// What to run besides the nominal release.
#[derive(Debug, Clone, Copy)]
pub struct SeparateRequest {
    /// Keep the time histories (for CSV curves and the report's plots).
    pub record_history: bool,
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
    let opts = RunOptions {
        record_history: req.record_history,
    };
    let result = separation::run(&model, &opts)?;
    let monte_carlo = match req.monte_carlo {
        Some(mc) => {
            progress.stage("separation Monte Carlo");
            Some(separation::monte_carlo(&model, mc.runs, mc.seed)?)
        }
        None => None,
    };
    Ok(SeparateRun {
        model,
        result,
        monte_carlo,
    })
}
