//! `[calibration]`: a flight scene's record of the values it took from a test model updated to
//! measurements (`satqual update` on the test scene). `qualify` checks the values still agree
//! with the test scene, and, when the test scene's fixture carries a plausible range, shows how
//! far the flight prediction moves across it.

use super::Locator;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CalibrationSpec {
    /// The test scene, relative to this scene's directory.
    pub test_scene: String,
    /// Dotted TOML paths of the numbers taken from the test scene (`[update]` parameters there).
    pub parameters: Vec<String>,
}

/// Every parameter names a number of this scene.
pub fn validate(spec: &CalibrationSpec, loc: &Locator) -> Result<(), SpecError> {
    if spec.parameters.is_empty() {
        let msg = "name at least one value taken from the test scene";
        return Err(loc.err("calibration.parameters", msg));
    }
    for path in &spec.parameters {
        let key = super::update::normalize_path(path);
        super::sweep::target(loc.doc_item(), &key)
            .map_err(|e| loc.err("calibration.parameters", e))?;
    }
    Ok(())
}
