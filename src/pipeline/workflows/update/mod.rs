//! The model-updating workflow of `satqual update`: the scene's `[update]` parameters adjusted
//! by bounded Levenberg–Marquardt until the paired FE frequencies match the test ones, with
//! the identifiability of the parameters and the updated scene text.

mod damping;
pub mod overlay;
pub mod problem;
mod result;

use crate::error::Error;
use crate::modal::updating::identifiability::{Identifiability, analyse};
use crate::modal::updating::lm::{self, Evaluation, Stop};
use crate::pipeline::plan::{ModalOverrides, modal_options};
use crate::pipeline::workflows::correlate::{fe_side, pair_modes, test_modes};
use crate::spec::Scene;
use crate::spec::update::UpdateSpec;
pub use damping::IdentifiedDamping;
use problem::{Param, Problem, Target};
pub use result::{ParameterResult, TargetResult, Update};

/// Updates the scene, then identifies the damping of the test modes that give a measured sine
/// peak; the result holds the updated scene text.
pub fn run(scene: &Scene) -> Result<Update, Error> {
    run_with(scene, true)
}

/// The frequency fit alone (the parameters), without the damping identification.
pub fn frequencies_only(scene: &Scene) -> Result<Update, Error> {
    run_with(scene, false)
}

fn run_with(scene: &Scene, identify_damping: bool) -> Result<Update, Error> {
    let loc = scene.locator();
    let Some(spec) = scene.file.update.clone() else {
        let msg = "update needs an [update] section with [[update.parameter]] entries";
        return Err(loc.err("update", msg).into());
    };
    if scene.file.test_point.is_empty() {
        let msg = "update needs [[test_point]] entries mapping channels to model DOFs";
        return Err(loc.err("test_point", msg).into());
    }
    let (test, _) = test_modes::test_modes(scene)?;
    let opts = modal_options(scene, &ModalOverrides::default());
    let mut problem = Problem {
        base: scene,
        params: params(scene, &spec),
        targets: Vec::new(),
        test,
        opts,
    };
    problem.targets = targets(&problem, &spec)?;
    let start: Vec<f64> = problem.params.iter().map(|p| p.start).collect();
    let before = problem.solve(&start)?;
    let j0 = problem.jacobian(&before)?;
    let reg = spec.regularization.unwrap_or(0.0);
    let id0 = analyse(&j0, &problem.residuals(&before), reg);
    if spec.regularization.is_none() {
        check_identifiable(&problem, &id0)?;
    }
    let outcome = minimize(&problem, &spec, &start)?;
    let values: Vec<f64> = (problem.params.iter().zip(&outcome.u))
        .map(|(p, &u)| p.to_p(u).clamp(p.lower, p.upper))
        .collect();
    let after = problem.solve(&values)?;
    let r = problem.residuals(&after);
    let id = analyse(&problem.jacobian(&after)?, &r, reg);
    let mut u = result::assemble(&problem, &spec, &before, &after, &id, &outcome)?;
    if identify_damping {
        u.damping = damping::identify(&problem.scene_at(&values)?, &u.targets)?;
    }
    if !u.damping.is_empty() {
        u.updated_text = with_identified_damping(&scene.path, &u.updated_text, &u.damping)?;
    }
    Ok(u)
}

/// `text` with the identified ratios in `[damping] modes`, each noting its evidence.
fn with_identified_damping(
    path: &std::path::Path,
    text: &str,
    identified: &[IdentifiedDamping],
) -> Result<String, Error> {
    use crate::spec::damping_edit::{IdentifiedModeDamping, with_mode_damping};
    let entries: Vec<IdentifiedModeDamping> = (identified.iter())
        .map(|d| IdentifiedModeDamping {
            mode: d.fe_mode,
            zeta: d.zeta,
            direction: d.direction.clone(),
            source: format!(
                "identified by satqual update: test mode {} peak {} g at `{}` reproduced (was ζ = {:.6})",
                d.test_mode, d.measured_g, d.channel, d.zeta_start
            ),
        })
        .collect();
    with_mode_damping(text, &entries).map_err(|e| Error::Other(format!("{}: {e}", path.display())))
}

