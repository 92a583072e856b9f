//! `qualify`: resolves the scene into a plan, runs each planned analysis once (reusing the
//! modes for the responses), gates every result and collects the findings.

use super::plan::{Plan, SeparationPlan};
use super::workflows::{self, separate::SeparateRequest};
use super::{Progress, comparison, provenance};
use crate::error::Error;
use crate::gates::{self, Group, Verdict};
use crate::response::SceneResponse;
use crate::results::{
    ModalSummary, PaperComparison, Provenance, Qualification, SeparationSummary, TestDataSummary,
};
use crate::spec::Scene;

/// What the stages found so far, in the order the report lists it.
#[derive(Default)]
struct Findings {
    ran: Vec<String>,
    gates: Vec<Verdict>,
    comparison: Vec<PaperComparison>,
}

impl Findings {
    /// Adds the gates of one family's rules, every one of them in `group`.
    fn extend_group(&mut self, group: Group, gates: impl IntoIterator<Item = Verdict>) {
        self.gates
            .extend(gates.into_iter().map(|g| g.in_group(group)));
    }
}

/// Plans the analyses the scene asks for, runs each once, and gates the results.
pub fn qualify(scene: &Scene, progress: &dyn Progress) -> Result<Qualification, Error> {
    let plan = Plan::resolve(scene)?;
    let mut found = Findings::default();
    let (modal, response) = modal_and_response(scene, &plan, progress, &mut found)?;
    let separation = match &plan.separation {
        Some(sep) => Some(separation(scene, &plan, sep, progress, &mut found)?),
        None => None,
    };
    let test_data = test_data(scene, &plan, progress, &mut found)?;
    let calibration = match &scene.file.calibration {
        Some(spec) => {
            progress.stage("flight prediction across the test fixture's range");
            Some(workflows::calibration::run(scene, spec)?)
        }
        None => None,
    };
    if found.gates.is_empty() {
        found.gates.push(gates::frequency::nothing_evaluated());
    }
    let provenance = Provenance {
        scene_file: scene.path.display().to_string(),
        scene_hash: provenance::fnv1a(&scene.text),
        satqual_version: env!("CARGO_PKG_VERSION").to_string(),
        modal_solver: modal.as_ref().map(|m| m.result.solver.clone()),
        separation_tolerance: separation.as_ref().map(|s| s.1),
    };
    Ok(Qualification {
        scene: scene.name(),
        title: scene.file.title.clone(),
        pass: found.gates.iter().all(|g| g.pass),
        gates: found.gates,
        ran: found.ran,
        skipped: plan.skipped,
        environments: response.as_ref().map(|r| r.environments.clone()),
        modal,
        response,
        separation: separation.map(|s| s.0),
        test_data,
        paper_comparison: found.comparison,
        calibration,
        assumptions: provenance::assumption_lines(&scene.text),
        provenance,
    })
}

/// The modes, when planned, then the sine and random responses on them; their gates and
/// comparisons.
fn modal_and_response(
    scene: &Scene,
    plan: &Plan,
    progress: &dyn Progress,
    found: &mut Findings,
) -> Result<(Option<ModalSummary>, Option<SceneResponse>), Error> {
    let Some(opts) = &plan.modal else {
        return Ok((None, None));
    };
    progress.stage("modal analysis");
    let (fe, sys) = workflows::modal::run(scene, opts)?;
    found.ran.push("modal".into());
    let mut response = None;
    if plan.sine.is_some() || plan.random.is_some() {
        progress.stage("sine and random response");
        let (sine, random) = (plan.sine.as_ref(), plan.random.as_ref());
        let resp = workflows::response::scene_response(scene, &fe, &sys, sine, random)?;
        found.ran.extend(sine.map(|_| "sine".to_string()));
        found.ran.extend(random.map(|_| "random".to_string()));
        found
            .gates
            .extend(gates::lock_integrity::governing(&resp.governing_margins()));
        if plan.paper_shaker_test {
            found.comparison.extend(comparison::sine_peaks(&resp.sine));
        }
        response = Some(resp);
    }
    let r = sys.result;
    let first = [0, 1, 2].map(|dir| gates::frequency::first_mode(&r, dir));
    found.gates.extend(gates::frequency::first_frequencies(
        first,
        gates::frequency::Band::of(&r),
        &plan.limits,
    ));
    let buckling = r.prestress.as_ref().and_then(|p| p.buckling_factor);
    found
        .gates
        .extend(gates::frequency::buckling(buckling, &plan.limits));
    if plan.paper_shaker_test {
        found.comparison.extend(comparison::resonances(&r));
    }
    let [first_x, first_y, first_z] = first;
    let summary = ModalSummary {
        result: r,
        first_x,
        first_y,
        first_z,
    };
    Ok((Some(summary), response))
}

/// The release and its Monte Carlo; their gates and comparisons. Also returns the
/// integrator tolerance, for the provenance.
fn separation(
    scene: &Scene,
    plan: &Plan,
    sep: &SeparationPlan,
    progress: &dyn Progress,
    found: &mut Findings,
) -> Result<(SeparationSummary, f64), Error> {
    let req = SeparateRequest {
        record_history: true,
        release_shock: false,
        monte_carlo: sep.monte_carlo,
    };
    let run = workflows::separate::run(scene, &req, progress)?;
    found.ran.push("separation".into());
    let limits = &plan.limits;
    let m = &run.model;
    let run_limits = gates::separation::RunLimits {
        max_time_s: m.max_time_s,
        stall_speed_m_s: m.stall_speed_m_s,
        track_clearance_to_m: m.track_clearance_to_m,
    };
    let nominal = gates::separation::nominal(&run.result, &run_limits, limits);
    found.extend_group(Group::Separation, nominal);
    if let (Some(mc), Some(p)) = (&run.monte_carlo, sep.monte_carlo) {
        let what = format!("separation Monte Carlo ({} runs, seed {})", p.runs, p.seed);
        found.ran.push(what);
        found.extend_group(
            Group::Separation,
            gates::separation::monte_carlo(mc, limits),
        );
    }
    found.comparison.extend(comparison::separation(&run.result));
    let summary = SeparationSummary {
        result: run.result,
        monte_carlo: run.monte_carlo,
    };
    Ok((summary, run.model.tolerance))
}

/// The measured logs, when the scene lists any; their gates.
fn test_data(
    scene: &Scene,
    plan: &Plan,
    progress: &dyn Progress,
    found: &mut Findings,
) -> Result<Option<TestDataSummary>, Error> {
    if plan.test_logs.is_empty() {
        return Ok(None);
    }
    progress.stage("test data");
    let loc = scene.locator();
    let (summary, verdicts) = workflows::test_data::run(&plan.test_logs, &plan.limits, &loc)?;
    found.extend_group(Group::TestData, verdicts);
    found.ran.push("test data".into());
    Ok(Some(summary))
}
