//! `[stack.fixture]`: the shaker test's fixture between the controlled shaker table (slip table
//! or head expander) and the stack's base. A test calibrates the whole load path it vibrates;
//! describing the fixture apart keeps its compliance out of the joint stiffnesses that a
//! flight scene inherits. Test-only: a flight scene has no fixture, its base is clamped.
//!
//! The model: a rigid adapter plate at the base centre carrying the fixture's mass, held to
//! the driven table by six springs; the carrier-platform points and the guide-bar roots ride on
//! the plate.

use super::Locator;
use super::plausible;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FixtureSpec {
    /// Mass of the adapter plate (what moves with the stack's base), kg.
    pub mass_kg: f64,
    /// Principal inertia of the plate about its centre, x, y, z, kg·m².
    #[serde(default)]
    pub inertia_kg_m2: [f64; 3],
    /// Translation stiffness along x and y between table and plate, N/m.
    pub lateral_stiffness_n_m: f64,
    /// Translation stiffness along z, N/m.
    pub axial_stiffness_n_m: f64,
    /// Rotation stiffness about x and y (rocking of the plate), N·m/rad.
    pub rocking_stiffness_n_m_rad: f64,
    /// Rotation stiffness about z, N·m/rad.
    pub torsional_stiffness_n_m_rad: f64,
    /// Where the numbers come from (report text).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Factors [low, high] on every fixture stiffness that bound the estimate; a flight scene
    /// calibrated on this test shows its prediction at both ends.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plausible_range: Option<[f64; 2]>,
}

impl FixtureSpec {
    /// Table-to-plate spring stiffness in global x, y, z, rx, ry, rz.
    pub fn stiffness(&self) -> [f64; 6] {
        let (l, r) = (self.lateral_stiffness_n_m, self.rocking_stiffness_n_m_rad);
        [
            l,
            l,
            self.axial_stiffness_n_m,
            r,
            r,
            self.torsional_stiffness_n_m_rad,
        ]
    }

    /// The same fixture with every stiffness times `factor`.
    pub fn scaled(&self, factor: f64) -> FixtureSpec {
        FixtureSpec {
            lateral_stiffness_n_m: self.lateral_stiffness_n_m * factor,
            axial_stiffness_n_m: self.axial_stiffness_n_m * factor,
            rocking_stiffness_n_m_rad: self.rocking_stiffness_n_m_rad * factor,
            torsional_stiffness_n_m_rad: self.torsional_stiffness_n_m_rad * factor,
            ..self.clone()
        }
    }

    pub fn validate(&self, loc: &Locator) -> Result<(), SpecError> {
        let k = |s: &str| format!("stack.fixture.{s}");
        plausible::check(loc, &k("mass_kg"), self.mass_kg, plausible::MASS_KG)?;
        for (i, v) in self.inertia_kg_m2.iter().enumerate() {
            let key = format!("stack.fixture.inertia_kg_m2[{i}]");
            plausible::check(loc, &key, *v, plausible::INERTIA_KG_M2)?;
        }
        for (key, v) in [
            ("lateral_stiffness_n_m", self.lateral_stiffness_n_m),
            ("axial_stiffness_n_m", self.axial_stiffness_n_m),
            ("rocking_stiffness_n_m_rad", self.rocking_stiffness_n_m_rad),
            (
                "torsional_stiffness_n_m_rad",
                self.torsional_stiffness_n_m_rad,
            ),
        ] {
            if v.is_nan() || v <= 0.0 {
                let msg = format!("must be positive (a fixture holds the stack), got {v}");
                return Err(loc.err(&k(key), msg));
            }
            plausible::check(loc, &k(key), v, plausible::STIFFNESS)?;
        }
        if let Some([lo, hi]) = self.plausible_range
            && !(lo > 0.0 && lo <= 1.0 && hi >= 1.0 && hi.is_finite())
        {
            let msg =
                format!("must be [low, high] factors with 0 < low ≤ 1 ≤ high, got [{lo}, {hi}]");
            return Err(loc.err(&k("plausible_range"), msg));
        }
        Ok(())
    }
}
