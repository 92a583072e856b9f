//! The finite-element model's mass properties and its modes with their effective masses.

use super::number;
use crate::report::Qualification;
use crate::report::document::{Block, Column, Section, Table, Text};

/// Modes listed in the report; the rest are in `results.json`, where nobody has to scroll.
const LISTED_MODES: usize = 30;

pub fn section(q: &Qualification) -> Option<Section> {
    let r = &q.modal.as_ref()?.result;
    let mut blocks = vec![Block::Paragraph(Text::plain(format!(
        "Total mass {:.3} kg, centre of mass ({:.4}, {:.4}, {:.4}) m, {} DOFs, solver {}.",
        r.total_mass_kg,
        r.center_of_mass_m[0],
        r.center_of_mass_m[1],
        r.center_of_mass_m[2],
        r.dofs,
        r.solver
    )))];
    if let Some(ps) = &r.prestress {
        let on = ps
            .buckling_model
            .as_ref()
            .map_or(String::new(), |m| format!(", taken on {m}"));
        blocks.push(Block::Paragraph(Text::plain(format!(
            "Buckling factor under the preload: {}{on}.",
            ps.buckling_factor.map(number).unwrap_or("none".into())
        ))));
    }
    let mut columns = vec![Column::right("mode"), Column::right("f [Hz]")];
    columns.extend(["x", "y", "z", "rx", "ry", "rz"].map(Column::right));
    let mut t = Table::new(columns);
    for md in r.modes.iter().take(LISTED_MODES) {
        let mut cells = vec![md.index.to_string(), format!("{:.3}", md.frequency_hz)];
        cells.extend(
            md.effective_mass_fraction
                .to_array()
                .iter()
                .map(|f| format!("{f:.3}")),
        );
        t.row(cells);
    }
    blocks.push(Block::Table(t));
    if r.modes.len() > LISTED_MODES {
        blocks.push(Block::Paragraph(Text::plain(format!(
            "({} more modes in results.json)",
            r.modes.len() - LISTED_MODES
        ))));
    }
    Some(Section::new("Model and modes", blocks))
}
