//! `[limits]`: the largest work a scene may ask for. Every allocation whose size follows from
//! the input is estimated before it is made and refused past these limits, naming the key that
//! drives it; a scene that really is that large raises the limit here.

use super::Locator;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

/// Beam elements of the model (6 DOFs per node, so about 1.2 million DOFs): far above any real
/// stack model, and below what fits in memory with the solvers' factors.
pub const MODEL_ELEMENTS: usize = 200_000;
/// Frequency points of a sine or random grid. Every point costs a complex solve per output,
/// so a grid this size already takes minutes.
pub const GRID_POINTS: usize = 2_000_000;
/// Monte Carlo runs of a release: each run is a full release simulation.
pub const MONTE_CARLO_RUNS: usize = 100_000;
/// Rows of a release's histories (samples × satellites): each row is held in memory (88 bytes)
/// and written as a CSV line (about 200 bytes). The reference scene writes 36 000.
pub const HISTORY_ROWS: usize = 2_000_000;

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LimitsSpec {
    /// Most beam elements of the (expanded) model.
    #[serde(default = "model_elements")]
    pub model_elements: usize,
    /// Most points of one sine or random frequency grid.
    #[serde(default = "grid_points")]
    pub grid_points: usize,
    /// Most Monte Carlo runs of a release.
    #[serde(default = "monte_carlo_runs")]
    pub monte_carlo_runs: usize,
    /// Most rows of a release's histories (samples × satellites).
    #[serde(default = "history_rows")]
    pub history_rows: usize,
}

fn model_elements() -> usize {
    MODEL_ELEMENTS
}
fn grid_points() -> usize {
    GRID_POINTS
}
fn monte_carlo_runs() -> usize {
    MONTE_CARLO_RUNS
}
fn history_rows() -> usize {
    HISTORY_ROWS
}

impl Default for LimitsSpec {
    fn default() -> Self {
        LimitsSpec {
            model_elements: MODEL_ELEMENTS,
            grid_points: GRID_POINTS,
            monte_carlo_runs: MONTE_CARLO_RUNS,
            history_rows: HISTORY_ROWS,
        }
    }
}

impl LimitsSpec {
    /// A limit of 0 would refuse every scene: it is a typo.
    pub fn validate(&self, loc: &Locator) -> Result<(), SpecError> {
        for (key, v) in [
            ("model_elements", self.model_elements),
            ("grid_points", self.grid_points),
            ("monte_carlo_runs", self.monte_carlo_runs),
            ("history_rows", self.history_rows),
        ] {
            if v == 0 {
                return Err(loc.err(&format!("limits.{key}"), "a limit must be at least 1"));
            }
        }
        Ok(())
    }
}

/// The sentence every refusal ends with: how to raise the limit when the size is meant.
pub fn raise_hint(key: &str) -> String {
    format!("if the size is meant, raise key `limits.{key}` in the scene")
}
