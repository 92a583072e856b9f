//! The report of `satqual update --report DIR`: the parameters before and after with their
//! intervals, the paired frequencies before and after, the correlation gates of the updated
//! model, the identifiability figures, the damping identified from measured peaks, and the
//! MAC matrix before and after as heat maps. `report.md`, `report.html` (inline SVG),
//! `results.json` (the update's JSON) and `plots/*.svg`, written as one folder.

use super::document::{Block, Column, Document, Figure, Section, Table, Text, VerdictLine};
use super::{mac_heatmap, render_html, render_md};
use crate::error::Error;
use crate::pipeline::workflows::correlate::Correlation;
use crate::pipeline::workflows::update::Update;
use crate::pipeline::workflows::update::overlay::Overlay;
use std::path::{Path, PathBuf};

/// Writes the report folder (see [`super::write_folder`]).
pub fn write(
    dir: &Path,
    u: &Update,
    (before, after): (&Correlation, &Correlation),
    overlays: &Result<Vec<Overlay>, String>,
) -> Result<Vec<PathBuf>, Error> {
    let mut figures = vec![
        mac_figure("mac-before", "MAC before the update", before)?,
        mac_figure("mac-after", "MAC after the update", after)?,
    ];
    for (i, o) in overlays.iter().flatten().enumerate() {
        figures.push(frf_figure(i, o)?);
    }
    let mut files: Vec<(String, Vec<u8>)> = figures
        .iter()
        .map(|f| (f.file(), f.svg.clone().into_bytes()))
        .collect();
    crate::output_check::check_json(u, "results.json")?;
    let json =
        serde_json::to_string_pretty(u).map_err(|e| Error::Other(format!("results.json: {e}")))?;
    files.push(("results.json".into(), (json + "\n").into_bytes()));
    let mut doc = document(u, after, figures);
    if let Err(why) = overlays {
        let note = Block::Paragraph(Text::plain(why.clone()));
        doc.sections
            .last_mut()
            .expect("Plots")
            .blocks
            .insert(0, note);
    }
    files.push(("report.md".into(), render_md::render(&doc).into_bytes()));
    files.push(("report.html".into(), render_html::render(&doc).into_bytes()));
    super::write_folder(dir, &files)
}

fn mac_figure(stem: &str, caption: &str, c: &Correlation) -> Result<Figure, Error> {
    let svg = mac_heatmap::of_correlation(c, caption)?;
    Ok(Figure {
        stem: stem.into(),
        caption: format!("{caption}: test modes (rows) against FE modes (columns), pairs outlined"),
        svg,
    })
}

/// |H| measured against the model before and after, log-log.
fn frf_figure(i: usize, o: &Overlay) -> Result<Figure, Error> {
    use super::plot::{Scale, Series, lines_svg};
    let pts = |v: &[f64]| -> Vec<(f64, f64)> {
        o.frequency_hz
            .iter()
            .copied()
            .zip(v.iter().copied())
            .collect()
    };
    let (m, b, a) = (pts(&o.measured), pts(&o.before), pts(&o.after));
    let series = [
        Series {
            label: "measured (H1)".into(),
            points: &m,
        },
        Series {
            label: "model before".into(),
            points: &b,
        },
        Series {
            label: "model after".into(),
            points: &a,
        },
    ];
    let title = format!("FRF {}: measured against the model", o.channel);
    let svg = lines_svg(
        &title,
        "frequency [Hz]",
        "|H| [g/g]",
        &series,
        Scale::Log,
        Scale::Log,
    )?;
    Ok(Figure {
        stem: format!("frf-{}", i + 1),
        caption: format!("{title}, before and after the update"),
        svg,
    })
}

fn document(u: &Update, after: &Correlation, figures: Vec<Figure>) -> Document {
    let failed = after.gates.iter().filter(|g| !g.pass).count();
    let mut sections = vec![
        Section::new("Parameters", vec![Block::Table(parameters(u))]),
        Section::new("Frequencies", vec![Block::Table(frequencies(u))]),
        Section::new(
            "Correlation of the updated model",
            vec![Block::Table(gates(after))],
        ),
        Section::new("Identifiability", identifiability(u)),
    ];
    if !u.damping.is_empty() {
        let blocks = vec![Block::Table(damping(u))];
        sections.push(Section::new("Damping from the measured sine peaks", blocks));
    }
    let notes: Vec<Block> = (u.warnings.iter().map(|w| format!("Warning: {w}")))
        .chain(u.notes.iter().map(|n| format!("Note: {n}")))
        .map(|t| Block::Paragraph(Text::plain(t)))
        .collect();
    if !notes.is_empty() {
        sections.push(Section::new("Warnings and notes", notes));
    }
    sections.push(Section::new("Plots", vec![Block::Figures(figures)]));
    Document {
        title: "Model update".into(),
        preamble: vec![
            Block::Verdict(VerdictLine {
                pass: u.converged && failed == 0,
                gates: after.gates.len(),
                failed,
            }),
            Block::Paragraph(Text::plain(format!("{}.", u.headline()))),
        ],
        sections,
    }
}

