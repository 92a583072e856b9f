//! The report of a parameter sweep: `sweep.json` (every number), `sweep.csv` (one row per
//! point), `report.md` and `report.html` (the design, the table with the failing points marked,
//! the plots) and `plots/*.svg`: each output percentile against each swept key. No timing and no
//! shard count: a merged sweep writes the same bytes as one machine.

mod outputs;
mod plots;

use super::document::{Block, Column, Document, Row, Section, Table, Text};
use super::figures::Files;
use super::{render_html, render_md};
use crate::error::Error;
use crate::results::SweepTable;
use crate::spec::sweep::SweepMethod;
use outputs::OUTPUTS;
use std::path::{Path, PathBuf};

/// Every file of the sweep report, in memory.
pub fn render(t: &SweepTable) -> Result<Files, Error> {
    crate::output_check::check_json(t, "sweep.json")?;
    let json =
        serde_json::to_string_pretty(t).map_err(|e| Error::Other(format!("sweep.json: {e}")))?;
    let figs = plots::figures(t)?;
    let doc = document(t, figs.clone());
    let mut files: Files = vec![
        ("sweep.json".into(), (json + "\n").into_bytes()),
        ("sweep.csv".into(), outputs::csv(t).into_bytes()),
        ("report.md".into(), render_md::render(&doc).into_bytes()),
        ("report.html".into(), render_html::render(&doc).into_bytes()),
    ];
    files.extend(figs.iter().map(|f| (f.file(), f.svg.clone().into_bytes())));
    Ok(files)
}

/// Writes the sweep report folder (atomically, as every report).
pub fn write(dir: &Path, t: &SweepTable) -> Result<Vec<PathBuf>, Error> {
    super::write_folder(dir, &render(t)?)
}

fn document(t: &SweepTable, figures: Vec<super::document::Figure>) -> Document {
    let failed = t.points.iter().filter(|p| !p.pass).count();
    let method = match t.sweep.method {
        SweepMethod::Grid => "a full grid".to_string(),
        SweepMethod::Lhs => format!("a Latin hypercube (seed {})", t.sweep.seed),
    };
    let preamble = vec![Block::Paragraph(
        Text::plain(format!(
            "{} points ({method}), each with a Monte Carlo of {} runs (seed {}; the same \
             draws at every point). ",
            t.points.len(),
            t.runs,
            t.seed
        ))
        .strong(format!(
            "{failed} of {} points fail a gate.",
            t.points.len()
        )),
    )];
    let mut sections =
        vec![
            Section::new("Swept keys", vec![Block::Table(keys(t))]),
            Section::new(
                "Results",
                vec![
                Block::Paragraph(Text::plain(
                    "Percentiles over every satellite and run of the point; a row that fails a \
                     gate is marked. The gates are the Monte Carlo bounds of `qualify`: ",
                )
                .and(gate_names(t))),
                Block::Table(results(t)),
            ],
            ),
        ];
    if !figures.is_empty() {
        sections.push(Section::new("Plots", vec![Block::Figures(figures)]));
    }
    sections.push(Section::new(
        "Provenance",
        vec![Block::Paragraph(
            Text::plain("Scene ")
                .code(&t.scene)
                .and(", FNV-1a hash ")
                .code(&t.scene_hash)
                .and(format!(", satqual {}.", t.satqual_version)),
        )],
    ));
    Document {
        title: format!("Parameter sweep: {}", t.scene),
        preamble,
        sections,
    }
}

/// The gates of the first point with their limits (every point has the same names).
fn gate_names(t: &SweepTable) -> String {
    t.points.first().map_or(String::new(), |p| {
        let g: Vec<String> = p
            .gates
            .iter()
            .map(|g| format!("{} (limit {})", g.name, g.limit))
            .collect();
        format!("{}.", g.join("; "))
    })
}

fn keys(t: &SweepTable) -> Table {
    let mut table = Table::new(vec![Column::left("key"), Column::left("values")]);
    for p in &t.sweep.parameter {
        let values = match (&t.sweep.method, p.bounds) {
            (SweepMethod::Lhs, Some([a, b])) => format!("uniform strata in [{a}, {b}]"),
            _ => p
                .grid_values()
                .iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(", "),
        };
        table.row(vec![p.key.clone(), values]);
    }
    table
}

fn results(t: &SweepTable) -> Table {
    let mut columns = vec![Column::right("point")];
    columns.extend(t.keys.iter().map(|k| Column::right(k)));
    columns.extend(OUTPUTS.iter().map(|o| Column::right(&o.heading())));
    columns.push(Column::left("failed gates"));
    let mut table = Table::new(columns);
    for p in &t.points {
        let mut cells = vec![p.point.to_string()];
        cells.extend(p.values.iter().map(|v| v.to_string()));
        cells.extend(OUTPUTS.iter().map(|o| match (o.get)(p) {
            Some(v) => format!("{v:.4}"),
            None => "–".into(),
        }));
        let failed: Vec<&str> = p
            .gates
            .iter()
            .filter(|g| !g.pass)
            .map(|g| g.name.as_str())
            .collect();
        cells.push(if failed.is_empty() {
            "none".into()
        } else {
            failed.join("; ")
        });
        table.rows.push(Row {
            cells,
            failed: !p.pass,
        });
    }
    table
}
