//! Pass/fail criteria. Each gate turns an analysis result and a limit from the scene (or a
//! documented default) into a `Verdict`. A failed gate is a result, not an error.

use serde::Serialize;

/// One criterion's outcome. `margin` is positive when the gate passes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    pub name: String,
    pub value: f64,
    pub limit: f64,
    pub margin: f64,
    pub pass: bool,
    /// Where the criterion comes from (standard, paper section, scene).
    pub source: String,
}
