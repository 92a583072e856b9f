//! MATLAB level 5 MAT-files (`save` with `-v6` or `-v7`, the default, whose variables are
//! zlib-compressed), the way labs save logs: vectors and matrices at the top level or as the
//! fields of a struct, a scalar sampling rate (`fs`) or a time vector (`t`, `time`) beside them.
//! Level 4 files (`save -v4`, [`v4`]) hold matrices only and go through the same rules.
//!
//! Hand-written: of the Rust crates, `matfile` reads numeric arrays only (no structs) and
//! `matrw` (0.1) unwraps on malformed input, which must give an error here, never a panic. The
//! element layout is small and fully specified; inflating uses `miniz_oxide`.
//!
//! How variables become channels:
//! - a vector (1xN or Nx1) is one channel named by its path (`log.accel` for a struct field);
//! - a matrix's longer dimension is time: an N x M matrix with N >= M gives channels
//!   `x(:,1)` ... `x(:,M)` (else `x(1,:)` ...);
//! - a scalar named like a sampling rate (`fs`, `Fs`, `sample_rate`, ...) gives the rate, one
//!   named `dt` the interval; other scalars, arrays of 3 or more dimensions, text, cells,
//!   complex and sparse arrays are not read and are listed;
//! - a vector named like a time column (`t`, `time`, `time_s`, `time_ms`) is the time vector;
//! - with no `--channels`, the channels of the most common length are read and the others
//!   are listed.

mod elements;
mod v4;

use super::table::{Rate, Series, Table, keep_common_length};
use crate::error::SignalError;
use crate::signal::ingest::time_column_unit;
use elements::{Reader, Value};
use std::path::Path;

/// The first bytes of a level 5 MAT-file's text header, or a level 4 file's first matrix
/// header.
pub fn looks_like_mat(head: &[u8]) -> bool {
    looks_like_mat5(head) || v4::looks_like_mat4(head)
}

fn looks_like_mat5(head: &[u8]) -> bool {
    head.starts_with(b"MATLAB ") && head.get(10..19) == Some(b" MAT-file".as_slice())
}

fn unsupported(path: &Path, message: impl Into<String>) -> SignalError {
    SignalError::Unsupported {
        file: path.to_path_buf(),
        message: message.into(),
    }
}

/// Reads the variables of a MAT-file (level 5, or level 4 when it has no level 5 header)
/// into named columns.
pub fn read_mat(path: &Path, bytes: &[u8]) -> Result<Table, SignalError> {
    if !looks_like_mat5(bytes) && v4::looks_like_mat4(bytes) {
        let vars = v4::read_mat4(bytes)
            .map_err(|e| unsupported(path, format!("MATLAB level 4 MAT-file: {e}")))?;
        return Ok(to_table(path, vars, 4));
    }
    if bytes.len() < 128 {
        return Err(unsupported(
            path,
            "shorter than the 128-byte MAT-file header",
        ));
    }
    // The version field reads 0x0100 for level 5 and 0x0200 for v7.3, an HDF5 file.
    if bytes[124..126] == [0, 2] || bytes[124..126] == [2, 0] {
        return Err(unsupported(
            path,
            "MATLAB v7.3 MAT-file (HDF5): save the log with `save(..., '-v7')` or `-v6`",
        ));
    }
    let big_endian = match &bytes[126..128] {
        b"IM" => false,
        b"MI" => true,
        other => {
            return Err(unsupported(
                path,
                format!("MAT-file endian indicator {other:?} (expected `IM` or `MI`)"),
            ));
        }
    };
    let mut r = Reader::new(&bytes[128..], big_endian);
    let mut vars = Vec::new();
    let mut k = 0;
    while !r.at_end() {
        k += 1;
        match r.variable() {
            Ok(Some(v)) => vars.push(v),
            Ok(None) => {}
            Err(e) => return Err(unsupported(path, format!("variable {k}: {e}"))),
        }
    }
    Ok(to_table(path, vars, 5))
}

/// Words that name a sampling rate, in Hz, and an interval, in s.
const RATE_NAMES: [&str; 7] = [
    "fs",
    "samplerate",
    "sample_rate",
    "sampling_rate",
    "samplingrate",
    "srate",
    "sr",
];
const INTERVAL_NAMES: [&str; 4] = ["dt", "delta_x", "sample_interval", "ts"];

