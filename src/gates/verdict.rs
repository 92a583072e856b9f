//! The shape every criterion's outcome takes, and the margin definitions shared by the gate
//! rules and the response analyses' lock-integrity margins. A leaf: it imports nothing of the
//! crate, so an analysis can return verdicts without depending on the gate rules.
//!
//! Margins are relative and positive when the criterion holds: value/limit − 1 for a minimum,
//! 1 − value/limit for a maximum; a margin of safety (MS) is gated against 0 and is its own
//! margin.
//!
//! Every verdict names its family ([`Group`]) and the unit of its value and limit, set with
//! the builders [`Verdict::in_group`] and [`Verdict::with_unit`] so that the constructors
//! below keep their short signatures.
//!
//! Every strength criterion (joint gapping and slip, shear paths, guide-bar yield and ultimate)
//! uses one convention, that of NASA-STD-5001B §4.1: MS = allowable / (FS × applied) − 1. Its
//! verdict shows the design load FS × applied as `value` and the allowable as `limit`, so the
//! margin can be checked from the row: margin = limit/value − 1 ([`strength_margin`],
//! [`design_margin`]).

use serde::Serialize;

/// The family a gate belongs to: the report groups the gates by it and names the governing
/// (smallest-margin) gate of each. Serialised in snake_case (`lock_integrity`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Group {
    /// First lateral and axial frequencies against the launcher's minimums.
    Frequency,
    /// Buckling of the preloaded stack.
    Buckling,
    /// Gapping and slip of the preloaded joints.
    LockIntegrity,
    /// Yield and ultimate strength of the guide bars.
    BarStrength,
    /// The in-orbit release: exit speed, tip-off, clearing the bars, clearance.
    Separation,
    /// Measured logs: random control tolerance, pre/post signatures.
    TestData,
}

impl Group {
    /// Every family, in the order the report lists them.
    pub const ALL: [Group; 6] = [
        Group::Frequency,
        Group::Buckling,
        Group::LockIntegrity,
        Group::BarStrength,
        Group::Separation,
        Group::TestData,
    ];

    /// The family's name as the report prints it.
    pub fn label(self) -> &'static str {
        match self {
            Group::Frequency => "frequency",
            Group::Buckling => "buckling",
            Group::LockIntegrity => "lock integrity",
            Group::BarStrength => "bar strength",
            Group::Separation => "separation",
            Group::TestData => "test data",
        }
    }
}

/// One criterion's outcome: a gate of the qualification, or a margin of safety of a response
/// analysis (which also names its `kind` and `load_case`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// What is checked, e.g. `first axial frequency z (mode 3) [Hz]` or
    /// `gapping interface sat 2/sat 1 column 3`.
    pub name: String,
    /// The gate's family; `null` in the JSON only for a verdict no rule assigned (a test
    /// checks that every gate of the reference scenes has one).
    pub group: Option<Group>,
    /// A response margin's family (`gapping`, `slip`, `bar yield`, `bar ultimate`); empty for a
    /// gate, whose name already says it (and then left out of the JSON).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub kind: String,
    /// A response margin's load case (`sine x`, `random z` ...); empty for a gate.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub load_case: String,
    pub value: f64,
    pub limit: f64,
    /// The unit of `value` and `limit` (SI, or `deg/s` and `%` where the gate is stated in
    /// them); empty only for a dimensionless quantity such as a buckling factor.
    pub unit: String,
    pub margin: f64,
    pub pass: bool,
    /// Where the criterion comes from (standard, paper section, scene).
    pub source: String,
}

impl Verdict {
    /// A gate verdict (no kind, no load case) with its margin given by the caller.
    pub fn gate(
        name: impl Into<String>,
        value: f64,
        limit: f64,
        margin: f64,
        pass: bool,
        source: impl Into<String>,
    ) -> Verdict {
        Verdict {
            name: name.into(),
            group: None,
            kind: String::new(),
            load_case: String::new(),
            value,
            limit,
            unit: String::new(),
            margin,
            pass,
            source: source.into(),
        }
    }

    /// The same verdict in family `group`.
    /// Marks one item of a family of like gates (a kind under a load case), which the report
    /// folds into one row, the worst.
    pub fn folded_as(mut self, kind: &str, load_case: &str) -> Verdict {
        self.kind = kind.to_string();
        self.load_case = load_case.to_string();
        self
    }

    pub fn in_group(mut self, group: Group) -> Verdict {
        self.group = Some(group);
        self
    }

    /// The same verdict with its value and limit in `unit` (`""` for dimensionless).
    pub fn with_unit(mut self, unit: &str) -> Verdict {
        self.unit = unit.to_string();
        self
    }
}

/// `value` must be at least `limit`; margin value/limit − 1 (the value itself for a 0 limit).
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
    Verdict::gate(name, value, limit, margin, value >= limit, source)
}

/// `value` must not exceed `limit`; margin 1 − value/limit (−value for a 0 limit).
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
    Verdict::gate(name, value, limit, margin, value <= limit, source)
}

/// A margin of safety, which passes at MS ≥ 0.
pub fn margin_of_safety(name: impl Into<String>, ms: f64, source: impl Into<String>) -> Verdict {
    Verdict::gate(name, ms, 0.0, ms, ms >= 0.0, source)
}

