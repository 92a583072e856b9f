//! Universal File Format dataset 58 (function at a node): time histories and spectra exported
//! by shaker controllers and modal acquisition systems, e.g. the VibControl PSD in
//! `data/realdata/pyuff-vibcontrol-psd`, in the ASCII form and the binary form 58b (text header,
//! IEEE values).
//!
//! Hand-written: no maintained Rust crate reads UFF (pyuff is Python). The layout follows the
//! SDRC/Siemens UFF58 description: 11 header records, then the data, in fixed-width fields
//! (ASCII) or as raw little- or big-endian floats (58b). Other datasets in the file are skipped
//! and listed.

mod cursor;
mod fortran;
mod header;

use crate::error::SignalError;
use cursor::Cursor;
use header::BinaryLayout;
pub use header::{Record6, function_type_name};
use std::path::{Path, PathBuf};

/// Data type, label and units label of one axis (UFF58 records 8-11).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct AxisInfo {
    /// 17 time, 18 frequency, 12 acceleration, 13 excitation force, 21 pressure, 0 unknown ...
    pub data_type: i64,
    /// What the axis is ("Acceleration"); empty for `NONE`.
    pub label: String,
    /// Its unit ("m/s2"); empty for `NONE`.
    pub unit: String,
}

/// One UFF58 record.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct UffRecord {
    /// Line of the `58` marker in the file (1-based).
    pub line: u64,
    /// Whether the values were stored in binary (58b).
    pub binary: bool,
    pub id1: String,
    /// The channel's name: ID line 4, else the response entity of record 6 (many exporters
    /// leave ID line 4 as `NONE`); empty when both are `NONE`.
    pub id4: String,
    /// Record 6: the function type and the response and reference entity, node, direction.
    #[serde(flatten)]
    pub function: Record6,
    /// 2 real single, 4 real double, 5 complex single, 6 complex double (record 7 field 1).
    pub ordinate_type: i64,
    /// The ordinate's units label (record 9), e.g. `m/s2`, `g`, `Pa`.
    pub ordinate_label: String,
    /// Record 8; its units label (`ms`, `kHz`) is kept as written, the abscissa below is
    /// converted from it.
    pub abscissa_axis: AxisInfo,
    pub ordinate_axis: AxisInfo,
    /// The ordinate denominator (record 10), e.g. the force of an FRF.
    pub denominator_axis: AxisInfo,
    /// The abscissa in seconds (a time axis) or hertz (a frequency axis), converted from the
    /// units label of record 8 (`ms`, `min`, `kHz`); as written when that label is `NONE`.
    pub abscissa: Vec<f64>,
    /// Real part (or the value of a real record).
    pub re: Vec<f64>,
    /// Imaginary part; empty for a real record.
    pub im: Vec<f64>,
    pub even_spacing: bool,
    /// Half the resolution of each abscissa value as written (an uneven record's x in ASCII:
    /// half a unit of its last digit, `4.88281e-04` ± 5e-10; in 58b single: half an f32 ulp),
    /// in the abscissa's unit after conversion. Empty when the abscissa is computed from record
    /// 7 or written as doubles.
    #[serde(skip)]
    pub abscissa_half_ulp: Vec<f64>,
    /// Why the abscissa's units label (record 8) is not read: the record is then left out
    /// (its spacing is unknown) while the file's other records are read.
    pub abscissa_unit_error: Option<String>,
}

impl UffRecord {
    pub fn is_complex(&self) -> bool {
        !self.im.is_empty()
    }

    /// Record 6's function type with its name, `function type 2 (auto spectrum)`, for
    /// messages about what the record holds.
    pub fn function_kind(&self) -> String {
        let t = self.function.function_type;
        format!("function type {t} ({})", function_type_name(t))
    }

