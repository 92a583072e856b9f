//! Pass/fail criteria. Each gate turns an analysis result and a limit from the scene (or a
//! documented default in `spec::qualify::GatesSpec`) into a [`Verdict`]. A failed gate is a
//! result, not an error. Margins are relative, positive when the gate passes:
//! value/limit − 1 for a minimum, 1 − value/limit for a maximum; a margin of safety (MS) is
//! gated against 0 and carried as its own margin.

use serde::Serialize;

/// One criterion's outcome.
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

/// `value` must be at least `limit`.
pub fn at_least(
    name: impl Into<String>,
    value: f64,
    limit: f64,
    source: impl Into<String>,
) -> Verdict {
    let margin = if limit != 0.0 {
        value / limit - 1.0
    } else {
        value
    };
    Verdict {
        name: name.into(),
        value,
        limit,
        margin,
        pass: value >= limit,
        source: source.into(),
    }
}

/// `value` must not exceed `limit`.
pub fn at_most(
    name: impl Into<String>,
    value: f64,
    limit: f64,
    source: impl Into<String>,
) -> Verdict {
    let margin = if limit != 0.0 {
        1.0 - value / limit
    } else {
        -value
    };
    Verdict {
        name: name.into(),
        value,
        limit,
        margin,
        pass: value <= limit,
        source: source.into(),
    }
}

/// A margin of safety, which passes at MS ≥ 0.
pub fn margin_of_safety(name: impl Into<String>, ms: f64, source: impl Into<String>) -> Verdict {
    Verdict {
        name: name.into(),
        value: ms,
        limit: 0.0,
        margin: ms,
        pass: ms >= 0.0,
        source: source.into(),
    }
}

/// `value` must be strictly above `limit` (e.g. a clearance above 0).
pub fn above(
    name: impl Into<String>,
    value: f64,
    limit: f64,
    source: impl Into<String>,
) -> Verdict {
    let margin = value - limit;
    Verdict {
        name: name.into(),
        value,
        limit,
        margin,
        pass: value > limit,
        source: source.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn margins_have_the_sign_of_the_verdict() {
        let v = at_least("f", 12.0, 10.0, "t");
        assert!(v.pass && (v.margin - 0.2).abs() < 1e-12);
        let v = at_least("f", 8.0, 10.0, "t");
        assert!(!v.pass && v.margin < 0.0);
        let v = at_most("rate", 1.0, 2.0, "t");
        assert!(v.pass && (v.margin - 0.5).abs() < 1e-12);
        let v = at_most("rate", 3.0, 2.0, "t");
        assert!(!v.pass && v.margin < 0.0);
        assert!(!margin_of_safety("ms", -0.1, "t").pass);
        assert!(!above("gap", 0.0, 0.0, "t").pass);
    }
}
