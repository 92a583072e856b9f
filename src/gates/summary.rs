//! The governing gate of each family: the one an engineer reads first. A failed gate governs
//! over any passed one; among equals the smallest margin governs (the first listed on a tie).

use super::verdict::{Group, Verdict};
use std::cmp::Ordering;

/// One family's count of gates and its governing gate.
#[derive(Debug, Clone, Copy)]
pub struct Family<'a> {
    /// `None` gathers verdicts no rule assigned to a family.
    pub group: Option<Group>,
    pub governing: &'a Verdict,
    pub failed: usize,
    pub total: usize,
}

/// Orders `a` before `b` when it is the more critical: failed first, then smaller margin.
pub fn more_critical(a: &Verdict, b: &Verdict) -> Ordering {
    a.pass.cmp(&b.pass).then(margin_order(a.margin, b.margin))
}

/// Relative difference under which two margins tie.
const MARGIN_TIE: f64 = 1e-9;

/// Margins equal to within round-off tie, so that the first listed governs: symmetric items
/// (the four columns of a joint, the four bars) do not take turns with the solver's last
/// digits.
fn margin_order(a: f64, b: f64) -> Ordering {
    if (a - b).abs() <= MARGIN_TIE * a.abs().max(b.abs()).max(1.0) {
        Ordering::Equal
    } else {
        a.total_cmp(&b)
    }
}

/// The margin as a reader wants it: a percentage when it is relative, in the value's unit
/// when it is absolute (a zero limit, where the margin is value − limit; see `verdict`).
pub fn margin_text(g: &Verdict) -> String {
    if !g.margin.is_finite() {
        "–".into()
    } else if g.limit == 0.0 && !g.unit.is_empty() && g.unit != "%" {
        format!("{:+.4} {}", g.margin + 0.0, g.unit)
    } else {
        // + 0.0 turns a −0 margin (nothing outside a band) into +0.
        format!("{:+.1}%", g.margin * 100.0 + 0.0)
    }
}

/// Every family that has gates, in the order of [`Group::ALL`] (unassigned verdicts last).
pub fn families(gates: &[Verdict]) -> Vec<Family<'_>> {
    let groups = Group::ALL.iter().map(|g| Some(*g)).chain([None]);
    groups
        .filter_map(|group| {
            let members: Vec<&Verdict> = gates.iter().filter(|g| g.group == group).collect();
            let governing = members.iter().copied().min_by(|a, b| more_critical(a, b))?;
            Some(Family {
                group,
                governing,
                failed: members.iter().filter(|g| !g.pass).count(),
                total: members.len(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gates::{at_least, at_most};

    /// Two symmetric items whose margins differ in the 13th digit tie: the first listed
    /// governs whichever carries the smaller rounding; a real difference still decides.
    #[test]
    fn margins_equal_to_round_off_tie_and_the_first_governs() {
        let gate =
            |name: &str, value: f64| at_most(name, value, 10.0, "t").in_group(Group::Frequency);
        for eps in [1e-13, -1e-13] {
            let gates = vec![gate("column 1", 20.0), gate("column 2", 20.0 * (1.0 + eps))];
            assert_eq!(families(&gates)[0].governing.name, "column 1", "{eps}");
        }
        let gates = vec![gate("column 1", 20.0), gate("column 2", 20.2)];
        assert_eq!(families(&gates)[0].governing.name, "column 2");
    }

    /// A failed gate governs its family even when a passed one has a smaller margin (a
    /// failing zero-limit gate can carry margin −0.001 while a passing one carries −1 never,
    /// but margins of different definitions need not compare); families keep Group::ALL order.
    #[test]
    fn the_failed_smallest_margin_gate_governs_each_family() {
        let gates = vec![
            at_most("rate", 1.0, 2.0, "t").in_group(Group::Separation),
            at_least("f x", 12.0, 10.0, "t").in_group(Group::Frequency),
            at_least("f y", 11.0, 10.0, "t").in_group(Group::Frequency),
            at_least("speed", 0.1, 0.2, "t").in_group(Group::Separation),
        ];
        let f = families(&gates);
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].group, Some(Group::Frequency));
        assert_eq!(
            (f[0].governing.name.as_str(), f[0].failed, f[0].total),
            ("f y", 0, 2)
        );
        assert_eq!(f[1].group, Some(Group::Separation));
        assert_eq!((f[1].governing.name.as_str(), f[1].failed), ("speed", 1));
    }

    /// 12/10 − 1 = +20.0%; a clearance above a 0 m limit has the absolute margin 0.5872 m.
    #[test]
    fn relative_margins_print_as_percent_and_absolute_ones_in_their_unit() {
        let f = at_least("f", 12.0, 10.0, "t").with_unit("Hz");
        assert_eq!(margin_text(&f), "+20.0%");
        let c = crate::gates::above("gap", 0.5872, 0.0, "t").with_unit("m");
        assert_eq!(margin_text(&c), "+0.5872 m");
        let none_outside = crate::gates::Verdict::gate("band", 0.0, 0.0, -0.0, true, "t");
        assert_eq!(margin_text(&none_outside), "+0.0%");
    }
}
