//! The verdict at the top of the report and the table of every gate.

use super::number;
use crate::report::Qualification;
use crate::report::document::{Block, Column, ListItem, Row, Section, Table, Text, VerdictLine};

/// The verdict and the names of the failed gates, before the first section.
pub fn preamble(q: &Qualification) -> Vec<Block> {
    let failed: Vec<ListItem> = q
        .gates
        .iter()
        .filter(|g| !g.pass)
        .map(|g| ListItem::new(Text::plain(format!("failed: {}", g.name))))
        .collect();
    vec![
        Block::Verdict(VerdictLine {
            pass: q.pass,
            gates: q.gates.len(),
            failed: failed.len(),
        }),
        Block::List(failed),
    ]
}

/// Every gate with its value, limit, margin and source; failed rows are marked.
pub fn section(q: &Qualification) -> Section {
    let mut t = Table::new(vec![
        Column::left("gate"),
        Column::right("value"),
        Column::right("limit"),
        Column::right("margin"),
        Column::left("verdict"),
        Column::left("source"),
    ]);
    for g in &q.gates {
        t.rows.push(Row {
            cells: vec![
                g.name.clone(),
                number(g.value),
                number(g.limit),
                format!("{:+.1}%", g.margin * 100.0),
                if g.pass { "pass" } else { "FAIL" }.into(),
                g.source.clone(),
            ],
            failed: !g.pass,
        });
    }
    Section::new("Gates", vec![Block::Table(t)])
}