    /// Spacing of an evenly spaced abscissa, or why it is not evenly spaced. Each step must be
    /// the mean step to 1e-6 relative, plus what the rounding of the written values allows: a
    /// step between two values each within half a unit of their last digit of the true one
    /// can be off by the sum of those halves (pyuff writes an uneven abscissa as `%13.5e`, six
    /// digits, so 1/2048 s steps read as 4.88281e-04, then 4.88280e-04 ...).
    pub fn spacing(&self) -> Result<f64, String> {
        if let Some(why) = &self.abscissa_unit_error {
            return Err(why.clone());
        }
        let x = &self.abscissa;
        let n = x.len();
        if n < 2 {
            return Err(format!(
                "the record holds {n} point(s): no abscissa spacing"
            ));
        }
        let d = (x[n - 1] - x[0]) / (n - 1) as f64;
        if d.is_nan() || d <= 0.0 {
            return Err("the abscissa does not increase".into());
        }
        let h = |k: usize| self.abscissa_half_ulp.get(k).copied().unwrap_or(0.0);
        // The mean step's own rounding, from the first and last values.
        let hd = (h(0) + h(n - 1)) / (n - 1) as f64;
        for (k, w) in x.windows(2).enumerate() {
            let step = w[1] - w[0];
            let dev = (step - d).abs();
            let allowed = 1e-6 * d + h(k) + h(k + 1) + hd;
            if dev > allowed {
                return Err(format!(
                    "the abscissa is not evenly spaced: the step from point {} (x = {}) to point \
                     {} (x = {}) is {step:e}, off the mean step {d:e} by {dev:e} ({:.3}%), more \
                     than the {allowed:e} the written digits of these values allow",
                    k + 1,
                    w[0],
                    k + 2,
                    w[1],
                    100.0 * dev / d
                ));
            }
        }
        Ok(d)
    }
}

/// The dataset-58 records of a file and the other datasets it skipped.
#[derive(Debug, Clone, PartialEq)]
pub struct UffFile {
    pub records: Vec<UffRecord>,
    /// (line of the marker, dataset number) of every dataset that is not 58.
    pub skipped: Vec<(u64, String)>,
}

impl UffFile {
    /// One stderr line naming the datasets skipped, if any.
    pub fn note(&self, file: &Path) -> Option<String> {
        if self.skipped.is_empty() {
            return None;
        }
        Some(format!(
            "{}: skipped UFF datasets {} (only dataset 58, a function at a node, is read)",
            file.display(),
            dataset_list(&self.skipped)
        ))
    }
}

fn err(file: &Path, line: u64, message: impl Into<String>) -> SignalError {
    SignalError::Uff {
        file: file.to_path_buf(),
        line,
        message: message.into(),
    }
}

/// Reads every dataset-58 record of a UFF file (ASCII or 58b).
pub fn read_uff58(path: &Path) -> Result<Vec<UffRecord>, SignalError> {
    read_uff(path).map(|f| f.records)
}

/// Reads a UFF file: its dataset-58 records and the list of datasets skipped.
pub fn read_uff(path: &Path) -> Result<UffFile, SignalError> {
    let bytes = std::fs::read(path).map_err(|e| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("cannot read: {e}"),
    })?;
    parse_uff(path, &bytes)
}

/// Parses UFF58 records from the bytes of a file named `path` (used in messages only).
pub fn parse_uff58(path: &Path, bytes: &[u8]) -> Result<Vec<UffRecord>, SignalError> {
    parse_uff(path, bytes).map(|f| f.records)
}

