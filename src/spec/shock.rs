//! `[shock]`: the shock specification that `[[test_log]] kind = "shock"` logs are checked
//! against. An SRS specification is a set of breakpoints in g against Hz, with a tolerance
//! band around it and a share of points allowed outside (NASA-STD-7003A, MIL-STD-810H
//! Method 516).

use super::Locator;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ShockSpec {
    /// Breakpoints `[f_hz, g]` of the maximax absolute-acceleration SRS, interpolated log-log.
    /// The log's SRS is computed over their frequency range.
    pub srs_g: Vec<[f64; 2]>,
    /// Quality factor of the SRS oscillators. Default 10 (NASA-STD-7003A).
    #[serde(default = "default_q")]
    pub q: f64,
    /// Natural frequencies per octave. Default 12 (1/12 octave; the standards ask 1/6 or finer).
    #[serde(default = "default_per_octave")]
    pub per_octave: u32,
    /// Tolerance above the specification, dB. Default 6 (MIL-STD-810H 516, NASA-STD-7003A).
    #[serde(default = "default_db")]
    pub upper_db: f64,
    /// Tolerance below the specification, dB. Default 6.
    #[serde(default = "default_db")]
    pub lower_db: f64,
    /// Share of SRS points allowed beyond each limit, in [0, 1). Default 0.
    #[serde(default)]
    pub allowed_fraction: f64,
}

fn default_q() -> f64 {
    10.0
}

fn default_per_octave() -> u32 {
    12
}

fn default_db() -> f64 {
    6.0
}

impl ShockSpec {
    /// The breakpoints as (f_hz, g) pairs.
    pub fn breakpoints(&self) -> Vec<(f64, f64)> {
        self.srs_g.iter().map(|p| (p[0], p[1])).collect()
    }
}

pub fn validate(s: &ShockSpec, loc: &Locator) -> Result<(), SpecError> {
    if s.srs_g.len() < 2 {
        return Err(loc.err("shock.srs_g", "needs at least two [f_hz, g] breakpoints"));
    }
    for (i, p) in s.srs_g.iter().enumerate() {
        if !(super::plausible::FREQUENCY_HZ.admits(p[0])
            && super::plausible::ACCELERATION_G.admits(p[1]))
        {
            let msg = format!(
                "breakpoint {}: [{}, {}] is outside the plausible ranges {} and {} (see docs/robustness.md)",
                i + 1,
                p[0],
                p[1],
                super::plausible::FREQUENCY_HZ.describe(),
                super::plausible::ACCELERATION_G.describe()
            );
            return Err(loc.err("shock.srs_g", msg));
        }
        if i > 0 && p[0] <= s.srs_g[i - 1][0] {
            let msg = format!("breakpoint {}: frequencies must increase", i + 1);
            return Err(loc.err("shock.srs_g", msg));
        }
    }
    if !(s.q.is_finite() && s.q > 0.5) {
        return Err(loc.err(
            "shock.q",
            format!("must be finite and above 0.5, got {}", s.q),
        ));
    }
    if !(1..=96).contains(&s.per_octave) {
        let msg = format!("must be 1 to 96, got {}", s.per_octave);
        return Err(loc.err("shock.per_octave", msg));
    }
    for (key, v) in [("upper_db", s.upper_db), ("lower_db", s.lower_db)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(loc.err(
                &format!("shock.{key}"),
                format!("must be finite and ≥ 0, got {v}"),
            ));
        }
    }
    if !(0.0..1.0).contains(&s.allowed_fraction) {
        let msg = format!("must be in [0, 1), got {}", s.allowed_fraction);
        return Err(loc.err("shock.allowed_fraction", msg));
    }
    Ok(())
}
