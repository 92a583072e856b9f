//! LabVIEW Measurement (`.lvm`) text files, as the LabVIEW "Write To Measurement File" express
//! VI writes them: a file header block and a segment header block, each closed by
//! `***End_of_Header***`, a line of column names, then the rows.
//!
//! Hand-written: no Rust crate reads LVM. The header fields say everything: `Separator` (Tab or
//! Comma), `Decimal_Separator` (`.` when missing), `X_Columns` (`No`: an X column left empty;
//! `One`: one X column; `Multi`: one X column before each channel), and per channel `Samples`,
//! `Y_Unit_Label` and `Delta_X`. Segments that continue one another are joined (`segments`).

mod segments;

use super::table::{Rate, Series, Table, most_common_interval, same_interval};
use crate::error::SignalError;
use crate::signal::ingest::sniff::number;
use std::path::Path;

const END_OF_HEADER: &str = "***End_of_Header***";

/// Whether the bytes start like an LVM file.
pub fn looks_like_lvm(head: &[u8]) -> bool {
    head.strip_prefix(b"\xef\xbb\xbf")
        .unwrap_or(head)
        .starts_with(b"LabVIEW Measurement")
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum XColumns {
    No,
    One,
    Multi,
}

struct Layout {
    sep: char,
    decimal_comma: bool,
    x: XColumns,
}

fn err(path: &Path, line: usize, message: impl Into<String>) -> SignalError {
    super::table::at_line(path, line, "LVM", message)
}

/// Reads an LVM file into named columns.
pub fn read_lvm(path: &Path, bytes: &[u8]) -> Result<Table, SignalError> {
    // UTF-8, else Windows-1252 (LabVIEW on Windows writes `°` as the byte 0xB0), or UTF-16.
    let text = crate::signal::ingest::text::decode(bytes);
    let lines: Vec<&str> = text.lines().map(|l| l.trim_end_matches('\r')).collect();
    let file_end = find_end(&lines, 0).ok_or_else(|| {
        err(
            path,
            lines.len(),
            format!("no `{END_OF_HEADER}` closes the file header"),
        )
    })?;
    let layout = file_layout(path, &lines[..file_end])?;
    let segments = segments::read_segments(path, &lines, file_end + 1, &layout)?;
    let (warnings, count_notes) = segments::segment_counts(path, &segments, &layout);
    let count = segments.len();
    let segments::Segment {
        header: segment,
        names,
        names_line,
        rows,
        ..
    } = segments::join(path, segments, &layout)?;
    let columns = channel_columns(&names, layout.x);
    let per_channel = |key: &str| segment_field(&segment, key, layout.x);
    let mut table = Table {
        format: "lvm",
        delimiter: if layout.sep == '\t' { "tab" } else { "comma" },
        decimal: if layout.decimal_comma { "," } else { "." },
        series: Vec::new(),
        rate: Rate::Unknown,
        ignored: Vec::new(),
        unreadable: Vec::new(),
        notes: vec![format!(
            "{}: LabVIEW .lvm, X columns {:?}, {} data rows from line {}{}",
            path.display(),
            layout.x,
            rows.len(),
            names_line + 1,
            if count > 1 {
                format!(", {count} segments joined (each starts where the one before ends)")
            } else {
                String::new()
            }
        )],
        warnings,
    };
    table.notes.extend(count_notes);
    let fields = ChannelFields {
        samples: per_channel("Samples"),
        units: per_channel("Y_Unit_Label"),
        delta: per_channel("Delta_X"),
    };
    let log_dt = read_channels(&mut table, &columns, &rows, &fields, &layout);
    if names.last().is_some_and(|n| n == "Comment") {
        table.ignored.push("`Comment` (text)".into());
    }
    table.rate = rate(&rows, log_dt, &layout);
    if let Some(note) = rounded_delta_x_note(path, &table.rate, &fields.delta, log_dt, &layout) {
        table.notes.push(note);
    }
    Ok(table)
}

/// A segment header's per-channel fields.
struct ChannelFields {
    samples: Vec<String>,
    units: Vec<String>,
    delta: Vec<String>,
}

/// Reads every channel column into `table`: the full ones at the log's interval as series,
/// the others as unreadable with their reason. Returns the log's interval.
fn read_channels(
    table: &mut Table,
    columns: &[(usize, String)],
    rows: &[Row],
    fields: &ChannelFields,
    layout: &Layout,
) -> Option<f64> {
    let mut found = Vec::new();
    for (k, (col, name)) in columns.iter().enumerate() {
        let declared_empty = fields.samples.get(k).is_some_and(|s| s == "0");
        let values: Vec<Option<f64>> = rows
            .iter()
            .map(|(_, r)| r.get(*col).copied().flatten())
            .collect();
        if declared_empty || values.iter().all(Option::is_none) {
            table.ignored.push(format!("`{name}` (empty throughout)"));
            continue;
        }
        found.push(Found {
            name: name.clone(),
            unit_label: fields.units.get(k).cloned().unwrap_or_default(),
            dt: fields
                .delta
                .get(k)
                .and_then(|d| number(d, layout.decimal_comma)),
            values,
        });
    }
    let log_dt = log_interval(&found);
    for f in found {
        match readable(&f, rows, log_dt) {
            Ok(values) => table.series.push(Series {
                name: f.name,
                unit_label: f.unit_label,
                values,
            }),
            Err(why) => table.unreadable.push((f.name, why)),
        }
    }
    log_dt
}

/// A note when the rate comes from a `Delta_X` written to too few digits to state it.
fn rounded_delta_x_note(
    path: &Path,
    rate: &Rate,
    delta: &[String],
    log_dt: Option<f64>,
    layout: &Layout,
) -> Option<String> {
    let Rate::Stated(fs, _) = *rate else {
        return None;
    };
    let text = delta
        .iter()
        .find(|d| number(d, layout.decimal_comma) == log_dt)?;
    let rel = rounding_of(text, 1.0 / fs)?;
    (rel > DELTA_X_ROUNDING_NOTE).then(|| {
        format!(
            "{}: Delta_X `{text}` is written to few digits: the rate {fs:.3} Hz is known to ±{:.2}%; pass --fs F --fs-override if the acquisition rate is known",
            path.display(),
            rel * 100.0
        )
    })
}

/// Relative rounding of a written `Delta_X` above which the rate it gives is noted as uncertain
/// (LabVIEW writes 6 decimals by default: 1/1024 s becomes 0.000977, 0.05% off).
const DELTA_X_ROUNDING_NOTE: f64 = 1e-4;

/// Half a unit of the last written digit of `text`, relative to its value `dt`.
fn rounding_of(text: &str, dt: f64) -> Option<f64> {
    let lower = text.to_ascii_lowercase();
    let (mantissa, exponent) = match lower.split_once('e') {
        Some((m, e)) => (m, e.parse::<i32>().ok()?),
        None => (lower.as_str(), 0),
    };
    let decimals = mantissa
        .split_once(['.', ','])
        .map_or(0, |(_, f)| f.len() as i32);
    Some(0.5 * 10f64.powi(exponent - decimals) / dt)
}

fn find_end(lines: &[&str], from: usize) -> Option<usize> {
    (from..lines.len()).find(|&i| lines[i].trim().trim_matches(['\t', ',']) == END_OF_HEADER)
}

fn file_layout(path: &Path, header: &[&str]) -> Result<Layout, SignalError> {
    // `key<TAB>value<TAB>` (or comma-separated): the value may itself be `,` or `.`.
    let value = |key: &str| {
        header.iter().find_map(|l| {
            let cut = if l.contains('\t') { '\t' } else { ',' };
            let (k, v) = l.split_once(cut)?;
            let v = v.trim_end_matches('\t').trim();
            let v = if cut == ',' {
                v.strip_suffix(',').unwrap_or(v)
            } else {
                v
            };
            (k.trim() == key).then(|| v.to_string())
        })
    };
    let sep = match value("Separator").as_deref() {
        None | Some("Tab") => '\t',
        Some("Comma") => ',',
        Some(other) => {
            return Err(err(
                path,
                1,
                format!("Separator `{other}` (expected Tab or Comma)"),
            ));
        }
    };
    let decimal_comma = match value("Decimal_Separator").as_deref() {
        None | Some(".") => false,
        Some(",") => true,
        Some(other) => {
            return Err(err(
                path,
                1,
                format!("Decimal_Separator `{other}` (expected . or ,)"),
            ));
        }
    };
    if decimal_comma && sep == ',' {
        return Err(err(
            path,
            1,
            "Separator Comma with Decimal_Separator `,` cannot be split",
        ));
    }
    let x = match value("X_Columns").as_deref() {
        Some("No") => XColumns::No,
        None | Some("One") => XColumns::One,
        Some("Multi") => XColumns::Multi,
        Some(other) => {
            return Err(err(
                path,
                1,
                format!("X_Columns `{other}` (expected No, One or Multi)"),
            ));
        }
    };
    Ok(Layout {
        sep,
        decimal_comma,
        x,
    })
}

/// Data columns of the channels: every column but the X columns and a trailing `Comment`.
fn channel_columns(names: &[String], x: XColumns) -> Vec<(usize, String)> {
    names
        .iter()
        .enumerate()
        .filter(|(i, n)| {
            let is_x = match x {
                XColumns::No | XColumns::One => *i == 0,
                XColumns::Multi => i % 2 == 0,
            };
            let trailing_comment = n.as_str() == "Comment" && *i + 1 == names.len();
            !(is_x || trailing_comment)
        })
        .map(|(i, n)| (i, n.clone()))
        .collect()
}

/// The per-channel values of a segment header field (one cell per channel, two with
/// `X_Columns Multi`, whose second cell is empty).
fn segment_field(segment: &[Vec<String>], key: &str, x: XColumns) -> Vec<String> {
    let Some(row) = segment.iter().find(|r| r.first().is_some_and(|k| k == key)) else {
        return Vec::new();
    };
    let step = if x == XColumns::Multi { 2 } else { 1 };
    row.iter().skip(1).step_by(step).cloned().collect()
}

type Row = (usize, Vec<Option<f64>>);

/// A channel column as found: its cells (empty ones `None`) and its `Delta_X`.
struct Found {
    name: String,
    unit_label: String,
    dt: Option<f64>,
    values: Vec<Option<f64>>,
}

/// The log's sampling interval: the `Delta_X` most of the full columns share (the first
/// channel's on a tie). LabVIEW writes channels of several rates into one segment, each slower
/// one with empty cells between its samples.
fn log_interval(found: &[Found]) -> Option<f64> {
    let full: Vec<f64> = found
        .iter()
        .filter(|f| f.values.iter().all(Option::is_some))
        .filter_map(|f| f.dt)
        .collect();
    most_common_interval(&full).map(|(dt, _)| dt)
}

/// A channel's values when it is sampled on every row at the log's interval; otherwise why
/// not (it is then listed as not read, and asking for it by name gives the reason).
fn readable(f: &Found, rows: &[Row], log_dt: Option<f64>) -> Result<Vec<f64>, String> {
    let other_rate = match (f.dt, log_dt) {
        (Some(dt), Some(log)) if !same_interval(dt, log) => {
            Some(format!("Delta_X {dt} s against the log's {log} s"))
        }
        _ => None,
    };
    let empty = f.values.iter().filter(|v| v.is_none()).count();
    if empty > 0 {
        let first = f.values.iter().position(Option::is_none).unwrap_or(0);
        let rate = other_rate.map_or(String::new(), |r| format!(": sampled at its own rate, {r}"));
        return Err(format!(
            "empty in {empty} of {} rows, first at line {}{rate}",
            f.values.len(),
            rows[first].0
        ));
    }
    if let Some(r) = other_rate {
        return Err(format!("{r}: one log is read at one rate"));
    }
    Ok(f.values.iter().flatten().copied().collect())
}

/// The sampling rate: the first X column when it holds times, else the `Delta_X` of the
/// channels read.
fn rate(rows: &[Row], log_dt: Option<f64>, l: &Layout) -> Rate {
    if l.x != XColumns::No {
        let times: Vec<Option<f64>> = rows
            .iter()
            .map(|(_, r)| r.first().copied().flatten())
            .collect();
        if times.iter().all(Option::is_some) {
            let t = times.into_iter().flatten().collect();
            return Rate::Times(t, "X_Value".into());
        }
    }
    match log_dt {
        Some(dt) if dt > 0.0 => Rate::Stated(1.0 / dt, "Delta_X of the LVM segment header".into()),
        _ => Rate::Unknown,
    }
}

#[cfg(test)]
mod tests {
    use super::rounding_of;

    /// Half a unit of the last digit over the value: LabVIEW's 6 decimals of 1/1024 s are
    /// 0.5e-6 / 0.000977 = 5.1e-4 off at most (the true 0.0009765625 is 4.5e-4 off); the
    /// `3,906250E-5` of short.lvm (1/25 600 s) is exact to 0.5e-11 / 3.90625e-5 = 1.3e-7.
    #[test]
    fn rounding_of_a_written_interval_is_half_its_last_digit() {
        let r = rounding_of("0.000977", 0.000977).unwrap();
        assert!((r - 0.5e-6 / 0.000977).abs() < 1e-15, "{r}");
        assert!((0.000977f64 - 1.0 / 1024.0).abs() / 0.000977 < r);
        let r = rounding_of("3,906250E-5", 3.90625e-5).unwrap();
        assert!((r - 0.5e-11 / 3.90625e-5).abs() < 1e-18, "{r}");
        assert_eq!(rounding_of("1", 1.0), Some(0.5));
        assert_eq!(rounding_of("1e-x", 1.0), None);
    }
}