/// Parses a whole UFF file: datasets are delimited by `-1` lines; the line after a delimiter
/// names the dataset.
pub fn parse_uff(path: &Path, bytes: &[u8]) -> Result<UffFile, SignalError> {
    let file: PathBuf = path.to_path_buf();
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(SignalError::EmptyFile { file });
    }
    let mut cur = Cursor::new(bytes);
    let mut out = UffFile {
        records: Vec::new(),
        skipped: Vec::new(),
    };
    while let Some(l) = cur.next_line() {
        if l.trim() != "-1" {
            check_text(&file, cur.line() - 1, &l)?;
            continue;
        }
        let marker_line = cur.line();
        let Some(kind) = cur.next_line() else {
            break;
        };
        let kind_word = kind.split_whitespace().next().unwrap_or("").to_string();
        match kind_word.as_str() {
            "-1" => continue,
            "58" => out
                .records
                .push(parse_record(&file, &mut cur, marker_line, None)?),
            "58b" => {
                let layout = header::binary_layout(&file, marker_line, &kind)?;
                out.records
                    .push(parse_record(&file, &mut cur, marker_line, Some(layout))?);
            }
            other if other.ends_with('b') => {
                // A foreign binary dataset cannot be skipped line by line.
                return Err(err(
                    &file,
                    marker_line,
                    format!("binary dataset {other}: only datasets 58 and 58b are read"),
                ));
            }
            other => {
                out.skipped.push((marker_line, other.to_string()));
                skip_dataset(&mut cur);
            }
        }
    }
    if out.records.is_empty() {
        let found = if out.skipped.is_empty() {
            "no dataset".to_string()
        } else {
            format!("datasets {} only", dataset_list(&out.skipped))
        };
        return Err(err(
            &file,
            1,
            format!(
                "no dataset 58 found ({found}; expected a line `    -1` then `    58` or `    58b`): export the time histories, spectra or FRFs as UFF58"
            ),
        ));
    }
    Ok(out)
}

/// The dataset numbers, each once, in file order.
fn dataset_list(skipped: &[(u64, String)]) -> String {
    let mut kinds: Vec<&str> = Vec::new();
    for (_, k) in skipped {
        if !kinds.contains(&k.as_str()) {
            kinds.push(k);
        }
    }
    kinds.join(", ")
}

/// Refuses a NUL byte outside a 58b data block: such a file is not UFF text.
fn check_text(file: &Path, line: u64, text: &str) -> Result<(), SignalError> {
    if text.contains('\0') {
        return Err(err(
            file,
            line,
            "binary content outside a 58b data block: not a UFF file",
        ));
    }
    Ok(())
}

/// Moves past the closing `-1` of a dataset that is not read.
fn skip_dataset(cur: &mut Cursor) {
    while let Some(l) = cur.next_line() {
        if l.trim() == "-1" {
            break;
        }
    }
}

/// Reads the 11 header lines and the data of one dataset 58 (ASCII) or 58b (`binary`).
fn parse_record(
    file: &Path,
    cur: &mut Cursor,
    marker: u64,
    binary: Option<BinaryLayout>,
) -> Result<UffRecord, SignalError> {
    let first = cur.line();
    let mut head: Vec<String> = Vec::with_capacity(11);
    for _ in 0..11 {
        let l = cur.next_line().ok_or_else(|| {
            err(
                file,
                cur.line(),
                format!(
                    "file ends inside the UFF58{} header",
                    if binary.is_some() { "b" } else { "" }
                ),
            )
        })?;
        head.push(l);
    }
    let line_of = |k: usize| first + k as u64;
    let id1 = head[0].trim().to_string();
    let id4 = head[3].trim().to_string();
    let r6 = header::record6(file, line_of(5), &head[5])?;
    let r7 = header::record7(file, line_of(6), &head[6])?;
    let abscissa_axis = header::axis(&head[7]);
    let ordinate_axis = header::axis(&head[8]);
    let denominator_axis = header::axis(&head[9]);
    let name = if id4.is_empty() || id4.eq_ignore_ascii_case("none") {
        r6.response_entity.clone()
    } else {
        id4
    };
    let complex = matches!(r7.ordinate_type, 5 | 6);
    if complex && r6.function_type == 1 {
        // Keeping the real part alone would drop half of what was written without a word.
        return Err(err(
            file,
            line_of(6),
            format!(
                "the record at line {marker} is a time history (record 6 function type 1) with \
                 complex values (record 7 ordinate data type {}): a measured time history is \
                 real, and which part of a complex one is the signal is not defined; export it \
                 as real values (ordinate data type 2, single, or 4, double)",
                r7.ordinate_type
            ),
        ));
    }
    // Values per point in the data block.
    let per_point = usize::from(!r7.even) + if complex { 2 } else { 1 };
    let need = r7
        .points
        .checked_mul(per_point)
        .ok_or_else(|| err(file, line_of(6), "number of data values overflows"))?;
    let (values, half_ulp) = match binary {
        None => ascii_values(file, cur, need, &r7, line_of(6))?,
        Some(layout) => binary_values(file, cur, need, &r7, layout, marker)?,
    };
    let (mut abscissa, re, im) = split_points(&values, &r7, complex);
    // Rounding of the written abscissa values, for the spacing check.
    let mut abscissa_half_ulp: Vec<f64> = if r7.even || half_ulp.is_empty() {
        Vec::new()
    } else {
        half_ulp.iter().step_by(per_point).copied().collect()
    };
    // The abscissa is kept in seconds (time) or hertz (frequency), whatever record 8 wrote.
    let (scale, abscissa_unit_error) = match abscissa_scale(&abscissa_axis, line_of(7)) {
        Ok(scale) => (scale, None),
        Err(why) => (1.0, Some(why)),
    };
    if scale != 1.0 {
        abscissa.iter_mut().for_each(|x| *x *= scale);
        abscissa_half_ulp.iter_mut().for_each(|h| *h *= scale);
    }
    if !r7.even && abscissa.windows(2).any(|w| w[1] <= w[0]) {
        return Err(err(file, marker, "the abscissa does not increase"));
    }
    Ok(UffRecord {
        line: marker,
        binary: binary.is_some(),
        id1,
        id4: name,
        function: r6,
        ordinate_type: r7.ordinate_type,
        ordinate_label: ordinate_axis.unit.clone(),
        abscissa_axis,
        ordinate_axis,
        denominator_axis,
        abscissa,
        re,
        im,
        even_spacing: r7.even,
        abscissa_half_ulp,
        abscissa_unit_error,
    })
}

