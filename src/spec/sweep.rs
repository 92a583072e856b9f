//! `[sweep]`: a parameter study of the release. It names scene keys by their dotted TOML path
//! (`stack.satellite_pitch_m`, `separation.contact.friction`, `separation.interface[0].stiffness_n_m[2]`)
//! and the values each takes: a full grid (`values` or `from`/`to`/`steps` per key) or a seeded
//! Latin hypercube (`method = "lhs"`, `points`, `seed`, `bounds` per key). Each point is the
//! scene with those values written in and loaded again through [`super::Scene::parse`], so every
//! check of the loader applies to it.
//!
//! Checked here, at load: every key exists in the scene text and holds a number, an integer key
//! gets integral values only, and no key is one the Monte Carlo redraws in every run.

use super::Locator;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

/// The most points a sweep may have: each point is a whole Monte Carlo.
pub const MAX_POINTS: usize = 100_000;

#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SweepMethod {
    /// Every combination of the keys' values; the first key varies slowest.
    #[default]
    Grid,
    /// A Latin hypercube of `points` points in the keys' bounds.
    Lhs,
}

#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    #[serde(default)]
    pub method: SweepMethod,
    /// Number of points of a Latin hypercube.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<usize>,
    /// Seed of the Latin hypercube (ChaCha8).
    #[serde(default)]
    pub seed: u64,
    pub parameter: Vec<SweepParameter>,
}

/// One swept key and the values it takes.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepParameter {
    /// Dotted TOML path of a number in the scene.
    pub key: String,
    /// Grid: the values, in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
    /// Grid: `steps` values evenly spaced from `from` to `to`, both included.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<usize>,
    /// Latin hypercube: [low, high].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<[f64; 2]>,
}

impl SweepParameter {
    /// The grid values of this key (empty for a Latin hypercube parameter).
    pub fn grid_values(&self) -> Vec<f64> {
        if let Some(v) = &self.values {
            return v.clone();
        }
        match (self.from, self.to, self.steps) {
            (Some(a), Some(b), Some(1)) if a == b => vec![a],
            (Some(a), Some(b), Some(n)) if n >= 2 => (0..n)
                .map(|k| {
                    if k + 1 == n {
                        b
                    } else {
                        a + (b - a) * k as f64 / (n - 1) as f64
                    }
                })
                .collect(),
            _ => Vec::new(),
        }
    }
}

/// What a swept key holds in the scene text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    Integer(i64),
    Float(f64),
}

/// The item at dotted path `key` (`a.b[2].c`), or why there is none.
pub fn find<'a>(root: &'a toml_edit::Item, key: &str) -> Result<&'a toml_edit::Item, String> {
    let mut item = root;
    for (name, index) in super::split_path(key) {
        item = item
            .get(name.as_str())
            .ok_or_else(|| format!("`{key}`: no key `{name}` in the scene"))?;
        if let Some(i) = index {
            item = item
                .get(i)
                .ok_or_else(|| format!("`{key}`: `{name}` has no element {i}"))?;
        }
    }
    Ok(item)
}

/// The number at `key`, or why it cannot be swept.
pub fn target(root: &toml_edit::Item, key: &str) -> Result<Target, String> {
    let item = find(root, key)?;
    match item.as_value() {
        Some(toml_edit::Value::Integer(i)) => Ok(Target::Integer(*i.value())),
        Some(toml_edit::Value::Float(f)) => Ok(Target::Float(*f.value())),
        Some(v) => Err(format!("`{key}` holds {}, not a number", v.type_name())),
        None => Err(format!("`{key}` is a table, not a number")),
    }
}

/// Keys the Monte Carlo replaces in every run when a dispersion range is set: sweeping them
/// would change nothing, silently.
const REDRAWN: [(&str, &str); 2] = [
    ("separation.contact.friction", "friction_range"),
    ("separation.contact.clearance_m", "clearance_range_m"),
];

/// Checks `[sweep]` against the scene text held by `loc`.
pub fn validate(spec: &SweepSpec, loc: &Locator) -> Result<(), SpecError> {
    if spec.parameter.is_empty() {
        return Err(loc.err("sweep", "a sweep needs at least one [[sweep.parameter]]"));
    }
    let mut count: usize = 1;
    for (i, p) in spec.parameter.iter().enumerate() {
        let at = format!("sweep.parameter[{i}]");
        check_key(spec, i, p, loc)?;
        let n = match spec.method {
            SweepMethod::Grid => check_grid(p, &at, loc)?,
            SweepMethod::Lhs => check_bounds(p, &at, loc)?,
        };
        count = count.saturating_mul(n);
    }
    if spec.method == SweepMethod::Lhs {
        count = match spec.points {
            Some(n) if n >= 1 => n,
            _ => return Err(loc.err("sweep.points", "a Latin hypercube needs points ≥ 1")),
        };
    } else if spec.points.is_some() {
        return Err(loc.err(
            "sweep.points",
            "`points` belongs to method = \"lhs\"; a grid has the product of its keys' values",
        ));
    }
    if count > MAX_POINTS {
        return Err(loc.err(
            "sweep",
            format!("{count} points is above the limit of {MAX_POINTS}"),
        ));
    }
    Ok(())
}

