//! FRFs measured and exported by a modal acquisition system (UFF58 records of function type 4,
//! complex, on frequency lines, in [`uff`]; or a text table, in [`table`]): `ema` fits them as
//! they are, instead of estimating FRFs from time histories. A roving test holds one FRF per point: either one reference and roving
//! responses (a shaker, a fixed hammer point) or one response and a roving hammer, whose shapes
//! are read at the hit points by reciprocity.

mod table;
mod uff;

use super::{FrfForm, FrfSet};
use crate::error::SignalError;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Frequency lines of two records agree to this fraction of the highest line.
const LINES_AGREE: f64 = 1e-9;

/// Whether `a` holds the lines of `b`, each within [`LINES_AGREE`] of `b`'s highest line.
fn same_lines(a: &[f64], b: &[f64]) -> bool {
    let top = b.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= LINES_AGREE * top)
}

/// Which end of the FRFs stays put over the test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    /// One reference (shaker, fixed hammer point), roving responses: shapes at the responses.
    CommonReference,
    /// One response (a fixed accelerometer), roving hammer: shapes at the hit points.
    CommonResponse,
}

/// Where an FRF of the set was read.
#[derive(Debug, Clone, Serialize)]
pub struct FrfRecordSource {
    pub channel: String,
    pub file: PathBuf,
    /// Line of the record's `58` marker.
    pub line: u64,
}

/// FRFs read from files, ready for [`super::identify`].
#[derive(Debug, Clone)]
pub struct MeasuredFrfs {
    pub set: FrfSet,
    /// What the FRFs measure per unit force, from the ordinate's data type (record 9); `None`
    /// when the file does not say.
    pub form: Option<FrfForm>,
    /// Where `form` comes from, or why the file does not give it.
    pub form_basis: String,
    pub layout: Layout,
    /// The point every FRF shares (`1:+Z`, with its entity when the file names it).
    pub common_point: String,
    /// The FRFs' unit (`g/N` when converted; the file's label, or `as stored`).
    pub unit: String,
    pub records: Vec<FrfRecordSource>,
    pub notes: Vec<String>,
}

/// The measured FRFs of `paths` when they are FRF tables or UFF files holding FRF records;
/// `None` when they are time histories, from which FRFs are estimated. `input` picks the
/// reference when UFF files hold several; `outputs` picks FRFs by name (all when empty).
pub fn read_measured_frfs(
    paths: &[PathBuf],
    input: Option<&str>,
    outputs: &[String],
) -> Result<Option<MeasuredFrfs>, SignalError> {
    if let Some(tables) = table::table_frfs(paths, input, outputs)? {
        return Ok(Some(tables));
    }
    uff::uff_frfs(paths, input, outputs)
}

fn distinct(items: impl Iterator<Item = String>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for i in items {
        if !out.contains(&i) {
            out.push(i);
        }
    }
    out
}

/// The FRFs `outputs` names, in that order; all of them when it is empty. `file` is named in
/// the error (the first file read).
fn select<T>(
    named: Vec<(String, T)>,
    outputs: &[String],
    file: &Path,
) -> Result<Vec<(String, T)>, SignalError> {
    if outputs.is_empty() {
        return Ok(named);
    }
    let available = named
        .iter()
        .map(|(n, _)| n.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let mut pool: Vec<Option<(String, T)>> = named.into_iter().map(Some).collect();
    outputs
        .iter()
        .map(|o| {
            let slot = pool
                .iter_mut()
                .find(|s| s.as_ref().is_some_and(|(n, _)| n == o));
            slot.and_then(Option::take)
                .ok_or_else(|| SignalError::NoSuchChannel {
                    file: file.to_path_buf(),
                    name: o.clone(),
                    available: format!("the FRFs {available}; each named once"),
                })
        })
        .collect()
}

fn span(lines: &[f64]) -> String {
    match (lines.first(), lines.last()) {
        (Some(a), Some(b)) => format!("{} lines, {a}–{b} Hz", lines.len()),
        _ => "no lines".into(),
    }
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}
