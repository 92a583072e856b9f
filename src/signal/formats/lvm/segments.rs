//! The segments of an LVM file. Each call of LabVIEW's "Write To Measurement File" appends a
//! segment: a header block closed by `***End_of_Header***`, a line of column names, the rows.
//! A logger that writes a long record block by block leaves one segment per block; they are
//! joined into one record when they hold the same columns at the same `Delta_X` and each starts
//! where the one before ends, by its `X0` or by the `Date`/`Time` of its header. Anything else
//! (other channels, a gap, an overlap) is refused at the segment's line: joining it would put
//! samples at the wrong times.

use super::{END_OF_HEADER, Layout, Row, err, find_end, number, segment_field};
use crate::error::SignalError;
use crate::signal::ingest::iso8601;
use std::path::Path;

/// One segment: its header fields, column names and rows.
pub(super) struct Segment {
    /// Line of the segment header's first line (1-based).
    pub line: usize,
    pub header: Vec<Vec<String>>,
    pub names: Vec<String>,
    /// Line of the column names (1-based).
    pub names_line: usize,
    pub rows: Vec<Row>,
}

/// Every segment from line index `from` (the line after the file header) to the end.
pub(super) fn read_segments(
    path: &Path,
    lines: &[&str],
    mut from: usize,
    layout: &Layout,
) -> Result<Vec<Segment>, SignalError> {
    let fields =
        |l: &str| -> Vec<String> { l.split(layout.sep).map(|f| f.trim().to_string()).collect() };
    let mut segments = Vec::new();
    loop {
        let end = find_end(lines, from).ok_or_else(|| {
            err(
                path,
                lines.len(),
                format!("no `{END_OF_HEADER}` closes the segment header"),
            )
        })?;
        let names = lines.get(end + 1).map(|l| fields(l)).ok_or_else(|| {
            err(
                path,
                end + 2,
                "no line of column names after the segment header",
            )
        })?;
        let (rows, next) = data_rows(path, lines, end + 2, layout, names.len())?;
        segments.push(Segment {
            line: from + 1,
            header: lines[from..end].iter().map(|l| fields(l)).collect(),
            names,
            names_line: end + 2,
            rows,
        });
        match next {
            Some(n) => from = n,
            None => break,
        }
    }
    if segments.iter().all(|s| s.rows.is_empty()) {
        return Err(SignalError::HeaderOnly {
            file: path.to_path_buf(),
        });
    }
    Ok(segments)
}

/// The rows from `start` up to the next segment header (whose line index is returned) or the
/// end: each cell a number or empty.
fn data_rows(
    path: &Path,
    lines: &[&str],
    start: usize,
    l: &Layout,
    width: usize,
) -> Result<(Vec<Row>, Option<usize>), SignalError> {
    let mut rows = Vec::new();
    for (i, line) in lines.iter().enumerate().skip(start) {
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(l.sep).map(str::trim).collect();
        if cells[0] == "LabVIEW Measurement" {
            return Err(err(
                path,
                i + 1,
                "a second file header starts here: two LVM files were joined; read each alone",
            ));
        }
        let starts_header = !cells[0].is_empty() && number(cells[0], l.decimal_comma).is_none();
        if starts_header && find_end(lines, i).is_some() {
            return Ok((rows, Some(i)));
        }
        let mut row = Vec::with_capacity(width);
        for (c, cell) in cells.iter().enumerate().take(width) {
            if cell.is_empty() {
                row.push(None);
            } else if let Some(v) = number(cell, l.decimal_comma) {
                row.push(Some(v));
            } else if c + 1 == width {
                // The trailing Comment column holds text.
                row.push(None);
            } else {
                return Err(err(
                    path,
                    i + 1,
                    format!("column {}: cannot parse number `{cell}`", c + 1),
                ));
            }
        }
        rows.push((i + 1, row));
    }
    Ok((rows, None))
}

/// One segment holding every segment's rows, when each continues the one before; the first
/// segment's header describes it.
pub(super) fn join(
    path: &Path,
    segments: Vec<Segment>,
    layout: &Layout,
) -> Result<Segment, SignalError> {
    let mut it = segments.into_iter();
    let mut whole = it
        .next()
        .expect("read_segments returns at least one segment");
    let mut end = span(&whole, layout).end();
    for (k, next) in it.enumerate() {
        let number = k + 2;
        if next.names != whole.names {
            return Err(err(
                path,
                next.line,
                format!(
                    "segment {number} holds other columns than segment 1 ({}); read files of one set of channels",
                    next.names.join(", ")
                ),
            ));
        }
        let here = span(&next, layout);
        if here.dt != end.dt {
            return Err(err(
                path,
                next.line,
                format!(
                    "segment {number} has Delta_X {:?} s, segment 1 {:?} s: one record has one rate",
                    here.dt, end.dt
                ),
            ));
        }
        continues(path, &next, number, &end, &here)?;
        end = here.end();
        whole.rows.extend(next.rows);
    }
    Ok(whole)
}