/// Seconds (time) or hertz (frequency) per unit of the abscissa's units label (record 8):
/// s, ms, µs, ns, min, h, or Hz, kHz; 1 when the label is `NONE` or blank (the SDRC default,
/// seconds or hertz). A label that is none of these is why the record is not read (see
/// [`UffRecord::spacing`]), never taken as seconds: a time axis in `ms` read as seconds puts
/// every frequency 1000 times too low.
fn abscissa_scale(axis: &AxisInfo, line: u64) -> Result<f64, String> {
    let label = axis.unit.trim();
    if label.is_empty() {
        return Ok(1.0);
    }
    let scale = match label.to_lowercase().as_str() {
        "s" | "sec" | "secs" | "second" | "seconds" => 1.0,
        "ms" | "msec" | "msecs" | "millisecond" | "milliseconds" => 1e-3,
        "us" | "µs" | "μs" | "usec" | "usecs" | "microsecond" | "microseconds" => 1e-6,
        "ns" | "nsec" | "nanosecond" | "nanoseconds" => 1e-9,
        "min" | "mins" | "minute" | "minutes" => 60.0,
        "h" | "hr" | "hrs" | "hour" | "hours" => 3600.0,
        "hz" | "1/s" => 1.0,
        "khz" => 1e3,
        _ => {
            return Err(format!(
                "record 8 (the abscissa, line {line}) gives the units label `{label}`, which is not a \
                     time unit (s, ms, us, ns, min, h) or a frequency unit (Hz, kHz): the \
                     abscissa is not read as seconds on a guess; export the record with its \
                     abscissa in one of these units"
            ));
        }
    };
    Ok(scale)
}

/// Half a unit of the last digit written in a number token: `4.88281e-04` gives 5e-10,
/// `12.5` 0.05, `3` 0.5, Fortran's `0.12345-100` 5e-106.
fn token_half_ulp(tok: &str) -> f64 {
    let (mantissa, exponent) = fortran::split(tok).unwrap_or((tok, 0));
    let decimals = mantissa.split_once('.').map_or(0, |(_, f)| f.len() as i32);
    0.5 * 10f64.powi(exponent - decimals)
}

