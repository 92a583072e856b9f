//! Report writing: JSON, Markdown, HTML with inline SVG plots, CSV curves. Every file is
//! written to a temporary name beside its target and renamed, so a reader never sees half a file.

mod build;
pub mod document;
mod figures;
pub mod plot;
pub mod qualify;
pub mod render_html;
pub mod render_md;
pub mod stabilization_svg;
pub mod svg_plot;

/// The results of a qualification, which the report presents. Imported here only, and used
/// through this re-export everywhere in `report`, so the results can move without the report
/// following them file by file.
pub(crate) use crate::results::{
    ModalSummary, Qualification, SeparationSummary, TestDataSummary, TestLogResult,
};

use crate::error::Error;
use std::path::Path;

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
