//! The scene's assumptions, the comparison with the paper, and the provenance.

use super::or_dash;
use crate::report::Qualification;
use crate::report::document::{Block, Column, ListItem, Section, Table, Text};

/// The assumptions the scene states, one bullet each.
pub fn assumptions(q: &Qualification) -> Option<Section> {
    if q.assumptions.is_empty() {
        return None;
    }
    let items = q
        .assumptions
        .iter()
        .map(|a| ListItem::new(Text::plain(a.clone())))
        .collect();
    Some(Section::new(
        "Assumptions of the scene",
        vec![Block::List(items)],
    ))
}

/// satqual's numbers beside the paper's measured or simulated ones.
pub fn paper_comparison(q: &Qualification) -> Option<Section> {
    if q.paper_comparison.is_empty() {
        return None;
    }
    let mut t = Table::new(
        ["quantity", "paper", "satqual", "source"]
            .map(Column::left)
            .to_vec(),
    );
    for c in &q.paper_comparison {
        t.row(vec![
            c.quantity.clone(),
            c.paper.clone(),
            c.satqual.clone(),
            c.source.clone(),
        ]);
    }
    Some(Section::new(
        "Comparison with the paper",
        vec![Block::Table(t)],
    ))
}

/// Enough to reproduce the report: the scene and its hash, the version, the solver settings.
pub fn provenance(q: &Qualification) -> Section {
    let p = &q.provenance;
    let items = vec![
        Text::plain("scene: ")
            .code(p.scene_file.clone())
            .and(format!(" (FNV-1a {})", p.scene_hash)),
        Text::plain(format!("satqual {}", p.satqual_version)),
        Text::plain(format!(
            "modal solver: {}",
            p.modal_solver.as_deref().unwrap_or("—")
        )),
        Text::plain(format!(
            "separation tolerance: {}",
            or_dash(p.separation_tolerance.map(|t| format!("{t:e}")))
        )),
    ];
    Section::new(
        "Provenance",
        vec![Block::List(items.into_iter().map(ListItem::new).collect())],
    )
}