/// ASCII data: numbers up to the closing `-1`, exactly `need` of them, in the fields of the
/// format record 7 declares (see [`fortran`]); for an abscissa written point by point, also
/// half a unit of the last written digit of each (see [`token_half_ulp`]).
fn ascii_values(
    file: &Path,
    cur: &mut Cursor,
    need: usize,
    r7: &header::Record7,
    record7_line: u64,
) -> Result<(Vec<f64>, Vec<f64>), SignalError> {
    let (points, resolution, ordinate_type) = (r7.points, !r7.even, r7.ordinate_type);
    let (widths, format) = fortran::line_format(ordinate_type, r7.even);
    let mut values: Vec<f64> = Vec::with_capacity(need.min(1 << 24));
    let mut half_ulp: Vec<f64> = Vec::new();
    let first_data_line = cur.line();
    let mut last_data_line = first_data_line;
    loop {
        let line_no = cur.line();
        let Some(l) = cur.next_line() else {
            let short = if values.len() < need {
                format!(
                    ": the file ends inside it, after {} of the {need} values record 7 (line \
                     {record7_line}) announces; the file is cut short",
                    values.len()
                )
            } else {
                String::new()
            };
            return Err(err(
                file,
                line_no.saturating_sub(1).max(1),
                format!("dataset 58 is not closed by `-1`{short}"),
            ));
        };
        if l.trim() == "-1" {
            break;
        }
        check_text(file, line_no, &l)?;
        last_data_line = line_no;
        let tokens = fortran::tokens(&l, widths).map_err(|bad| {
            err(
                file,
                line_no,
                format!(
                    "field {} (columns {}–{}): cannot parse `{}` as a number (the data lines \
                     of ordinate data type {ordinate_type} are {format}, read at blanks or, \
                     where fields touch, by column)",
                    bad.field, bad.columns.0, bad.columns.1, bad.text
                ),
            )
        })?;
        for (tok, v) in tokens {
            if !v.is_finite() {
                return Err(err(file, line_no, format!("non-finite value `{tok}`")));
            }
            values.push(v);
            if resolution {
                half_ulp.push(token_half_ulp(tok));
            }
        }
    }
    if values.len() != need {
        return Err(err(
            file,
            record7_line,
            format!(
                "this header line (record 7, the data form) announces {points} points ({need} \
                 values), but the data block below it (lines {first_data_line}–{}) holds {}",
                last_data_line,
                values.len()
            ),
        ));
    }
    Ok((values, half_ulp))
}

/// 58b data: `layout.bytes` raw IEEE values (single for ordinate types 2 and 5, double for 4
/// and 6), then the closing `-1`; for single values, also half an f32 ulp of each.
fn binary_values(
    file: &Path,
    cur: &mut Cursor,
    need: usize,
    r7: &header::Record7,
    layout: BinaryLayout,
    marker: u64,
) -> Result<(Vec<f64>, Vec<f64>), SignalError> {
    let width = if matches!(r7.ordinate_type, 2 | 5) {
        4
    } else {
        8
    };
    let expected = need.saturating_mul(width);
    if layout.bytes != expected {
        return Err(err(
            file,
            marker,
            format!(
                "58b announces {} data bytes, but record 7 ({} points of ordinate type {}) needs {expected}",
                layout.bytes, r7.points, r7.ordinate_type
            ),
        ));
    }
    let at = cur.line();
    let block = cur.take(layout.bytes).ok_or_else(|| {
        err(
            file,
            at,
            format!(
                "file ends inside the 58b data block of {} bytes",
                layout.bytes
            ),
        )
    })?;
    let mut values = Vec::with_capacity(need);
    for chunk in block.chunks_exact(width) {
        let v = match (width, layout.little_endian) {
            (4, true) => f32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]) as f64,
            (4, false) => f32::from_be_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]) as f64,
            (_, true) => f64::from_le_bytes(chunk.try_into().unwrap_or([0; 8])),
            (_, false) => f64::from_be_bytes(chunk.try_into().unwrap_or([0; 8])),
        };
        if !v.is_finite() {
            return Err(err(
                file,
                marker,
                format!("58b value {} is not finite", values.len() + 1),
            ));
        }
        values.push(v);
    }
    // f64 rounding is below the 1e-6 relative of the spacing check; f32's is not.
    let half_ulp: Vec<f64> = if width == 4 && !r7.even {
        values.iter().map(|&v| half_f32_ulp(v)).collect()
    } else {
        Vec::new()
    };
    cur.finish_binary_line();
    let close = cur.line();
    match cur.next_line() {
        Some(l) if l.trim() == "-1" => Ok((values, half_ulp)),
        _ => Err(err(
            file,
            close,
            "the 58b data block is not followed by `-1` (byte count of the 58b line wrong?)",
        )),
    }
}

