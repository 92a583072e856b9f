//! Measured FRFs from text tables ([`crate::signal::ema::frf_table`]): one or several files on
//! the same lines, their FRFs named by their columns.

use super::{FrfRecordSource, Layout, MeasuredFrfs, same_lines, select, span};
use crate::error::SignalError;
use crate::signal::ema::FrfSet;
use crate::signal::ema::frf_table::{FrfTable, read_frf_table};
use crate::signal::uff;
use realfft::num_complex::Complex64;
use std::path::PathBuf;

/// An FRF of a table by its name.
type NamedColumn = (String, TableColumn);

/// One FRF of a table, with where it was read.
struct TableColumn {
    file: PathBuf,
    header_line: u64,
    h: Vec<Complex64>,
}

/// The FRFs of text tables (a frequency column, then re/im or magnitude/phase pairs), when the
/// first file is one; every file must then be one, on the same lines.
pub(super) fn table_frfs(
    paths: &[PathBuf],
    input: Option<&str>,
    outputs: &[String],
) -> Result<Option<MeasuredFrfs>, SignalError> {
    let Some(tables) = read_tables(paths)? else {
        return Ok(None);
    };
    let mut notes: Vec<String> = tables.iter().flat_map(|(_, t)| t.notes.clone()).collect();
    let (freqs, named) = join_tables(tables)?;
    let chosen = select(named, outputs, &paths[0])?;
    let records = chosen
        .iter()
        .map(|(n, c)| FrfRecordSource {
            channel: n.clone(),
            file: c.file.clone(),
            line: c.header_line,
        })
        .collect();
    let note = format!(
        "{} FRF(s) read from {} table(s), fitted as stored: a table states neither its \
         reference, nor what its FRFs measure, nor the window the acquisition applied",
        chosen.len(),
        paths.len()
    );
    notes.push(note);
    let (channels, h) = chosen.into_iter().map(|(n, c)| (n, c.h)).unzip();
    Ok(Some(MeasuredFrfs {
        set: FrfSet { freqs, channels, h },
        form: None,
        form_basis: "a table does not say what its FRFs measure".into(),
        layout: Layout::CommonReference,
        common_point: input.unwrap_or("the table's reference").to_string(),
        unit: "as stored".into(),
        records,
        notes,
    }))
}

/// Every file read as an FRF table, when the first one is one (`None`: time logs or UFF).
fn read_tables(paths: &[PathBuf]) -> Result<Option<Vec<(PathBuf, FrfTable)>>, SignalError> {
    let Some(first) = paths.first().filter(|p| !uff::looks_like_uff(p)) else {
        return Ok(None);
    };
    let Some(head) = read_frf_table(first)? else {
        return Ok(None);
    };
    let mut tables = vec![(first.clone(), head)];
    for p in &paths[1..] {
        let t = read_frf_table(p)?.ok_or_else(|| SignalError::Unsupported {
            file: p.clone(),
            message: format!(
                "{} is an FRF table and this file is not: FRFs cannot be averaged with time \
                 histories",
                first.display()
            ),
        })?;
        tables.push((p.clone(), t));
    }
    Ok(Some(tables))
}

/// The tables' common lines and their FRFs by name (unique over every table).
fn join_tables(
    tables: Vec<(PathBuf, FrfTable)>,
) -> Result<(Vec<f64>, Vec<NamedColumn>), SignalError> {
    let (first, freqs) = (tables[0].0.clone(), tables[0].1.freqs.clone());
    let mut named: Vec<NamedColumn> = Vec::new();
    for (p, t) in tables {
        let at = |message: String| SignalError::AtLine {
            file: p.clone(),
            line: t.header_line,
            message,
        };
        if !same_lines(&t.freqs, &freqs) {
            return Err(at(format!(
                "other frequency lines than {}: {} against {}",
                first.display(),
                span(&t.freqs),
                span(&freqs)
            )));
        }
        for f in t.frfs {
            if named.iter().any(|(n, _)| *n == f.name) {
                return Err(at(format!("a second FRF named `{}`", f.name)));
            }
            let column = TableColumn {
                file: p.clone(),
                header_line: t.header_line,
                h: f.h,
            };
            named.push((f.name, column));
        }
    }
    Ok((freqs, named))
}