/// The key exists, holds a number, is swept once, and no dispersion redraws it.
fn check_key(
    spec: &SweepSpec,
    i: usize,
    p: &SweepParameter,
    loc: &Locator,
) -> Result<(), SpecError> {
    let at = format!("sweep.parameter[{i}].key");
    if p.key == "sweep" || p.key.starts_with("sweep.") {
        return Err(loc.err(&at, "the sweep cannot sweep its own keys"));
    }
    let target = target(loc.doc.as_item(), &p.key).map_err(|why| {
        loc.err(
            &at,
            format!("{why}; a swept key must be a number written in the scene (its nominal value)"),
        )
    })?;
    if spec.parameter[..i].iter().any(|q| q.key == p.key) {
        return Err(loc.err(&at, format!("`{}` is swept twice", p.key)));
    }
    for (key, range) in REDRAWN {
        let dispersed = loc
            .doc
            .get("separation")
            .and_then(|s| s.get("dispersion"))
            .and_then(|d| d.get(range))
            .is_some();
        if p.key == key && dispersed {
            return Err(loc.err(
                &at,
                format!(
                    "`{key}` is redrawn in every Monte Carlo run from separation.dispersion.{range}: \
                     remove that range to sweep it"
                ),
            ));
        }
    }
    if let Target::Integer(_) = target {
        let values = p
            .grid_values()
            .into_iter()
            .chain(p.bounds.into_iter().flatten());
        if let Some(v) = values
            .into_iter()
            .find(|v| v.fract() != 0.0 || v.abs() > 9.0e15)
        {
            return Err(loc.err(
                &at,
                format!(
                    "`{}` is an integer in the scene; the sweep gives it {v}",
                    p.key
                ),
            ));
        }
    }
    Ok(())
}

/// A grid key: `values`, or `from`/`to`/`steps`; returns its number of values.
fn check_grid(p: &SweepParameter, at: &str, loc: &Locator) -> Result<usize, SpecError> {
    if p.bounds.is_some() {
        return Err(loc.err(
            &format!("{at}.bounds"),
            "`bounds` belongs to method = \"lhs\"; a grid takes `values` or `from`/`to`/`steps`",
        ));
    }
    let ramp = [p.from.is_some(), p.to.is_some(), p.steps.is_some()];
    match (&p.values, ramp) {
        (Some(v), [false, false, false]) => {
            if v.is_empty() {
                return Err(loc.err(&format!("{at}.values"), "needs at least one value"));
            }
            Ok(v.len())
        }
        (None, [true, true, true]) => {
            let (a, b, n) = (
                p.from.unwrap_or(0.0),
                p.to.unwrap_or(0.0),
                p.steps.unwrap_or(0),
            );
            if n == 0 || n > MAX_POINTS || (n == 1 && a != b) || (n >= 2 && a == b) {
                return Err(loc.err(
                    &format!("{at}.steps"),
                    format!(
                        "{n} steps from {a} to {b}: give steps ≥ 2 between two different values \
                         (or steps = 1 with from = to), at most {MAX_POINTS}"
                    ),
                ));
            }
            Ok(n)
        }
        _ => Err(loc.err(
            at,
            "a grid key takes either `values = [...]` or all of `from`, `to` and `steps`",
        )),
    }
}

/// A Latin hypercube key: `bounds = [low, high]` only.
fn check_bounds(p: &SweepParameter, at: &str, loc: &Locator) -> Result<usize, SpecError> {
    if p.values.is_some() || p.from.is_some() || p.to.is_some() || p.steps.is_some() {
        return Err(loc.err(
            at,
            "a Latin hypercube key takes `bounds = [low, high]` only (no values, from, to, steps)",
        ));
    }
    match p.bounds {
        Some([a, b]) if a < b => Ok(1),
        Some([a, b]) => Err(loc.err(
            &format!("{at}.bounds"),
            format!("[{a}, {b}]: the low bound must be below the high one"),
        )),
        None => Err(loc.err(at, "a Latin hypercube key needs `bounds = [low, high]`")),
    }
}