/// Half the distance from an f32 value to the next one away from zero.
fn half_f32_ulp(v: f64) -> f64 {
    let a = (v as f32).abs();
    let next = f32::from_bits(a.to_bits().saturating_add(1));
    if next.is_finite() {
        0.5 * f64::from(next - a)
    } else {
        0.0
    }
}

/// Splits the data block into abscissa, real and imaginary parts.
fn split_points(
    values: &[f64],
    r7: &header::Record7,
    complex: bool,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let per_point = usize::from(!r7.even) + if complex { 2 } else { 1 };
    let n = values.len() / per_point;
    let mut abscissa = Vec::with_capacity(n);
    let mut re = Vec::with_capacity(n);
    let mut im = Vec::with_capacity(if complex { n } else { 0 });
    for (k, chunk) in values.chunks_exact(per_point).enumerate() {
        let mut c = chunk.iter();
        let x = if r7.even {
            r7.x0 + k as f64 * r7.dx
        } else {
            *c.next().unwrap_or(&0.0)
        };
        abscissa.push(x);
        re.push(*c.next().unwrap_or(&0.0));
        if complex {
            im.push(*c.next().unwrap_or(&0.0));
        }
    }
    (abscissa, re, im)
}

/// The channel name of each record, unique within the file: ID line 4, else record 6's
/// response entity, else `record k`. Records sharing a name (a roving test names every record
/// by its test case) gain their response node and direction, `TestCase:3:+Z`, as modal tests
/// name their points, and `(record k)` if that is still not unique: a selection by name must
/// never pick one of several records silently.
pub fn channel_names(records: &[UffRecord]) -> Vec<String> {
    let base: Vec<String> = records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            if r.id4.is_empty() {
                format!("record {}", i + 1)
            } else {
                r.id4.clone()
            }
        })
        .collect();
    let count = |names: &[String], n: &str| names.iter().filter(|m| *m == n).count();
    let pointed: Vec<String> = base
        .iter()
        .zip(records)
        .map(|(b, r)| {
            if count(&base, b) > 1 {
                format!("{b}:{}", point_label(&r.function))
            } else {
                b.clone()
            }
        })
        .collect();
    pointed
        .iter()
        .enumerate()
        .map(|(i, n)| {
            if count(&pointed, n) > 1 {
                format!("{n} (record {})", i + 1)
            } else {
                n.clone()
            }
        })
        .collect()
}

/// `node:direction` of a record's response (`12:+Z`, `4:-RX`; the node alone for a scalar).
fn point_label(r6: &Record6) -> String {
    point(r6.response_node, r6.response_direction)
}

/// `node:direction` of a point with its UFF direction code (1..6 = ±X, Y, Z, RX, RY, RZ).
pub fn point(node: i64, direction: i64) -> String {
    const AXES: [&str; 6] = ["X", "Y", "Z", "RX", "RY", "RZ"];
    match AXES.get((direction.unsigned_abs() as usize).wrapping_sub(1)) {
        Some(axis) => format!("{node}:{}{axis}", if direction < 0 { "-" } else { "+" }),
        None => node.to_string(),
    }
}

/// Whether a record of abscissa step `step` (s) is sampled at `fs` (Hz), to the 1e-6 that the
/// E13.5 fields of record 7 carry.
pub fn same_rate(fs: f64, step: f64) -> bool {
    (fs * step - 1.0).abs() <= 1e-6
}

/// Whether a file looks like UFF (first non-blank line is the `-1` delimiter).
pub fn looks_like_uff(path: &Path) -> bool {
    use std::io::Read;
    let mut buf = [0u8; 256];
    let Ok(mut f) = std::fs::File::open(path) else {
        return false;
    };
    let n = f.read(&mut buf).unwrap_or(0);
    let s = String::from_utf8_lossy(&buf[..n]);
    s.lines()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|l| l.trim() == "-1")
}

