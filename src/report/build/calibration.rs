//! The values the scene took from an updated test model, and how far the flight prediction
//! moves across the test fixture's plausible range.

use super::number;
use crate::report::Qualification;
use crate::report::document::{Block, Column, Section, Table, Text};

/// The section, when the scene has a `[calibration]`.
pub fn section(q: &Qualification) -> Option<Section> {
    let c = q.calibration.as_ref()?;
    let mut blocks = vec![Block::Paragraph(
        Text::plain("Values taken from the test model ")
            .code(c.test_scene.clone())
            .and(", updated there to the measured modes (satqual update):"),
    )];
    let mut values = Table::new(vec![
        Column::left("parameter"),
        Column::right("this scene"),
        Column::right("test model"),
    ]);
    for p in &c.parameters {
        values.row(vec![p.path.clone(), number(p.flight), number(p.test)]);
    }
    blocks.push(Block::Table(values));
    for w in &c.warnings {
        blocks.push(Block::Paragraph(Text::plain(format!("Warning: {w}"))));
    }
    if c.cases.len() > 1 {
        blocks.push(Block::Paragraph(Text::plain(format!(
            "First modes of this scene with the test model recalibrated at both ends of its fixture estimate's plausible range (fixture: {}):",
            c.fixture_source.as_deref().unwrap_or("no source given")
        ))));
        blocks.push(Block::Table(cases(q)));
    }
    Some(Section::new("Calibration from the test", blocks))
}

fn cases(q: &Qualification) -> Table {
    let c = q.calibration.as_ref().expect("called with a calibration");
    let mut columns = vec![Column::left("fixture stiffness")];
    columns.extend(c.parameters.iter().map(|p| Column::right(&p.path)));
    columns.extend(["first x [Hz]", "first y [Hz]", "first z [Hz]"].map(Column::right));
    let mut t = Table::new(columns);
    for case in &c.cases {
        let label = if case.fixture_factor == 1.0 {
            "× 1 (the estimate, as this scene)".to_string()
        } else {
            format!("× {}", number(case.fixture_factor))
        };
        let mut row = vec![label];
        row.extend(case.values.iter().map(|&v| number(v)));
        row.extend(case.first_hz.map(|f| f.map_or("—".into(), number)));
        t.row(row);
    }
    t
}