/// The `[[update.parameter]]`s with their starting values read from the scene.
pub fn params(scene: &Scene, spec: &UpdateSpec) -> Vec<Param> {
    let loc = scene.locator();
    spec.parameter
        .iter()
        .map(|p| {
            let key = p.key();
            let start = match crate::spec::sweep::target(loc.doc_item(), &key) {
                Ok(crate::spec::sweep::Target::Float(v)) => v,
                Ok(crate::spec::sweep::Target::Integer(v)) => v as f64,
                Err(_) => unreachable!("validated at load: `{key}` holds a number"),
            };
            Param {
                path: p.path.clone(),
                key,
                start,
                lower: p.lower,
                upper: p.upper,
                scale: p.scale,
            }
        })
        .collect()
}

/// The `[[update.target]]`s, or every test mode paired at the starting values.
fn targets(problem: &Problem, spec: &UpdateSpec) -> Result<Vec<Target>, Error> {
    let loc = problem.base.locator();
    if !spec.target.is_empty() {
        let n = problem.test.len();
        if let Some(i) = spec.target.iter().position(|t| t.test_mode > n) {
            let msg = format!(
                "test mode {} is not one of the {n} test modes",
                spec.target[i].test_mode
            );
            return Err(loc
                .err(&format!("update.target[{i}].test_mode"), msg)
                .into());
        }
        return Ok(spec
            .target
            .iter()
            .map(|t| Target {
                test: t.test_mode - 1,
                weight: t.weight,
            })
            .collect());
    }
    let scene = problem.base;
    let (model, sys) = super::modal::run(scene, &problem.opts)?;
    let rows = fe_side::test_dof_rows(scene, &model, &sys)?;
    fe_side::held_points(scene, &rows)?;
    let fe = fe_side::fe_modes(&sys, &rows);
    let (_, _, pairs) = pair_modes(scene, &problem.test, &fe);
    if pairs.is_empty() {
        return Err(loc
            .err(
                "update",
                "no test mode pairs with an FE mode: nothing to fit",
            )
            .into());
    }
    Ok(pairs
        .iter()
        .map(|p| Target {
            test: p.test,
            weight: 1.0,
        })
        .collect())
}

/// Without regularization, a direction the targets cannot resolve is an error at the
/// parameter that leans on it most, naming every parameter in it.
fn check_identifiable(problem: &Problem, id: &Identifiability) -> Result<(), Error> {
    let Some(v) = id.unresolved.first() else {
        return Ok(());
    };
    let worst = (0..v.len())
        .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()).then(b.cmp(&a)))
        .unwrap_or(0);
    let involved: Vec<String> = (0..v.len())
        .filter(|&c| v[c].abs() >= crate::modal::updating::identifiability::COMPONENT)
        .map(|c| format!("{} ({:+.3})", problem.params[c].path, v[c]))
        .collect();
    let (m, n) = (problem.targets.len(), problem.params.len());
    let msg = format!(
        "the {m} target frequencies cannot identify the {n} parameters: {} unresolved direction(s) (singular values {}), the first along {}; fix or remove a parameter, add targets, or give [update] regularization",
        id.unresolved.len(),
        id.singular_values
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect::<Vec<_>>()
            .join(", "),
        involved.join(", ")
    );
    Err(problem
        .base
        .locator()
        .err(&format!("update.parameter[{worst}].path"), msg)
        .into())
}

fn minimize(problem: &Problem, spec: &UpdateSpec, start: &[f64]) -> Result<lm::Outcome, Error> {
    let u0: Vec<f64> = problem
        .params
        .iter()
        .zip(start)
        .map(|(p, &v)| p.to_u(v))
        .collect();
    let o = lm::Options {
        max_iterations: spec.max_iterations,
        regularization: spec.regularization.unwrap_or(0.0),
        prior: u0.clone(),
        lower: problem.params.iter().map(|p| p.to_u(p.lower)).collect(),
        upper: problem.params.iter().map(|p| p.to_u(p.upper)).collect(),
    };
    let eval = |u: &[f64]| -> Result<Evaluation, Error> {
        let values: Vec<f64> = (problem.params.iter().zip(u))
            .map(|(p, &x)| p.to_p(x).clamp(p.lower, p.upper))
            .collect();
        let s = problem.solve(&values)?;
        Ok(Evaluation {
            r: problem.residuals(&s),
            j: problem.jacobian(&s)?,
        })
    };
    lm::minimize(eval, &u0, &o)
}

pub(crate) fn stop_text(stop: Stop) -> &'static str {
    match stop {
        Stop::Step => "relative step below 1e-8",
        Stop::Gradient => "gradient below 1e-10",
        Stop::MaxIterations => "max_iterations reached",
    }
}