/// The unit of a record's channel: a `--units` entry for the channel wins, then the record's
/// units field (an acceleration unit [`Unit::parse`] knows; volts are kept, see
/// [`crate::signal::ingest::unit::is_electrical`]), then the default unit of the read.
pub(crate) fn ordinate_unit(
    label: &str,
    ingest: &crate::signal::ingest::IngestOptions,
    name: &str,
) -> crate::signal::ingest::Unit {
    use crate::signal::ingest::Unit;
    if let Some((_, u)) = ingest.channel_units.iter().find(|(n, _)| n == name) {
        return *u;
    }
    match Unit::parse(label).ok().or_else(|| density_unit(label)) {
        Some(unit) if unit != Unit::AsIs => unit,
        // Volts become g only through a sensitivity the record does not give.
        _ if crate::signal::ingest::unit::is_electrical(label) => Unit::AsIs,
        _ => ingest.default_unit.unwrap_or(Unit::AsIs),
    }
}

/// The notes for the records `psd` and `srs` read whose units field states volts: kept in
/// them while `--units` gives one unit for all, or read unchanged as the acceleration
/// `--units NAME=UNIT` names (`named`: channel name and record).
pub(crate) fn electrical_notes(
    named: &[(&String, &UffRecord)],
    ingest: &crate::signal::ingest::IngestOptions,
) -> Vec<String> {
    named
        .iter()
        .filter_map(|(name, r)| {
            let label = &r.ordinate_label;
            let read_as = ordinate_unit(label, ingest, name);
            let is_named = ingest.channel_units.iter().any(|(n, _)| n == *name);
            crate::signal::ingest::unit::volts_note(
                name,
                label,
                read_as,
                is_named,
                ingest.default_unit,
            )
        })
        .collect()
}

/// The unit of a spectral density's label, the unit squared per hertz as controllers write it
/// (`g^2/Hz`, `(m/s2)^2/Hz`, VibControl's `gM-2/Hz`): the longest start of the squared part
/// that is a unit.
fn density_unit(label: &str) -> Option<crate::signal::ingest::Unit> {
    let lower = label.trim().to_lowercase();
    let squared = lower.strip_suffix("/hz")?.trim_start_matches('(');
    let ends = squared.char_indices().map(|(i, _)| i).skip(1);
    let mut starts: Vec<&str> = ends.map(|i| &squared[..i]).collect();
    starts.push(squared);
    starts
        .iter()
        .rev()
        .find_map(|s| crate::signal::ingest::Unit::parse(s).ok())
}

#[cfg(test)]
mod tests {
    use super::{Record6, density_unit, half_f32_ulp, parse_uff58, point_label, token_half_ulp};
    use std::path::Path;

    /// Records 1-11 of a record of ordinate type `r7` (its record 7 line) as a catman export
    /// writes them: a time history in g, its abscissa in s.
    fn catman_header(r7: &str) -> String {
        format!(
            "    -1\n    58\ncatman\nNONE\nNONE\nAcc 1\nNONE\n\
             {:5}{:10}{:5}{:10} {:<10}{:10}{:4} {:<10}{:10}{:4}\n{r7}\n\
             {:>10}    0    0    0 Time                 s                   \n\
             {:>10}    0    0    0 Acceleration         g                   \n\
             {:>10}    0    0    0 NONE                 NONE                \n\
             {:>10}    0    0    0 NONE                 NONE                \n",
            1, 0, 0, 0, "Acc 1", 1, 3, "NONE", 0, 0, 17, 12, 0, 0
        )
    }