/// Where a segment starts and how long it lasts, as its header states it.
struct Span {
    dt: Option<f64>,
    rows: usize,
    /// `X0` of the first channel, s.
    x0: Option<f64>,
    /// `Date` and `Time` of the first channel, s since 1970.
    clock: Option<f64>,
}

impl Span {
    /// Where the segment ends: its start moved on by its rows.
    fn end(self) -> Span {
        let duration = self.dt.unwrap_or(0.0) * self.rows as f64;
        Span {
            x0: self.x0.map(|x| x + duration),
            clock: self.clock.map(|c| c + duration),
            ..self
        }
    }
}

fn span(s: &Segment, layout: &Layout) -> Span {
    let first = |key: &str| segment_field(&s.header, key, layout.x).into_iter().next();
    let num = |key: &str| first(key).and_then(|v| number(&v, layout.decimal_comma));
    let clock = first("Date").zip(first("Time")).and_then(|(d, t)| {
        let stamp = format!("{}T{}", d.replace('/', "-"), t.replace(',', "."));
        iso8601::parse(&stamp).map(|i| i.seconds as f64 + i.fraction)
    });
    Span {
        dt: num("Delta_X"),
        rows: s.rows.len(),
        x0: num("X0"),
        clock,
    }
}

/// A segment continues the record when its `X0`, or else its header's clock, is where the one
/// before ends, within half a sample.
fn continues(
    path: &Path,
    next: &Segment,
    number: usize,
    end: &Span,
    here: &Span,
) -> Result<(), SignalError> {
    let half = 0.5 * here.dt.unwrap_or(0.0);
    let gap = |a: Option<f64>, b: Option<f64>| a.zip(b).map(|(a, b)| b - a);
    let by_x0 = gap(end.x0, here.x0);
    let by_clock = gap(end.clock, here.clock);
    if [by_x0, by_clock].iter().flatten().any(|g| g.abs() <= half) {
        return Ok(());
    }
    let off = |what: &str, g: Option<f64>| g.map(|g| format!("{what} {g:+.6} s"));
    let shown: Vec<String> = [off("by X0", by_x0), off("by the header clock", by_clock)]
        .into_iter()
        .flatten()
        .collect();
    let shown = if shown.is_empty() {
        "no X0, Date or Time to place it".to_string()
    } else {
        format!("off {}", shown.join(", "))
    };
    Err(err(
        path,
        next.line,
        format!(
            "segment {number} does not start where segment {} ends ({shown}: a gap or an overlap in the record); split the file at this line and read each part",
            number - 1
        ),
    ))
}

/// The rows of each segment against the `Samples` its header announces (per channel, the
/// fastest channel's), as (warnings, notes).
/// - Fewer rows: the file was cut short, as a copy stopped mid-way leaves it. The rows present
///   are read; the warning says what is missing.
/// - More rows: LabVIEW's one-header mode appends later writes under the first header. They
///   are read as one record; the note says so, since separate records joined this way (two
///   impacts in one file) would cross the join in every Welch segment.
pub(super) fn segment_counts(
    path: &Path,
    segments: &[Segment],
    layout: &Layout,
) -> (Vec<String>, Vec<String>) {
    let (mut warnings, mut notes) = (Vec::new(), Vec::new());
    for seg in segments {
        let Some(announced) = segment_field(&seg.header, "Samples", layout.x)
            .iter()
            .filter_map(|s| s.parse::<usize>().ok())
            .max()
        else {
            continue;
        };
        let at = seg
            .header
            .iter()
            .position(|r| r.first().is_some_and(|k| k == "Samples"));
        let line = seg.line + at.unwrap_or(0);
        let rows = seg.rows.len();
        if announced > rows {
            warnings.push(format!(
                "{}: line {line}: the LVM segment header announces {announced} samples per channel, but {rows} rows follow: the file ends early (cut short?); the rows present are analysed",
                path.display(),
            ));
        } else if announced > 0 && rows > announced {
            let writes = if rows % announced == 0 {
                format!("{} writes of {announced}", rows / announced)
            } else {
                format!("writes of about {announced}")
            };
            notes.push(format!(
                "{}: line {line}: the LVM segment header announces {announced} samples per channel and {rows} rows follow ({writes} appended under one header): read as one record; if they are separate records, split the file at the joins",
                path.display(),
            ));
        }
    }
    (warnings, notes)
}
