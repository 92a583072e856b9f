//! The first screen of the report (the verdict, the governing gate of each family with its
//! cause, what was skipped) and the Gates section: one table per family, the items of one
//! kind and load case (a joint's gapping at every interface under random z, say) folded to
//! their worst, with every row in a collapsible table below.

use super::{cause, quantity};
use crate::gates::summary::{self, Family};
use crate::gates::{Group, Verdict};
use crate::report::Qualification;
use crate::report::document::{Block, Column, ListItem, Row, Section, Table, Text, VerdictLine};

/// The verdict, the governing gates and the skipped analyses, before the first section.
pub fn preamble(q: &Qualification) -> Vec<Block> {
    let families = summary::families(&q.gates);
    let mut governing = Table::new(vec![
        Column::left("family"),
        Column::left("gates"),
        Column::left("governing gate"),
        Column::right("value"),
        Column::right("limit"),
        Column::right("margin"),
        Column::left("cause"),
    ]);
    for f in &families {
        governing.rows.push(governing_row(f));
    }
    let skipped: Vec<ListItem> = q
        .skipped
        .iter()
        .map(|s| {
            ListItem::new(
                Text::plain("skipped ")
                    .strong(s.analysis.clone())
                    .and(format!(": {}", s.reason)),
            )
        })
        .collect();
    let warnings: Vec<ListItem> = q
        .warnings()
        .into_iter()
        .map(|(from, w)| {
            ListItem::new(
                Text::plain("")
                    .strong("warning")
                    .and(format!(" ({from}): {w}")),
            )
        })
        .collect();
    vec![
        Block::Verdict(VerdictLine {
            pass: q.pass,
            gates: q.gates.len(),
            failed: q.gates.iter().filter(|g| !g.pass).count(),
        }),
        Block::Paragraph(
            Text::plain("")
                .strong("Governing gates")
                .and(" (the failed or smallest-margin gate of each family):"),
        ),
        Block::Table(governing),
        Block::List(skipped),
        Block::List(warnings),
    ]
}

fn family_label(group: Option<Group>) -> &'static str {
    group.map_or("other", Group::label)
}

fn governing_row(f: &Family) -> Row {
    let g = f.governing;
    Row {
        cells: vec![
            family_label(f.group).into(),
            if f.failed == 0 {
                format!("pass ({})", f.total)
            } else {
                format!("FAIL ({} of {})", f.failed, f.total)
            },
            g.name.clone(),
            quantity(g.value, &g.unit),
            quantity(g.limit, &g.unit),
            summary::margin_text(g),
            cause::sentence(g),
        ],
        failed: !g.pass,
    }
}

fn columns() -> Vec<Column> {
    vec![
        Column::left("gate"),
        Column::right("value"),
        Column::right("limit"),
        Column::right("margin"),
        Column::left("verdict"),
        Column::left("source"),
    ]
}

fn gate_row(g: &Verdict, name: String, verdict: String) -> Row {
    Row {
        cells: vec![
            name,
            quantity(g.value, &g.unit),
            quantity(g.limit, &g.unit),
            summary::margin_text(g),
            verdict,
            g.source.clone(),
        ],
        failed: !g.pass,
    }
}

/// The gates family by family; see the module comment.
pub fn section(q: &Qualification) -> Section {
    let mut blocks = Vec::new();
    for f in summary::families(&q.gates) {
        let members: Vec<&Verdict> = q.gates.iter().filter(|g| g.group == f.group).collect();
        blocks.push(Block::Paragraph(
            Text::plain("").strong(family_label(f.group)).and(format!(
                ": {} gate{}, {} failed",
                f.total,
                if f.total == 1 { "" } else { "s" },
                f.failed
            )),
        ));
        let mut t = Table::new(columns());
        let mut runs = fold_by_kind_and_case(&members);
        runs.sort_by(|a, b| summary::more_critical(worst(a), worst(b)));
        for run in runs {
            t.rows.push(folded_row(&run));
        }
        let folded = t.rows.len() < members.len();
        blocks.push(Block::Table(t));
        if folded {
            let mut all = Table::new(columns());
            for g in &members {
                all.rows
                    .push(gate_row(g, g.name.clone(), pass_word(g).into()));
            }
            let what = format!("all {} {} gates", members.len(), family_label(f.group));
            blocks.push(Block::Details(what, all));
        }
    }
    Section::new("Gates", blocks)
}

