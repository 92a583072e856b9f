//! What `satqual update` reports: each parameter's start, updated value and 95% interval,
//! each target's frequencies before and after, the identifiability figures, how the solver
//! stopped, and the updated scene text with each changed value annotated.

use super::problem::{Problem, Solved};
use crate::error::Error;
use crate::modal::updating::identifiability::{Identifiability, t975};
use crate::modal::updating::lm::{Outcome, Stop};
use crate::spec::update::{Scale, UpdateSpec};
use serde::Serialize;

#[derive(Debug, Clone, Serialize)]
pub struct ParameterResult {
    pub path: String,
    pub start: f64,
    pub value: f64,
    /// 95% interval of the linearised estimate; null when undefined (see `notes`).
    pub ci_low: Option<f64>,
    pub ci_high: Option<f64>,
    pub lower: f64,
    pub upper: f64,
    pub scale: Scale,
    pub identifiable: bool,
    pub at_bound: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct TargetResult {
    pub test_mode: usize,
    /// The FE mode paired after updating (and before, when it differs: mode switching).
    pub fe_mode: usize,
    pub fe_mode_before: usize,
    pub weight: f64,
    pub test_hz: f64,
    pub before_hz: f64,
    pub after_hz: f64,
    pub error_before_pct: f64,
    pub error_after_pct: f64,
    pub mac: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Update {
    pub parameters: Vec<ParameterResult>,
    pub targets: Vec<TargetResult>,
    /// Of the weighted sensitivity matrix in scaled parameters at the updated values.
    pub singular_values: Vec<f64>,
    pub correlation: Vec<Vec<f64>>,
    pub iterations: usize,
    pub converged: bool,
    pub stop: &'static str,
    /// RMS of the relative frequency errors of the targets, %.
    pub residual_before_pct: f64,
    pub residual_after_pct: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regularization: Option<f64>,
    pub warnings: Vec<String>,
    pub notes: Vec<String>,
    /// Per-mode damping identified from the test modes' measured sine peaks.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub damping: Vec<super::damping::IdentifiedDamping>,
    /// The scene with the updated values written in.
    #[serde(skip)]
    pub updated_text: String,
}

impl Update {
    /// One line on how the fit went: counts, iterations, the stop and the RMS error before
    /// and after (the command's first line and the report's preamble).
    pub fn headline(&self) -> String {
        format!(
            "{} parameter(s), {} target(s); {} iteration(s), {} ({}); RMS frequency error {:.3}% -> {:.3}%",
            self.parameters.len(),
            self.targets.len(),
            self.iterations,
            if self.converged {
                "converged"
            } else {
                "NOT converged"
            },
            self.stop,
            self.residual_before_pct,
            self.residual_after_pct
        )
    }
}

pub fn assemble(
    problem: &Problem,
    spec: &UpdateSpec,
    before: &Solved,
    after: &Solved,
    id: &Identifiability,
    outcome: &Outcome,
) -> Result<Update, Error> {
    let targets = target_rows(problem, before, after);
    let rms = |f: fn(&TargetResult) -> f64| {
        (targets.iter().map(|t| f(t).powi(2)).sum::<f64>() / targets.len() as f64).sqrt()
    };
    let (rms_before, rms_after) = (rms(|t| t.error_before_pct), rms(|t| t.error_after_pct));
    let parameters = parameter_rows(problem, after, id);
    let mut u = Update {
        parameters,
        targets,
        singular_values: id.singular_values.clone(),
        correlation: id.correlation.clone(),
        iterations: outcome.iterations,
        converged: outcome.stop != Stop::MaxIterations,
        stop: super::stop_text(outcome.stop),
        residual_before_pct: rms_before,
        residual_after_pct: rms_after,
        regularization: spec.regularization,
        warnings: Vec::new(),
        notes: Vec::new(),
        damping: Vec::new(),
        updated_text: String::new(),
    };
    explain(&mut u, problem, spec, after, id);
    let notes = annotations(problem, &u);
    u.updated_text = problem.text_at(&after.values, Some(&notes))?;
    finite(&u)?;
    Ok(u)
}

fn target_rows(problem: &Problem, before: &Solved, after: &Solved) -> Vec<TargetResult> {
    let pct = |f: f64, t: f64| 100.0 * (f - t) / t;
    (problem.targets.iter().enumerate())
        .map(|(i, t)| {
            let test_hz = problem.test[t.test].frequency_hz;
            let (b, a) = (&before.paired[i], &after.paired[i]);
            TargetResult {
                test_mode: t.test + 1,
                fe_mode: a.fe_mode,
                fe_mode_before: b.fe_mode,
                weight: t.weight,
                test_hz,
                before_hz: b.fe_hz,
                after_hz: a.fe_hz,
                error_before_pct: pct(b.fe_hz, test_hz),
                error_after_pct: pct(a.fe_hz, test_hz),
                mac: a.mac,
            }
        })
        .collect()
}

fn parameter_rows(problem: &Problem, after: &Solved, id: &Identifiability) -> Vec<ParameterResult> {
    let dof = problem.targets.len().saturating_sub(problem.params.len());
    (problem.params.iter().enumerate())
        .map(|(c, p)| {
            let value = after.values[c];
            let ci = id.std_dev.as_ref().map(|sd| {
                let half = t975(dof) * sd[c];
                let u = p.to_u(value);
                let (a, b) = (p.to_p(u - half), p.to_p(u + half));
                (a.min(b), a.max(b))
            });
            // An interval beyond the floating-point range is no interval: reported as undefined.
            let ci = ci.filter(|(a, b)| a.is_finite() && b.is_finite());
            ParameterResult {
                path: p.path.clone(),
                start: p.start,
                value,
                ci_low: ci.map(|c| c.0),
                ci_high: ci.map(|c| c.1),
                lower: p.lower,
                upper: p.upper,
                scale: p.scale,
                identifiable: id.identifiable[c],
                at_bound: value <= p.lower || value >= p.upper,
            }
        })
        .collect()
}

/// Warnings (what may make the result wrong) and notes (how to read it).
fn explain(
    u: &mut Update,
    problem: &Problem,
    spec: &UpdateSpec,
    after: &Solved,
    id: &Identifiability,
) {
    let (m, n) = (problem.targets.len(), problem.params.len());
    if !u.converged {
        u.warnings.push(format!(
            "not converged: stopped after max_iterations = {} with the last iterate; the values may be short of the optimum",
            spec.max_iterations
        ));
    }
    for p in u.parameters.iter().filter(|p| p.at_bound) {
        let side = if p.value <= p.lower { "lower" } else { "upper" };
        u.warnings.push(format!(
            "`{}` ended at its {side} bound {}: the best fit may lie beyond it",
            p.path, p.value
        ));
    }
    for p in u.parameters.iter().filter(|p| !p.identifiable) {
        u.warnings.push(format!(
            "`{}` is not identifiable from the targets (it lies along a direction of singular value < 1e-6 of the largest); {}",
            p.path,
            if spec.regularization.is_some() {
                "its value is held by the regularization"
            } else {
                "it became so at the updated values: its value is arbitrary along that direction"
            }
        ));
    }
    for p in u.parameters.iter().filter(|p| p.ci_low.is_none()) {
        if id.std_dev.is_some() {
            u.notes.push(format!(
                "the 95% interval of `{}` is beyond the floating-point range: the data bound it in no useful sense",
                p.path
            ));
        }
    }
    correlated(u);
    if id.std_dev.is_none() {
        let why = if m <= n {
            format!(
                "{m} target(s) for {n} parameter(s) leave no degree of freedom to estimate the residual's scatter"
            )
        } else if spec.regularization.is_some() {
            "the regularization biases the estimate toward the starting values".to_string()
        } else {
            "some direction is not identifiable".to_string()
        };
        u.notes.push(format!("95% intervals undefined: {why}"));
    } else {
        u.notes.push(format!(
            "95% intervals: linearised, cov = s²(JᵀJ)⁻¹ with s² = ‖r‖²/(m − n), m − n = {}, Student t {:.3}",
            m - n,
            t975(m - n)
        ));
    }
    if after.prestressed {
        u.notes.push("the prestress stiffness K_G is left out of the sensitivities (the frequencies themselves include it)".into());
    }
    for t in u.targets.iter().filter(|t| t.fe_mode != t.fe_mode_before) {
        u.notes.push(format!(
            "test mode {} paired with FE mode {} before and {} after updating (mode switching, followed by re-pairing at every iteration)",
            t.test_mode, t.fe_mode_before, t.fe_mode
        ));
    }
}

/// Above this |correlation| two estimates are one combination the data fix, not two values.
const CORRELATED: f64 = 0.99;

fn correlated(u: &mut Update) {
    let n = u.parameters.len();
    for a in 0..n {
        for b in a + 1..n {
            let c = u.correlation[a][b];
            if c.abs() > CORRELATED {
                u.warnings.push(format!(
                    "the estimates of `{}` and `{}` are correlated at {c:+.4}: the targets fix a combination of the two, not each (their effects on the frequencies are nearly proportional)",
                    u.parameters[a].path, u.parameters[b].path
                ));
            }
        }
    }
}

/// `updated by satqual update from <as written> (<m> paired modes, residual <rms>%)` for each
/// changed value.
fn annotations(problem: &Problem, u: &Update) -> Vec<Option<String>> {
    let loc = problem.base.locator();
    (problem.params.iter().zip(&u.parameters))
        .map(|(p, r)| {
            if r.value == r.start {
                return None;
            }
            let written = crate::spec::sweep::find(loc.doc_item(), &p.key)
                .ok()
                .and_then(|i| i.span())
                .and_then(|s| problem.base.text.get(s))
                .map(|t| t.trim().to_string())
                .unwrap_or_else(|| p.start.to_string());
            Some(format!(
                "updated by satqual update from {written} ({} paired modes, residual {:.2}%)",
                u.targets.len(),
                u.residual_after_pct
            ))
        })
        .collect()
}

/// No NaN or infinity reaches an output.
fn finite(u: &Update) -> Result<(), Error> {
    let value = serde_json::to_value(u).map_err(|e| Error::Other(e.to_string()))?;
    crate::output_check::check_json(&value, "update result")
}
