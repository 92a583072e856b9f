//! The qualification report an engineer signs: `report.html` (self-contained, inline SVG, no
//! network, printable), `report.md` with the plots as SVG files beside it, `results.json`
//! (every number, no timestamps) and `curves/*.csv` (the data behind every plot).
//! Input: a [`Qualification`]. The report is built once as a [`super::document::Document`]
//! and rendered to both Markdown and HTML. The whole folder is built under a temporary name
//! and swapped in only when complete, so an existing report is never left half-replaced.

use super::Qualification;
use super::figures::{self, Files};
use super::{build, render_html, render_md};
use crate::error::Error;
use std::path::{Path, PathBuf};

/// Renders every file of the report in memory.
pub fn render(q: &Qualification) -> Result<Files, Error> {
    let mut files: Files = Vec::new();
    let figs = figures::build(q, &mut files)?;
    let plots: Files = figs
        .iter()
        .map(|f| (f.file(), f.svg.clone().into_bytes()))
        .collect();
    crate::output_check::check_json(q, "results.json")?;
    let json =
        serde_json::to_string_pretty(q).map_err(|e| Error::Other(format!("results.json: {e}")))?;
    files.push(("results.json".into(), (json + "\n").into_bytes()));
    let doc = build::document(q, figs);
    files.push(("report.md".into(), render_md::render(&doc).into_bytes()));
    files.push(("report.html".into(), render_html::render(&doc).into_bytes()));
    files.extend(plots);
    Ok(files)
}

/// Writes the report folder of a qualification (see [`super::write_folder`]).
pub fn write(dir: &Path, q: &Qualification) -> Result<Vec<PathBuf>, Error> {
    super::write_folder(dir, &render(q)?)
}