struct Found {
    series: Vec<Series>,
    rate: Option<(f64, String)>,
    times: Option<(Vec<f64>, String)>,
    ignored: Vec<String>,
    unreadable: Vec<(String, String)>,
    notes: Vec<String>,
}

/// The channels, rate and time vector of a file's variables (`level`: 4 or 5, for the note).
fn to_table(path: &Path, vars: Vec<(String, Value)>, level: u8) -> Table {
    let mut f = Found {
        series: Vec::new(),
        rate: None,
        times: None,
        ignored: Vec::new(),
        unreadable: Vec::new(),
        notes: Vec::new(),
    };
    for (name, value) in vars {
        collect(&name, value, &mut f);
    }
    keep_common_length(
        &mut f.series,
        &mut f.unreadable,
        f.times.as_ref().map(|(t, name)| (t.len(), name.as_str())),
    );
    let rate = match (f.times, f.rate) {
        (Some((t, name)), _) => Rate::Times(t, name),
        (None, Some((fs, from))) => Rate::Stated(fs, from),
        (None, None) => Rate::Unknown,
    };
    let mut notes = vec![format!(
        "{}: MATLAB level {level} MAT-file, {} channel(s)",
        path.display(),
        f.series.len()
    )];
    notes.extend(f.notes);
    Table {
        format: "mat",
        delimiter: "none (binary)",
        decimal: ".",
        series: f.series,
        rate,
        ignored: f.ignored,
        unreadable: f.unreadable,
        notes,
        warnings: Vec::new(),
    }
}

/// Adds one variable (or struct field) at `path` to what was found.
fn collect(name: &str, value: Value, f: &mut Found) {
    match value {
        Value::Struct(fields) => {
            for (field, v) in fields {
                collect(&format!("{name}.{field}"), v, f);
            }
        }
        Value::Other(what) => f.ignored.push(format!("`{name}` ({what})")),
        Value::Numeric { dims, data } => numeric(name, &dims, data, f),
    }
}

fn numeric(name: &str, dims: &[usize], data: Vec<f64>, f: &mut Found) {
    let leaf = name.rsplit('.').next().unwrap_or(name).to_ascii_lowercase();
    let non_single = dims.iter().filter(|&&d| d > 1).count();
    if data.is_empty() {
        f.ignored.push(format!("`{name}` (empty)"));
    } else if data.len() == 1 {
        scalar(name, &leaf, data[0], f);
    } else if dims.len() > 2 && non_single > 1 {
        f.ignored
            .push(format!("`{name}` ({dims:?} array: more than 2 dimensions)"));
    } else if non_single == 1 {
        if let Some(unit) = time_column_unit(&leaf) {
            let k = unit.map_or(1.0, |u| u.seconds());
            f.times = Some((data.iter().map(|v| v * k).collect(), name.to_string()));
        } else {
            f.series.push(Series {
                name: name.to_string(),
                unit_label: String::new(),
                values: data,
            });
        }
    } else {
        matrix_channels(name, dims[0], dims[1], &data, f);
    }
}

fn scalar(name: &str, leaf: &str, v: f64, f: &mut Found) {
    let as_rate = if RATE_NAMES.contains(&leaf) {
        Some(v)
    } else if INTERVAL_NAMES.contains(&leaf) && v != 0.0 {
        Some(1.0 / v)
    } else {
        None
    };
    match as_rate {
        Some(fs) if f.rate.is_none() => f.rate = Some((fs, format!("variable `{name}`"))),
        _ => f.ignored.push(format!("`{name}` (scalar {v})")),
    }
}

/// Columns (or rows) of an N x M matrix, column-major, as channels along the longer dimension.
fn matrix_channels(name: &str, rows: usize, cols: usize, data: &[f64], f: &mut Found) {
    if rows >= cols {
        for c in 0..cols {
            f.series.push(Series {
                name: format!("{name}(:,{})", c + 1),
                unit_label: String::new(),
                values: data[c * rows..(c + 1) * rows].to_vec(),
            });
        }
        f.notes.push(format!(
            "matrix `{name}` {rows}x{cols}: {cols} channels, one per column"
        ));
    } else {
        for r in 0..rows {
            f.series.push(Series {
                name: format!("{name}({},:)", r + 1),
                unit_label: String::new(),
                values: (0..cols).map(|c| data[c * rows + r]).collect(),
            });
        }
        f.notes.push(format!(
            "matrix `{name}` {rows}x{cols}: {rows} channels, one per row"
        ));
    }
}
