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
    if let Some(s) = short_of_runs(g, &v, &l) {
        return s;
    }
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

/// A Monte Carlo gate that fails on its run count: the value is the bound the runs do show,
/// which may well meet the limit, so the minimum-or-maximum reading of [`bound_sentence`]
/// would misstate it.
fn short_of_runs(g: &Verdict, v: &str, l: &str) -> Option<String> {
    use crate::gates::separation::NOT_DEMONSTRATED;
    if g.pass {
        return None;
    }
    let subject = subject(g);
    let (what, why) = subject.split_once(&format!(" {NOT_DEMONSTRATED}"))?;
    let why = why.trim_start_matches(':').trim();
    let why = why.split(" (value:").next().unwrap_or(why);
    Some(format!(
        "{} is {NOT_DEMONSTRATED} ({why}): the gate fails on the run count; the bound the runs do show is {v}, against a limit of {l}.",
        capitalise(what.trim_end_matches(','))
    ))
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

    /// A bound the runs cannot demonstrate fails on the run count even where the bound they
    /// do show meets its minimum: the sentence says so instead of "exceeds the maximum".
    #[test]
    fn a_bound_short_of_runs_reads_as_such() {
        let name = "Monte Carlo slowest exit speed, lower 99.73% bound at 95% confidence not demonstrated: \
                    59 runs support at most 95.05% at 95% confidence; need 1109 (value: the 95.05% bound) [m/s]";
        let g = Verdict::gate(name, 0.2857, 0.2, 59.0 / 1109.0 - 1.0, false, "t")
            .in_group(Group::Separation)
            .with_unit("m/s");
        assert_eq!(
            sentence(&g),
            "Monte Carlo slowest exit speed, lower 99.73% bound at 95% confidence is not demonstrated \
             (59 runs support at most 95.05% at 95% confidence; need 1109): the gate fails on the run \
             count; the bound the runs do show is 0.2857 m/s, against a limit of 0.2000 m/s."
        );
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