    /// E13.5 fields as old Fortran and C writers leave them (the UFF58 description's `6E13.5`
    /// for ordinate type 2): Fortran's `0.12345-100` (the `E` dropped for a three-digit
    /// exponent) and C's `-1.23456e-100`, which fills its 13 columns and touches the field
    /// before it. Each value must be the decimal written, to the f64 nearest it (exact).
    #[test]
    fn three_digit_exponents_read_in_their_e13_5_fields() {
        let text =
            catman_header("         2         8         1  0.00000E+00  0.10000E-02  0.00000E+00")
                + "  0.12345E+01  0.12345-100 -0.54321-101  0.10000E+00-1.23456e-100-2.50000e-100\n"
                + "  0.50000E+00  0.25000E+00\n    -1\n";
        let r = &parse_uff58(Path::new("catman.uff"), text.as_bytes()).unwrap()[0];
        let want = [
            1.2345,
            0.12345e-100,
            -0.54321e-101,
            0.1,
            -1.23456e-100,
            -2.5e-100,
            0.5,
            0.25,
        ];
        assert_eq!(r.re, want);
        // A field that is no number is named by its line (the first data line is 14), its
        // place and its columns.
        let bad = text.replace("  0.12345-100", "  0.1234x-100");
        let e = parse_uff58(Path::new("catman.uff"), bad.as_bytes()).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("catman.uff: line 14: field 2 (columns 14–26): cannot parse `0.1234x-100` as a number (the data lines of ordinate data type 2 are 6E13.5"),
            "{e}"
        );
    }

    /// Ordinate type 4 with an uneven abscissa is `2(E13.5,E20.12)`: a 20-column double
    /// `-1.500000000000e-100` touches the abscissa before it.
    #[test]
    fn touching_double_fields_read_by_their_columns() {
        let text =
            catman_header("         4         3         0  0.00000E+00  0.00000E+00  0.00000E+00")
                + "  0.00000e+00-1.500000000000e-100  1.00000e-03  2.500000000000e+00\n"
                + "  2.00000e-03-3.250000000000e-101\n    -1\n";
        let r = &parse_uff58(Path::new("d.uff"), text.as_bytes()).unwrap()[0];
        assert_eq!(r.abscissa, [0.0, 1e-3, 2e-3]);
        assert_eq!(r.re, [-1.5e-100, 2.5, -3.25e-101]);
    }

    /// Half a unit of the last written digit, by construction of the decimal forms: six
    /// digits at 1e-4 (`%13.5e` of 1/2048 s) resolve 1e-9, so half of it is 5e-10.
    #[test]
    fn a_written_number_rounds_by_half_its_last_digit() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b;
        assert!(close(token_half_ulp("4.88281e-04"), 5e-10));
        assert!(close(token_half_ulp("-1.03675257619E+01"), 5e-11));
        assert!(close(token_half_ulp("1.5D-3"), 5e-5));
        assert!(close(token_half_ulp("12.5"), 0.05));
        assert!(close(token_half_ulp("3"), 0.5));
        // f32 has 24 significant bits: at 1.0 the next value is 2^-23 above.
        assert_eq!(half_f32_ulp(1.0), 0.5 * 2f64.powi(-23));
        assert_eq!(half_f32_ulp(-1.0), 0.5 * 2f64.powi(-23));
    }

    /// Record 6's direction code (UFF58: 1–3 translations X, Y, Z, 4–6 rotations, negative for
    /// the minus direction, 0 scalar) written as a modal test names its points.
    #[test]
    fn a_point_is_its_node_and_signed_direction() {
        let r6 = |node, dir| Record6 {
            function_type: 1,
            response_entity: String::new(),
            response_node: node,
            response_direction: dir,
            reference_entity: String::new(),
            reference_node: 0,
            reference_direction: 0,
        };
        assert_eq!(point_label(&r6(12, 3)), "12:+Z");
        assert_eq!(point_label(&r6(4, -4)), "4:-RX");
        assert_eq!(point_label(&r6(7, 0)), "7");
        assert_eq!(point_label(&r6(7, 9)), "7");
    }

    /// A PSD record's units field is its unit squared per hertz.
    #[test]
    fn a_density_label_gives_its_squared_unit() {
        use crate::signal::ingest::Unit;
        assert_eq!(density_unit("gM-2/Hz"), Some(Unit::G));
        assert_eq!(density_unit("g^2/Hz"), Some(Unit::G));
        assert_eq!(density_unit("(m/s2)^2/Hz"), Some(Unit::MPerS2));
        assert_eq!(density_unit("mg²/Hz"), Some(Unit::MilliG));
        assert_eq!(density_unit("Pa^2/Hz"), None);
        assert_eq!(density_unit("g"), None);
    }
}
