//! Builds the report [`Document`] from the results of a qualification: one file per section,
//! assembled here in reading order.

mod analyses;
mod gates;
mod joint_loads;
mod modes;
mod notes;
mod response;
mod separation;
mod test_data;

use super::Qualification;
use super::document::{Block, Document, Figure, Section};

/// The report of `q`, with `figures` (already drawn) in its Plots section.
pub fn document(q: &Qualification, figures: Vec<Figure>) -> Document {
    let mut sections = vec![gates::section(q), analyses::section(q)];
    sections.extend(modes::section(q));
    sections.extend(response::sections(q));
    sections.extend(notes::assumptions(q));
    sections.extend(separation::section(q));
    sections.extend(test_data::section(q));
    sections.extend(notes::paper_comparison(q));
    if !figures.is_empty() {
        sections.push(Section::new("Plots", vec![Block::Figures(figures)]));
    }
    sections.push(notes::provenance(q));
    Document {
        title: format!(
            "Qualification report: {}",
            q.title.as_deref().unwrap_or(&q.scene)
        ),
        preamble: gates::preamble(q),
        sections,
    }
}

/// A number for a table: four decimals, or scientific notation when very large or small;
/// a dash for a non-finite value.
fn number(v: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.4e}")
    } else {
        format!("{v:.4}")
    }
}

/// An optional value, or a dash when there is none.
fn or_dash(v: Option<String>) -> String {
    v.unwrap_or_else(|| "—".into())
}