/// `value` must be strictly above `limit` (e.g. a clearance above 0); margin value − limit,
/// in the value's unit, because a relative margin against a 0 limit has no meaning.
pub fn above(
    name: impl Into<String>,
    value: f64,
    limit: f64,
    source: impl Into<String>,
) -> Verdict {
    Verdict::gate(name, value, limit, value - limit, value > limit, source)
}

/// Strength margins above this are reported as this value: the path carries no meaningful
/// load, and an unbounded ratio would only hide the rows that matter.
pub const MARGIN_CAP: f64 = 999.0;

/// A strength margin of safety, NASA-STD-5001B §4.1: MS = allowable / (FS × applied) − 1.
/// `value` is the design load FS × applied, `limit` the allowable (same unit); passes at
/// MS ≥ 0. A nil applied load gives [`MARGIN_CAP`].
pub fn strength_margin(
    name: impl Into<String>,
    applied: f64,
    allowable: f64,
    fs: f64,
    source: impl Into<String>,
) -> Verdict {
    design_margin(name, fs * applied, allowable, source)
}

/// A strength margin of safety from a design load already factored, MS = allowable / design
/// − 1: for a load that is not one applied load times one factor, such as the von Mises stress
/// of a preloaded bar (NASA-STD-5020B §4.3.1 form: the preload at its maximum, unfactored, plus
/// FS × the external load).
pub fn design_margin(
    name: impl Into<String>,
    design: f64,
    allowable: f64,
    source: impl Into<String>,
) -> Verdict {
    let ms = if design > 1e-12 * allowable.abs().max(1e-300) {
        (allowable / design - 1.0).min(MARGIN_CAP)
    } else {
        MARGIN_CAP
    };
    Verdict::gate(name, design, allowable, ms, ms >= 0.0, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed joint: 45 kN / 4 = 11 250 N nominal preload, −10 % uncertainty and −5 %
    /// relaxation: P_min = 11 250 · 0.9 · 0.95 = 9 618.75 N. External tension 5 000 N with
    /// FF 1.15 and FS_sep 1.2: design 1.15 · 1.2 · 5 000 = 6 900 N, MS = 9 618.75 / 6 900 − 1
    /// = 0.394022 (NASA-STD-5001B §4.1 convention; exact to rounding).
    #[test]
    fn a_strength_margin_divides_the_allowable_by_the_factored_load() {
        let pmin = 11_250.0 * 0.9 * 0.95;
        let v = strength_margin("gapping", 5_000.0, pmin, 1.15 * 1.2, "t");
        assert!((v.value - 6_900.0).abs() < 1e-9);
        assert_eq!(v.limit, pmin);
        assert!((v.margin - (9_618.75 / 6_900.0 - 1.0)).abs() < 1e-12);
        assert!((v.margin - 0.394022).abs() < 1e-6);
        assert!(v.pass);
        // The same joint at 7 000 N: design 9 660 N > 9 618.75 N, MS = −0.00427.
        let v = strength_margin("gapping", 7_000.0, pmin, 1.15 * 1.2, "t");
        assert!(!v.pass && (v.margin - (9_618.75 / 9_660.0 - 1.0)).abs() < 1e-12);
        // No load on the path: the cap, a pass.
        let v = strength_margin("slip", 0.0, 1_000.0, 1.0, "t");
        assert!(v.pass && v.margin == MARGIN_CAP);
    }

    /// Hand-computed: 12/10 − 1 = 0.2; 1 − 1/2 = 0.5; 0.03 − 0 = 0.03.
    #[test]
    fn margins_follow_their_definitions_and_carry_the_verdicts_sign() {
        let v = at_least("f", 12.0, 10.0, "t");
        assert!(v.pass && (v.margin - 0.2).abs() < 1e-12);
        let v = at_least("f", 8.0, 10.0, "t");
        assert!(!v.pass && (v.margin + 0.2).abs() < 1e-12);
        let v = at_most("rate", 1.0, 2.0, "t");
        assert!(v.pass && (v.margin - 0.5).abs() < 1e-12);
        let v = at_most("rate", 3.0, 2.0, "t");
        assert!(!v.pass && (v.margin + 0.5).abs() < 1e-12);
        assert!(!margin_of_safety("ms", -0.1, "t").pass);
        assert!(!above("gap", 0.0, 0.0, "t").pass);
        assert!((above("gap", 0.03, 0.0, "t").margin - 0.03).abs() < 1e-15);
    }

    #[test]
    fn a_zero_limit_gives_an_absolute_margin() {
        assert_eq!(at_least("x", 0.5, 0.0, "t").margin, 0.5);
        assert_eq!(at_most("x", 0.5, 0.0, "t").margin, -0.5);
    }

    #[test]
    fn a_gate_leaves_kind_and_load_case_out_of_the_json() {
        let gate = at_least("f", 12.0, 10.0, "t")
            .in_group(Group::Frequency)
            .with_unit("Hz");
        let json = serde_json::to_string(&gate).unwrap();
        assert_eq!(
            json,
            r#"{"name":"f","group":"frequency","value":12.0,"limit":10.0,"unit":"Hz","margin":0.19999999999999996,"pass":true,"source":"t"}"#
        );
    }
}
