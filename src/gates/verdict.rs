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

#[cfg(test)]
mod tests {
    use super::*;

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
