//! The cause of a governing gate in one sentence, written from its family, kind, value and
//! limit: what the numbers mean physically, not only that a margin is negative.

use super::quantity;
use crate::gates::{Group, Verdict};

/// One sentence saying why `g` passes or fails.
pub fn sentence(g: &Verdict) -> String {
    if !g.value.is_finite() {
        return format!(
            "{} could not be evaluated: {}.",
            subject(g),
            g.source.trim_end_matches('.')
        );
    }
    let (v, l) = (quantity(g.value, &g.unit), quantity(g.limit, &g.unit));
    let case = if g.load_case.is_empty() {
        String::new()
    } else {
        format!("under {}, ", g.load_case)
    };
    match (g.group, g.kind.as_str()) {
        (Some(Group::LockIntegrity), "gapping") => capitalise(&format!(
            "{case}the factored tension {v} {} the {l} minimum preload: the joint {}.",
            if g.pass { "stays below" } else { "exceeds" },
            if g.pass { "stays closed" } else { "opens" }
        )),
        (Some(Group::LockIntegrity), "slip") => capitalise(&format!(
            "{case}the factored shear {v} {} the {l} friction capacity: the joint {}.",
            if g.pass { "stays below" } else { "exceeds" },
            if g.pass { "holds by friction" } else { "slips" }
        )),
        (Some(Group::BarStrength), kind) => capitalise(&format!(
            "{case}the factored von Mises stress {v} {} the {l} {} allowable of the guide bar.",
            if g.pass { "stays below" } else { "exceeds" },
            kind.trim_start_matches("bar ")
        )),
        (Some(Group::Buckling), _) => format!(
            "The stack buckles at {} times the preload; at least {} is required.",
            super::number(g.value),
            super::number(g.limit)
        ),
        _ => bound_sentence(g, &v, &l),
    }
}

/// A minimum or maximum criterion in words. The margin's sign follows value − limit for a
/// minimum and limit − value for a maximum, which tells which one `g` is (at the limit
/// itself it cannot tell, and says only that).
fn bound_sentence(g: &Verdict, v: &str, l: &str) -> String {
    if g.value == g.limit {
        let verdict = if g.pass { "passes" } else { "fails" };
        return format!(
            "{} is {v}, at its limit, and {verdict}.",
            capitalise(&subject(g))
        );
    }
    let minimum = (g.value >= g.limit) == (g.margin >= 0.0);
    let relation = match (minimum, g.pass) {
        (true, true) => "meets the minimum of",
        (true, false) => "falls short of the minimum of",
        (false, true) => "stays within the maximum of",
        (false, false) => "exceeds the maximum of",
    };
    format!("{} is {v}, which {relation} {l}.", capitalise(&subject(g)))
}

/// The gate's name without its trailing `[unit]`.
fn subject(g: &Verdict) -> String {
    match g.name.rfind(" [") {
        Some(i) if g.name.ends_with(']') => g.name[..i].to_string(),
        _ => g.name.clone(),
    }
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gates::{at_least, at_most};

    #[test]
    fn a_failed_minimum_and_a_passed_maximum_read_as_such() {
        let f = at_least("first lateral frequency y (mode 2) [Hz]", 7.4711, 10.0, "t")
            .in_group(Group::Frequency)
            .with_unit("Hz");
        assert_eq!(
            sentence(&f),
            "First lateral frequency y (mode 2) is 7.4711 Hz, which falls short of the minimum of 10.0000 Hz."
        );
        let r = at_most("satellite 1 tip-off rate [deg/s]", 0.5, 2.5, "t")
            .in_group(Group::Separation)
            .with_unit("deg/s");
        assert!(sentence(&r).contains("stays within the maximum of 2.5000 deg/s"));
    }

    #[test]
    fn a_gapping_margin_names_the_load_case_and_the_physical_outcome() {
        let g = Verdict {
            kind: "gapping".into(),
            load_case: "random z".into(),
            ..Verdict::gate("gapping: i", 20489.0, 9618.75, -0.53, false, "t")
                .in_group(Group::LockIntegrity)
                .with_unit("N")
        };
        assert_eq!(
            sentence(&g),
            "Under random z, the factored tension 20489.0000 N exceeds the 9618.7500 N minimum preload: the joint opens."
        );
    }
}