fn pass_word(g: &Verdict) -> &'static str {
    if g.pass { "pass" } else { "FAIL" }
}

/// The gates in runs sharing a kind and load case (in first-seen order); a gate without a
/// kind is a run of its own.
fn fold_by_kind_and_case<'a>(gates: &[&'a Verdict]) -> Vec<Vec<&'a Verdict>> {
    let mut runs: Vec<Vec<&Verdict>> = Vec::new();
    for g in gates {
        let same = |r: &&mut Vec<&Verdict>| {
            !g.kind.is_empty() && r[0].kind == g.kind && r[0].load_case == g.load_case
        };
        match runs.iter_mut().find(|r| same(r)) {
            Some(r) => r.push(g),
            None => runs.push(vec![g]),
        }
    }
    runs
}

fn worst<'a>(run: &[&'a Verdict]) -> &'a Verdict {
    run.iter()
        .copied()
        .min_by(|a, b| summary::more_critical(a, b))
        .expect("a run is never empty")
}

/// One gate as it is, or the worst of several with how many failed.
fn folded_row(run: &[&Verdict]) -> Row {
    let worst = worst(run);
    if run.len() == 1 {
        return gate_row(worst, worst.name.clone(), pass_word(worst).into());
    }
    let failed = run.iter().filter(|g| !g.pass).count();
    // The item alone: the gate name without the kind and load case this row already states.
    let item = worst
        .name
        .trim_start_matches(&format!("{}: ", worst.kind))
        .trim_end_matches(&format!(" ({})", worst.load_case));
    let name = format!(
        "{} ({}), worst of {}: {item}",
        worst.kind,
        worst.load_case,
        run.len(),
    );
    let verdict = if failed == 0 {
        "pass".to_string()
    } else {
        format!("FAIL ({failed} of {})", run.len())
    };
    gate_row(worst, name, verdict)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn margin(name: &str, case: &str, m: f64) -> Verdict {
        Verdict {
            kind: "slip".into(),
            load_case: case.into(),
            ..Verdict::gate(name, 1.0, 1.0 + m, m, m > 0.0, "s")
                .in_group(Group::LockIntegrity)
                .with_unit("N")
        }
    }

    /// Three slip items under two load cases fold into two rows, each the worst of its case.
    #[test]
    fn items_of_one_kind_and_load_case_fold_to_their_worst() {
        let gates = [
            margin("a", "sine x", 0.5),
            margin("b", "sine x", -0.2),
            margin("a", "random z", 0.1),
        ];
        let refs: Vec<&Verdict> = gates.iter().collect();
        let runs = fold_by_kind_and_case(&refs);
        assert_eq!(runs.len(), 2);
        let row = folded_row(&runs[0]);
        assert_eq!(row.cells[0], "slip (sine x), worst of 2: b");
        assert_eq!(row.cells[4], "FAIL (1 of 2)");
        assert!(row.failed);
        assert_eq!(folded_row(&runs[1]).cells[0], "a");
    }

    /// The nominal release's per-satellite gates fold like joints: six exit speeds make one
    /// row, the slowest satellite, with how many failed.
    #[test]
    fn per_satellite_separation_gates_fold_to_the_worst_satellite() {
        use crate::gates::separation::NOMINAL_RELEASE;
        let gates: Vec<Verdict> = [0.33, 0.31, 0.04, 0.32, 0.30, 0.05]
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                Verdict::gate(
                    format!("satellite {} exit speed [m/s]", i + 1),
                    v,
                    0.1,
                    v / 0.1 - 1.0,
                    v >= 0.1,
                    "s",
                )
                .in_group(Group::Separation)
                .folded_as("exit speed", NOMINAL_RELEASE)
            })
            .collect();
        let refs: Vec<&Verdict> = gates.iter().collect();
        let runs = fold_by_kind_and_case(&refs);
        assert_eq!(runs.len(), 1);
        let row = folded_row(&runs[0]);
        assert_eq!(
            row.cells[0],
            "exit speed (nominal release), worst of 6: satellite 3 exit speed [m/s]"
        );
        assert_eq!(row.cells[4], "FAIL (2 of 6)");
    }
}
