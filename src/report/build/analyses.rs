//! Which analyses ran, and why the others were skipped.

use crate::report::Qualification;
use crate::report::document::{Block, ListItem, Section, Text};

pub fn section(q: &Qualification) -> Section {
    let skipped = q
        .skipped
        .iter()
        .map(|sk| {
            ListItem::new(
                Text::plain("skipped ")
                    .strong(sk.analysis.clone())
                    .and(format!(": {}", sk.reason)),
            )
        })
        .collect();
    Section::new(
        "Analyses",
        vec![
            Block::Paragraph(Text::plain(format!("Ran: {}.", q.ran.join(", ")))),
            Block::List(skipped),
        ],
    )
}
