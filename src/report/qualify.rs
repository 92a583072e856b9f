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

/// Writes the report folder: everything into a temporary sibling folder first, then swapped
/// in. An existing report is replaced only once the new one is complete; on failure nothing
/// half-written is left behind.
pub fn write(dir: &Path, q: &Qualification) -> Result<Vec<PathBuf>, Error> {
    let files = render(q)?;
    let parent = dir
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "report".into());
    let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
    let cleanup = |p: &Path| {
        let _ = std::fs::remove_dir_all(p);
    };
    cleanup(&tmp);
    let mut written = Vec::new();
    for (rel, bytes) in &files {
        let p = tmp.join(rel);
        if let Err(e) = super::write_atomic(&p, bytes) {
            cleanup(&tmp);
            return Err(e);
        }
        written.push(dir.join(rel));
    }
    let old = parent.join(format!(".{name}.old-{}", std::process::id()));
    if dir.exists() {
        std::fs::rename(dir, &old).map_err(|e| {
            cleanup(&tmp);
            Error::io(dir, e)
        })?;
    }
    if let Err(e) = std::fs::rename(&tmp, dir) {
        // Put the previous report back.
        let _ = std::fs::rename(&old, dir);
        cleanup(&tmp);
        return Err(Error::io(dir, e));
    }
    cleanup(&old);
    Ok(written)
}
