//! Text tables over frequency (FRFs for `ema`, PSDs for `psd`): a frequency first column,
//! read with the log reader's dialect ([`super::sniff`]).

use super::sniff::{Dialect, number, sniff_dialect, split_fields};
use crate::error::SignalError;
use std::path::Path;

fn err(file: &Path, line: u64, message: impl Into<String>) -> SignalError {
    SignalError::AtLine {
        file: file.to_path_buf(),
        line,
        message: message.into(),
    }
}

/// The dialect of the file's head (its first 64 KB), so that a long time log is not read
/// whole to be told apart from a table.
pub fn sniff_head(path: &Path) -> Option<Dialect> {
    use std::io::Read;
    const HEAD: u64 = 64 * 1024;
    let mut head = Vec::new();
    let (file, _) = super::text::open(path).ok()?;
    file.take(HEAD).read_to_end(&mut head).ok()?;
    let eof = (head.len() as u64) < HEAD;
    sniff_dialect(&head, eof)
}

/// How a table's text was read, one note per decision (encoding, delimiter, decimal comma,
/// preamble, units row), as a log's are.
pub fn table_notes(path: &Path, dialect: &Dialect, header: &[String]) -> Vec<String> {
    super::text::open(path)
        .ok()
        .and_then(|(_, form)| form.note(path))
        .into_iter()
        .chain(super::dialect_notes(path, dialect, header))
        .collect()
}

/// Whether a header cell names a frequency column (`f`, `freq`, `Frequency [Hz]`, `Frequenz`).
pub fn is_frequency_column(name: &str) -> bool {
    let n = stem_of_unit(&name.to_lowercase());
    let n = n.trim().trim_end_matches("_hz").trim_end_matches(" hz");
    matches!(
        n.trim(),
        "f" | "freq" | "frequency" | "frequenz" | "fréquence" | "frequence" | "hz"
    )
}

/// A name without a trailing unit in brackets (`frequency [hz]` -> `frequency`).
fn stem_of_unit(n: &str) -> String {
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let Some(inner) = n.trim_end().strip_suffix(close)
            && let Some(i) = inner.rfind(open)
        {
            return inner[..i].trim_end().to_string();
        }
    }
    n.to_string()
}

/// Every data row, as numbers, with its line.
pub fn data_rows(
    path: &Path,
    bytes: &[u8],
    dialect: &Dialect,
    what: &str,
) -> Result<Vec<(u64, Vec<f64>)>, SignalError> {
    let text = String::from_utf8_lossy(&bytes[dialect.data_offset..]);
    let mut rows = Vec::new();
    for (k, l) in text.lines().enumerate() {
        let line = dialect.data_line + k as u64;
        if l.trim().is_empty() {
            continue;
        }
        let fields = split_fields(l, dialect.delimiter);
        let mut values = Vec::with_capacity(fields.len());
        for (c, f) in fields.iter().enumerate() {
            if dialect.empty_columns.contains(&c) && f.is_empty() {
                values.push(0.0);
                continue;
            }
            let v = number(f, dialect.decimal_comma).ok_or_else(|| {
                err(
                    path,
                    line,
                    format!("column {}: `{f}` is not a finite number", c + 1),
                )
            })?;
            values.push(v);
        }
        if values.len() != dialect.width {
            return Err(err(
                path,
                line,
                format!("{} fields, the header has {}", values.len(), dialect.width),
            ));
        }
        rows.push((line, values));
    }
    if rows.is_empty() {
        return Err(err(
            path,
            dialect.header_line,
            format!("a {what} with no rows"),
        ));
    }
    Ok(rows)
}
