//! Report writing: JSON, Markdown, HTML with inline SVG plots, CSV curves. Every file is
//! written to a temporary name beside its target and renamed, so a reader never sees half a file.

mod build;
pub mod document;
mod figures;
pub mod format;
pub mod mac_heatmap;
pub mod plot;
pub mod qualify;
pub mod render_html;
pub mod render_md;
pub mod stabilization_svg;
pub mod svg_plot;
pub mod sweep;
pub mod update;

/// The results of a qualification, which the report presents. Imported here only, and used
/// through this re-export everywhere in `report`, so the results can move without the report
/// following them file by file.
pub(crate) use crate::results::{
    ModalSummary, Qualification, SeparationSummary, TestDataSummary, TestLogResult,
};

use crate::error::Error;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, then a rename.
/// Parent folders are created.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write;
    // Every CSV the program writes passes here: a NaN or infinity in a cell is an error.
    if path.extension().is_some_and(|e| e == "csv") {
        crate::output_check::check_csv(
            &path.display().to_string(),
            &String::from_utf8_lossy(bytes),
        )?;
    }
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let mut f = std::fs::File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
    f.write_all(bytes).map_err(|e| Error::io(&tmp, e))?;
    f.sync_all().map_err(|e| Error::io(&tmp, e))?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

/// Writes a report folder: every file (path relative to `dir`, content) into a temporary
/// sibling folder first, then swapped in. An existing report is replaced only once the new one is complete; on failure nothing
/// half-written is left behind.
pub fn write_folder(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<PathBuf>, Error> {
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
    for (rel, bytes) in files {
        let p = tmp.join(rel);
        if let Err(e) = write_atomic(&p, bytes) {
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
