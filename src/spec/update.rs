//! `[update]`: model updating (`satqual update`). Names the scene numbers to adjust (dotted TOML
//! paths, as `[sweep]` does), their bounds and scale, and which paired test modes' frequencies
//! the model is fitted to. Checked here, at load: every path holds a number of the scene text,
//! within its bounds, and every target names a `[test_modes]` mode.

use super::Locator;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

/// Iterations of Levenberg–Marquardt when `max_iterations` is not given.
pub const DEFAULT_MAX_ITERATIONS: usize = 50;

#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UpdateSpec {
    #[serde(default = "default_max_iterations")]
    pub max_iterations: usize,
    /// Tikhonov weight toward the starting values (in scaled parameters); lets an
    /// unidentifiable set of parameters be updated anyway.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regularization: Option<f64>,
    pub parameter: Vec<ParameterSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub target: Vec<TargetSpec>,
}

fn default_max_iterations() -> usize {
    DEFAULT_MAX_ITERATIONS
}

/// How a parameter is scaled for the solver.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Scale {
    /// u = ln p: stiffnesses and masses vary by factors, and stay positive.
    #[default]
    Log,
    /// u = p / |p₀|.
    Linear,
}

#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ParameterSpec {
    /// Dotted TOML path of a number in the scene: `a.b`, `spring.0.stiffness.4` or `mass[1].mass_kg`.
    pub path: String,
    pub lower: f64,
    pub upper: f64,
    #[serde(default)]
    pub scale: Scale,
}

impl ParameterSpec {
    /// The path in the `a[0].b[4]` form the scene locator and `sweep::find` read.
    pub fn key(&self) -> String {
        normalize_path(&self.path)
    }
}

#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TargetSpec {
    /// 1-based number of the test mode, in `[test_modes]` (or identification) order.
    pub test_mode: usize,
    #[serde(default = "one")]
    pub weight: f64,
}

fn one() -> f64 {
    1.0
}

/// `spring.0.stiffness.4` → `spring[0].stiffness[4]`; bracketed paths are left as they are.
pub fn normalize_path(path: &str) -> String {
    let mut out = String::new();
    for part in path.split('.') {
        if !out.is_empty() && !part.is_empty() && part.bytes().all(|b| b.is_ascii_digit()) {
            out.push_str(&format!("[{part}]"));
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out.push_str(part);
        }
    }
    out
}

/// Checks `[update]` against the scene text held by `loc`; `test_modes` is the number of
/// `[test_modes]` modes when the table is given (identified modes are checked when run).
pub fn validate(
    spec: &UpdateSpec,
    test_modes: Option<usize>,
    loc: &Locator,
) -> Result<(), SpecError> {
    if spec.parameter.is_empty() {
        return Err(loc.err("update", "[update] needs at least one [[update.parameter]]"));
    }
    if spec.max_iterations == 0 {
        return Err(loc.err("update.max_iterations", "must be at least 1"));
    }
    if let Some(r) = spec.regularization
        && r <= 0.0
    {
        let msg = format!("must be positive, got {r} (leave it out for none)");
        return Err(loc.err("update.regularization", msg));
    }
    for (i, p) in spec.parameter.iter().enumerate() {
        check_parameter(spec, i, p, loc)?;
    }
    for (i, t) in spec.target.iter().enumerate() {
        check_target(spec, i, t, test_modes, loc)?;
    }
    Ok(())
}

fn check_parameter(
    spec: &UpdateSpec,
    i: usize,
    p: &ParameterSpec,
    loc: &Locator,
) -> Result<(), SpecError> {
    let at = |k: &str| format!("update.parameter[{i}].{k}");
    let key = p.key();
    let own = ["update", "test_modes", "correlation", "sweep"];
    if own.iter().any(|o| {
        key == *o || key.starts_with(&format!("{o}.")) || key.starts_with(&format!("{o}["))
    }) {
        let msg = format!(
            "`{}` is not a model value: update adjusts the model only",
            p.path
        );
        return Err(loc.err(&at("path"), msg));
    }
    let value = match super::sweep::target(loc.doc.as_item(), &key) {
        Ok(super::sweep::Target::Float(v)) => v,
        Ok(super::sweep::Target::Integer(v)) => v as f64,
        Err(why) => {
            let msg = format!(
                "{why}; a parameter must be a number written in the scene (its starting value)"
            );
            return Err(loc.err(&at("path"), msg));
        }
    };
    if spec.parameter[..i].iter().any(|q| q.key() == key) {
        return Err(loc.err(&at("path"), format!("`{}` is a parameter twice", p.path)));
    }
    if p.lower >= p.upper {
        let msg = format!("lower {} must be below upper {}", p.lower, p.upper);
        return Err(loc.err(&at("lower"), msg));
    }
    if p.scale == Scale::Log && p.lower <= 0.0 {
        let msg = format!("a log-scaled parameter needs lower > 0, got {}", p.lower);
        return Err(loc.err(&at("lower"), msg));
    }
    if p.scale == Scale::Linear && value == 0.0 {
        let msg = "a linear parameter is scaled by its starting value, which is 0 here";
        return Err(loc.err(&at("path"), msg));
    }
    if value < p.lower || value > p.upper {
        let msg = format!(
            "the starting value {value} of `{}` is outside [{}, {}]",
            p.path, p.lower, p.upper
        );
        let bound = if value < p.lower { "lower" } else { "upper" };
        return Err(loc.err(&at(bound), msg));
    }
    Ok(())
}

fn check_target(
    spec: &UpdateSpec,
    i: usize,
    t: &TargetSpec,
    test_modes: Option<usize>,
    loc: &Locator,
) -> Result<(), SpecError> {
    let at = |k: &str| format!("update.target[{i}].{k}");
    if t.test_mode == 0 || test_modes.is_some_and(|n| t.test_mode > n) {
        let n = test_modes.map_or("the".to_string(), |n| n.to_string());
        let msg = format!(
            "test mode {} is not one of {n} test modes (1-based)",
            t.test_mode
        );
        return Err(loc.err(&at("test_mode"), msg));
    }
    if spec.target[..i].iter().any(|o| o.test_mode == t.test_mode) {
        let msg = format!("test mode {} is a target twice", t.test_mode);
        return Err(loc.err(&at("test_mode"), msg));
    }
    if t.weight <= 0.0 {
        let msg = format!("must be positive, got {}", t.weight);
        return Err(loc.err(&at("weight"), msg));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dotted_indices_become_brackets() {
        assert_eq!(
            normalize_path("spring.0.stiffness.4"),
            "spring[0].stiffness[4]"
        );
        assert_eq!(normalize_path("mass[1].mass_kg"), "mass[1].mass_kg");
        assert_eq!(
            normalize_path("stack.interface.axial_stiffness_n_m"),
            "stack.interface.axial_stiffness_n_m"
        );
    }
}