fn parameters(u: &Update) -> Table {
    let mut t = Table::new(vec![
        Column::left("parameter"),
        Column::right("start"),
        Column::right("updated"),
        Column::right("change"),
        Column::right("95 % interval"),
        Column::right("bounds"),
        Column::left("identifiable"),
    ]);
    for p in &u.parameters {
        let ci = match (p.ci_low, p.ci_high) {
            (Some(a), Some(b)) => format!("[{a:.5e}, {b:.5e}]"),
            _ => "undefined".into(),
        };
        t.row(vec![
            p.path.clone(),
            format!("{:.6e}", p.start),
            format!("{:.6e}", p.value),
            format!("{:+.2} %", 100.0 * (p.value - p.start) / p.start),
            ci,
            format!("[{:.3e}, {:.3e}]", p.lower, p.upper),
            if p.identifiable { "yes" } else { "NO" }.into(),
        ]);
    }
    t
}

fn frequencies(u: &Update) -> Table {
    let mut t = Table::new(vec![
        Column::right("test mode"),
        Column::right("FE mode"),
        Column::right("test [Hz]"),
        Column::right("before [Hz]"),
        Column::right("after [Hz]"),
        Column::right("error before"),
        Column::right("error after"),
        Column::right("MAC"),
    ]);
    for r in &u.targets {
        t.row(vec![
            r.test_mode.to_string(),
            r.fe_mode.to_string(),
            format!("{:.4}", r.test_hz),
            format!("{:.4}", r.before_hz),
            format!("{:.4}", r.after_hz),
            format!("{:+.3} %", r.error_before_pct),
            format!("{:+.3} %", r.error_after_pct),
            format!("{:.4}", r.mac),
        ]);
    }
    t
}

fn gates(c: &Correlation) -> Table {
    let mut t = Table::new(vec![
        Column::left("gate"),
        Column::right("value"),
        Column::right("limit"),
        Column::left("verdict"),
    ]);
    for g in &c.gates {
        t.row(vec![
            g.name.clone(),
            format!("{:.4}", g.value),
            format!("{}", g.limit),
            if g.pass { "pass" } else { "FAIL" }.into(),
        ]);
    }
    t
}

fn identifiability(u: &Update) -> Vec<Block> {
    let sv: Vec<String> = u
        .singular_values
        .iter()
        .map(|s| format!("{s:.4e}"))
        .collect();
    let mut columns = vec![Column::left("correlation")];
    columns.extend(u.parameters.iter().map(|p| Column::right(&p.path)));
    let mut t = Table::new(columns);
    for (p, row) in u.parameters.iter().zip(&u.correlation) {
        let mut cells = vec![p.path.clone()];
        cells.extend(row.iter().map(|c| format!("{c:+.3}")));
        t.row(cells);
    }
    vec![
        Block::Paragraph(Text::plain(format!(
            "Singular values of the weighted sensitivity matrix: {}.",
            sv.join(", ")
        ))),
        Block::Table(t),
    ]
}

fn damping(u: &Update) -> Table {
    let mut t = Table::new(vec![
        Column::right("test mode"),
        Column::right("FE mode"),
        Column::left("channel"),
        Column::right("measured [g]"),
        Column::right("predicted [g]"),
        Column::right("ζ before"),
        Column::right("ζ identified"),
    ]);
    for d in &u.damping {
        t.row(vec![
            d.test_mode.to_string(),
            d.fe_mode.to_string(),
            d.channel.clone(),
            format!("{:.4}", d.measured_g),
            format!("{:.4}", d.predicted_g),
            format!("{:.5}", d.zeta_start),
            format!("{:.5}", d.zeta),
        ]);
    }
    t
}
