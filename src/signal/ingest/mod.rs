//! CSV log ingest, streamed: one row at a time goes to a caller's sink, so memory does not grow
//! with the file. Input: a text CSV whose header names the channels, with a time column
//! (`time`, `time_s`, `t`, ...) or a sampling rate given by the caller.
//!
//! The reader checks, and reports with file, line and column: binary content, empty files,
//! header-only files, unnamed or duplicate columns, ragged rows, cells that are not finite
//! numbers, a time column that does not increase, and one with a gap. Jittered timestamps are
//! read at their mean step and the jitter reported; with `resample` a log is interpolated onto
//! a uniform grid (anti-aliased onto another rate) and that is reported (`timing.rs`).
//!
//! Rows are read in 4 MiB blocks cut at newlines, and each block is split into pieces parsed in
//! parallel (rayon), handed on in file order: memory stays flat and errors come out exactly as
//! a sequential reader would give them. Plain numeric rows are split on commas with `memchr`;
//! a block holding a quote goes through the `csv` crate. A quoted field with an embedded
//! newline is not supported (numeric logs have none). Numbers are parsed by `fast-float2`.

pub mod bandlimit;
pub mod clock;
pub mod freq_table;
pub mod iso8601;
mod plausible_rate;
mod preamble_rate;
mod preamble_unit;
pub mod sniff;
pub mod text;
mod time_unit;
mod timing;
mod trailer;
pub mod unit;

use crate::error::SignalError;
pub use bandlimit::AntiAliasReport;
pub use plausible_rate::plausible_rate;
use sniff::{Delimiter, Dialect};
use std::io::Read;
use std::path::{Path, PathBuf};
pub use time_unit::{TimeUnit, time_column_unit};
pub use timing::{FS_AGREEMENT, JITTER_LIMIT, JitterReport};
use timing::{Timing, TimingOutcome};
pub use unit::Unit;

/// Where a channel's unit came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum UnitSource {
    Name,
    Option,
    Default,
}

/// How to read a log.
#[derive(Debug, Clone, PartialEq)]
pub struct IngestOptions {
    /// Channels to keep, in this order; `None` keeps every non-time column.
    pub channels: Option<Vec<String>>,
    /// Sampling rate, Hz. Required without a time column; with one, it must agree.
    pub fs: Option<f64>,
    /// Unit for every channel whose name does not state one.
    pub default_unit: Option<Unit>,
    /// Per-channel units, overriding the name.
    pub channel_units: Vec<(String, Unit)>,
    /// Interpolate a non-uniform time column onto a uniform grid instead of failing.
    pub resample: bool,
    /// Resample onto this rate, Hz, through an anti-alias low-pass (implies `resample`).
    pub resample_fs: Option<f64>,
    /// Allowed departure of one time step from the sampling interval, as a fraction of it.
    pub jitter_tolerance: f64,
    /// Column names for a headerless file (or replacing the header's).
    pub columns: Option<Vec<String>>,
    /// Unit of the time column when its name does not state one.
    pub time_unit: Option<TimeUnit>,
    /// `fs` wins over a time column that disagrees with it (the time column is then ignored).
    pub fs_override: bool,
    /// Where `fs` came from, as messages name it: `--fs` on the command line, `fs_hz` in a
    /// scene's `[[test_log]]` (which has no override).
    pub fs_name: &'static str,
    /// Most spectral lines, counted from 0 Hz, a PSD record read from a file may span
    /// (`--max-psd-lines`; default [`crate::signal::logpsd::MAX_PSD_LINES`]).
    pub max_psd_lines: usize,
}

/// The given rate `fs` disagrees with what the file states (`stated`: "the time column of F,
/// which gives X Hz"): an error naming where `fs` came from (`fs_name`, see
/// [`IngestOptions::fs_name`]) and the cure there (the command line can override the file; a
/// scene's `fs_hz` cannot).
pub fn fs_disagrees(name: &str, fs: f64, stated: &str) -> SignalError {
    let cure = if name == "--fs" {
        "drop --fs, or pass --fs-override to use --fs".to_string()
    } else {
        format!("remove {name}: the file states its own rate")
    };
    SignalError::BadParameter {
        name: "fs",
        value: fs.to_string(),
        reason: format!(
            "{name} {fs} Hz disagrees with {stated} (more than {}%); {cure}",
            FS_AGREEMENT * 100.0
        ),
    }
}

impl Default for IngestOptions {
    fn default() -> Self {
        IngestOptions {
            channels: None,
            fs: None,
            default_unit: None,
            channel_units: Vec::new(),
            resample: false,
            resample_fs: None,
            jitter_tolerance: 0.01,
            columns: None,
            time_unit: None,
            fs_override: false,
            fs_name: "--fs",
            max_psd_lines: crate::signal::logpsd::MAX_PSD_LINES,
        }
    }
}

/// One channel of a log.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ChannelInfo {
    pub name: String,
    /// Unit in the file.
    pub unit: Unit,
    pub unit_source: UnitSource,
    /// Index of the column in the file (0-based).
    pub column: usize,
    /// For a channel kept as it is, the unit the file states for it (`N`, `Pa`, `V`): its
    /// values are in that unit. Empty when converted or when the file states none.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub unit_label: String,
    /// The unit text the file states for the channel, whatever unit it is read in (for the
    /// notes on volts read as an acceleration).
    #[serde(skip)]
    pub stated_label: String,
}

impl ChannelInfo {
    /// The unit of the channel's values as results state it: g for an acceleration, the
    /// file's own unit for a channel kept as it is, `as-is` when the file states none.
    pub fn reported_unit(&self) -> String {
        self.unit.reported_with(&self.unit_label)
    }
}

/// What resampling did to a non-uniform log.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ResampleReport {
    pub uniform_dt_s: f64,
    /// Rows whose step departed from the interval by more than the tolerance.
    pub irregular_rows: u64,
    /// First such row (line number in the file).
    pub first_irregular_line: u64,
    pub largest_step_s: f64,
    pub input_rows: u64,
    pub output_samples: u64,
    /// The low-pass applied when resampling onto another rate.
    pub anti_alias: Option<AntiAliasReport>,
}

/// Description of a log once read.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LogInfo {
    pub file: PathBuf,
    pub channels: Vec<ChannelInfo>,
    pub time_column: Option<String>,
    pub fs_hz: f64,
    pub samples: u64,
    pub resampled: Option<ResampleReport>,
    pub ingest: IngestRecord,
}

/// The decisions the reader made about the file's dialect.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IngestRecord {
    pub delimiter: &'static str,
    pub decimal: &'static str,
    /// Lines before the data that are neither the header, the units row nor blank.
    pub skipped_lines: u64,
    pub time_column: Option<String>,
    pub time_unit: Option<TimeUnit>,
    /// Columns not read: empty throughout, or metadata filled only at the top.
    pub ignored_columns: Vec<String>,
    /// Metadata columns holding one value, e.g. a sample rate.
    pub metadata: Vec<(String, f64)>,
    /// Steps of the time column varying around their mean, when they do.
    pub jitter: Option<JitterReport>,
    /// One line per decision that departs from a plain comma CSV, for stderr.
    #[serde(skip)]
    pub notes: Vec<String>,
    /// What the file says is wrong with it; printed as warnings and kept in the JSON.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// A log held in memory: `data[c]` is channel `c`, already converted to its reported unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Log {
    pub info: LogInfo,
    pub data: Vec<Vec<f64>>,
}

impl Log {
    pub fn channel(&self, name: &str) -> Result<&[f64], SignalError> {
        self.info
            .channels
            .iter()
            .position(|c| c.name == name)
            .map(|i| self.data[i].as_slice())
            .ok_or_else(|| SignalError::NoSuchChannel {
                file: self.info.file.clone(),
                name: name.to_string(),
                available: self
                    .info
                    .channels
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }
}

/// Whether a header names a time column.
pub fn is_time_column(name: &str) -> bool {
    time_column_unit(name).is_some()
}

/// Reads the first bytes to refuse binary files before the CSV parser sees them, and tells
/// the text encoding (the bytes checked are the decoded ones).
fn sniff(path: &Path) -> Result<text::TextForm, SignalError> {
    let (reader, form) = text::open(path).map_err(|e| io_error(path, e))?;
    let mut buf = Vec::new();
    reader
        .take(8192)
        .read_to_end(&mut buf)
        .map_err(|e| io_error(path, e))?;
    if buf.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(SignalError::EmptyFile {
            file: path.to_path_buf(),
        });
    }
    if let Some(offset) = buf
        .iter()
        .position(|&b| b == 0 || (b < 0x20 && !matches!(b, b'\n' | b'\r' | b'\t')))
    {
        return Err(SignalError::BinaryFile {
            file: path.to_path_buf(),
            offset,
            byte: buf[offset],
        });
    }
    if let Err(e) = std::str::from_utf8(&buf) {
        // A multi-byte character cut by the 8 KiB sniff window is not binary content.
        if e.error_len().is_some() {
            let offset = e.valid_up_to();
            return Err(SignalError::BinaryFile {
                file: path.to_path_buf(),
                offset,
                byte: buf[offset],
            });
        }
    }
    Ok(form)
}

fn io_error(path: &Path, e: std::io::Error) -> SignalError {
    SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("cannot read: {e}"),
    }
}

fn parse_cell(bytes: &[u8], decimal_comma: bool) -> Option<f64> {
    let t = bytes.trim_ascii();
    let v: f64 = if decimal_comma && t.contains(&b',') {
        let fixed: Vec<u8> = t
            .iter()
            .map(|&b| if b == b',' { b'.' } else { b })
            .collect();
        fast_float2::parse(&fixed).ok()?
    } else {
        fast_float2::parse(t).ok()?
    };
    v.is_finite().then_some(v)
}

fn bad_cell(file: &Path, line: u64, column: &str, bytes: &[u8]) -> SignalError {
    let text = String::from_utf8_lossy(bytes.trim_ascii()).into_owned();
    let lower = text.to_ascii_lowercase();
    let what = if text.is_empty() {
        "empty cell (a column that stops before the others, as a slower channel group does, is \
         left out by naming the other channels with --channels)"
    } else if lower.contains("nan") {
        "not a number"
    } else if lower.contains("inf") || fast_float2::parse::<f64, _>(text.as_bytes()).is_ok() {
        "non-finite value"
    } else {
        "cannot parse number"
    };
    SignalError::BadCell {
        file: file.to_path_buf(),
        line,
        column: column.to_string(),
        text,
        what,
    }
}

/// Streams a CSV log: calls `sink` with one row of the selected channels (converted to their
/// reported unit) per uniform sample, and returns the log's description.
pub fn stream_csv(
    path: &Path,
    opts: &IngestOptions,
    mut sink: impl FnMut(&[f64]),
) -> Result<LogInfo, SignalError> {
    let form = sniff(path)?;
    let fpath = path.to_path_buf();
    let dialect = read_dialect(path)?;
    let plan = plan_columns(&fpath, &dialect, opts)?;
    let (text_reader, _) = text::open(path).map_err(|e| io_error(path, e))?;
    let mut reader = std::io::BufReader::with_capacity(1 << 16, text_reader);
    // The data offset is in the decoded text, so the preamble is read through, not sought.
    std::io::copy(
        &mut (&mut reader).take(dialect.data_offset as u64),
        &mut std::io::sink(),
    )
    .map_err(|e| io_error(path, e))?;
    let header = plan.header.clone();
    let time_col = plan.time_col;
    let selected = plan.selected.clone();
    let channels = plan.channels.clone();
    let factors: Vec<f64> = channels.iter().map(|c| c.unit.to_report_factor()).collect();
    let ncols = header.len();
    let mut slots: Vec<Option<(usize, f64)>> = vec![None; ncols];
    let off = usize::from(time_col.is_some());
    if let Some(tc) = time_col {
        slots[tc] = Some((0, plan.time_unit.map_or(1.0, TimeUnit::seconds)));
    }
    for (k, &c) in selected.iter().enumerate() {
        slots[c] = Some((off + k, factors[k]));
    }
    let iso_time = iso_origin(&fpath, &dialect, time_col, plan.time_unit)?;
    let layout = RowLayout {
        file: fpath.clone(),
        header: header.clone(),
        slots,
        width: off + selected.len(),
        delim: dialect.delimiter.byte(),
        whitespace: dialect.delimiter == Delimiter::Whitespace,
        decimal_comma: dialect.decimal_comma,
        iso_time,
    };
    let opts = &IngestOptions {
        fs: opts.fs.or(plan.fs_from_metadata),
        ..opts.clone()
    };
    let mut rows: u64 = 0;
    let mut timing = Timing::new(opts, fpath.clone());
    let mut midnight = MidnightCrossing::new(&dialect, layout.iso_time);
    let mut feed = |vals: &[f64], lines: &[u64]| -> Result<(), SignalError> {
        let w = layout.width;
        for (row, &line) in vals.chunks_exact(w).zip(lines) {
            rows += 1;
            if time_col.is_some() {
                let t = midnight.count_on(row[0], line);
                timing.push(t, line, &row[1..], &mut sink)?;
            } else {
                sink(row);
            }
        }
        Ok(())
    };
    // Small files get a buffer of their own size, not a whole block.
    let size = std::fs::metadata(path).map_or(BLOCK_BYTES as u64, |m| m.len());
    let block = (size as usize)
        .saturating_add(1)
        .clamp(1 << 12, BLOCK_BYTES);
    let trailer = read_rows(&mut reader, &layout, block, dialect.data_line, &mut feed)?;
    if rows == 0 {
        return Err(SignalError::HeaderOnly {
            file: fpath.clone(),
        });
    }
    let outcome = match time_col {
        Some(_) => timing.finish(&mut sink)?,
        None if opts.resample_fs.is_some() => {
            return Err(SignalError::Unsupported {
                file: fpath,
                message: "--resample-fs needs a time column to resample through".into(),
            });
        }
        None => TimingOutcome {
            fs_hz: opts.fs.unwrap_or(1.0),
            samples: rows,
            resampled: None,
            jitter: None,
        },
    };
    let mut record = plan.record;
    record.notes.splice(0..0, form.note(&fpath));
    record.notes.extend(midnight.note(&fpath));
    record.notes.extend(trailer.map(|t| t.note(&fpath)));
    record.notes.extend(timing_notes(&fpath, &outcome));
    record.jitter = outcome.jitter;
    Ok(LogInfo {
        file: fpath,
        channels,
        time_column: time_col.map(|i| header[i].clone()),
        fs_hz: outcome.fs_hz,
        samples: outcome.samples,
        resampled: outcome.resampled,
        ingest: record,
    })
}

/// The stderr lines for jitter and for an anti-alias filter, once each.
fn timing_notes(file: &Path, t: &TimingOutcome) -> Vec<String> {
    let f = file.display();
    let mut notes = Vec::new();
    if let Some(j) = &t.jitter {
        let how = if t.resampled.is_some() {
            "interpolated through the timestamps"
        } else {
            "analysed at the mean step"
        };
        notes.push(format!(
            "{f}: time steps jitter from line {} ({} step(s) off the interval; RMS {:.2}%, largest {:.2}% of the mean step {:.6e} s): {how}",
            j.first_jittered_line, j.jittered_steps, j.rms_deviation_pct, j.max_deviation_pct, j.mean_step_s
        ));
    }
    if let Some(a) = t.resampled.as_ref().and_then(|r| r.anti_alias.as_ref()) {
        notes.push(format!(
            "{f}: resampled to {} Hz through an anti-alias low-pass ({}, {} taps): flat to {} Hz, {} dB down from {} Hz",
            t.fs_hz, a.filter, a.taps, a.passband_hz, a.stopband_attenuation_db, a.stopband_hz
        ));
    }
    notes
}

/// The dialect of a log: sniffed from its head, or plain CSV with the header on line 1.
fn read_dialect(path: &Path) -> Result<Dialect, SignalError> {
    let (f, _) = text::open(path).map_err(|e| io_error(path, e))?;
    let mut head = Vec::new();
    f.take(sniff::HEAD_BYTES as u64)
        .read_to_end(&mut head)
        .map_err(|e| io_error(path, e))?;
    let eof = head.len() < sniff::HEAD_BYTES;
    if let Some(d) = sniff::sniff_dialect(&head, eof) {
        return Ok(d);
    }
    plain_dialect(path, &head)
}

/// Plain CSV: the first line is the header (read by the csv crate for quoted names).
fn plain_dialect(path: &Path, head: &[u8]) -> Result<Dialect, SignalError> {
    let fpath = path.to_path_buf();
    let end = memchr::memchr(b'\n', head).map_or(head.len(), |p| p + 1);
    let mut record = csv::ByteRecord::new();
    let mut hr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(&head[..end]);
    if !hr
        .read_byte_record(&mut record)
        .map_err(|e| SignalError::BadHeader {
            file: fpath.clone(),
            message: e.to_string(),
        })?
    {
        return Err(SignalError::EmptyFile { file: fpath });
    }
    let header: Vec<String> = record
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let s = String::from_utf8_lossy(b).trim().to_string();
            if i == 0 {
                s.trim_start_matches('\u{feff}').to_string()
            } else {
                s
            }
        })
        .collect();
    Ok(Dialect {
        delimiter: Delimiter::Comma,
        decimal_comma: false,
        width: header.len(),
        header: Some(header),
        header_line: 1,
        units: None,
        data_offset: end,
        data_line: 2,
        skipped_lines: 0,
        empty_columns: Vec::new(),
        metadata_columns: Vec::new(),
        index_columns: Vec::new(),
        first_row: Vec::new(),
        second_row: Vec::new(),
        preamble_rate: None,
        preamble_unit: None,
        preamble_electrical: None,
    })
}

/// Which columns are read, and how: the outcome of the header, the options and the dialect.
struct ColumnPlan {
    header: Vec<String>,
    time_col: Option<usize>,
    time_unit: Option<TimeUnit>,
    selected: Vec<usize>,
    channels: Vec<ChannelInfo>,
    fs_from_metadata: Option<f64>,
    record: IngestRecord,
}

/// Names that hold a sampling rate in a metadata column.
fn is_rate_name(name: &str) -> bool {
    let n = name.trim().to_ascii_lowercase().replace([' ', '-'], "_");
    matches!(
        n.as_str(),
        "fs" | "fs_hz" | "sample_rate" | "sampling_rate" | "samplerate" | "sample_rate_hz"
    )
}

fn header_names(
    file: &Path,
    d: &Dialect,
    opts: &IngestOptions,
) -> Result<Vec<String>, SignalError> {
    match (&opts.columns, &d.header) {
        (Some(cols), _) if cols.len() != d.width => Err(SignalError::Unsupported {
            file: file.to_path_buf(),
            message: format!(
                "line {}: the rows have {} fields but --columns names {}",
                d.data_line,
                d.width,
                cols.len()
            ),
        }),
        (Some(cols), _) => Ok(cols.iter().map(|c| c.trim().to_string()).collect()),
        (None, Some(h)) => Ok(h.clone()),
        (None, None) => Err(SignalError::Unsupported {
            file: file.to_path_buf(),
            message: format!(
                "line {}: no header line above the first data row; pass --columns with {} names (e.g. --columns time,a,b)",
                d.data_line, d.width
            ),
        }),
    }
}

fn check_names(
    file: &Path,
    header: &[String],
    ignored: &[usize],
    named_only: bool,
) -> Result<(), SignalError> {
    for (i, h) in header.iter().enumerate() {
        if ignored.contains(&i) {
            continue;
        }
        if h.is_empty() && !named_only {
            return Err(SignalError::BadHeader {
                file: file.to_path_buf(),
                message: format!("column {} has no channel name", i + 1),
            });
        }
        if !h.is_empty() && header[..i].contains(h) {
            return Err(SignalError::BadHeader {
                file: file.to_path_buf(),
                message: format!("channel name `{h}` appears twice"),
            });
        }
    }
    Ok(())
}

/// The time column's unit: the option, the units row, the name, else seconds unless the first
/// value is an epoch timestamp, whose unit follows from its size where that is unambiguous.
fn time_unit_of(
    file: &Path,
    d: &Dialect,
    opts: &IngestOptions,
    col: usize,
    name: &str,
) -> Result<TimeUnit, SignalError> {
    if let Some(u) = opts.time_unit {
        return Ok(u);
    }
    if d.first_row.get(col).and_then(|c| clock::parse(c)).is_some() {
        return Ok(TimeUnit::Iso8601);
    }
    if let Some(u) = d
        .units
        .as_ref()
        .and_then(|u| TimeUnit::parse(u[col].trim_matches(['[', ']', '(', ')'])).ok())
    {
        return Ok(u);
    }
    if let Some(Some(u)) = time_column_unit(name) {
        return Ok(u);
    }
    let first = d
        .first_row
        .get(col)
        .and_then(|c| sniff::number(c, d.decimal_comma));
    if is_spreadsheet_days(d, col) {
        return Ok(TimeUnit::Days);
    }
    match first {
        Some(v) if v.abs() > 1e8 => epoch_unit(v).ok_or_else(|| SignalError::Unsupported {
            file: file.to_path_buf(),
            message: format!(
                "line {}: time column `{name}` starts at {v:e}, an epoch timestamp whose unit the name does not state; pass --time-unit s, ms, us or ns",
                d.data_line
            ),
        }),
        _ => Ok(TimeUnit::S),
    }
}

/// A column whose units-row cell is a unit of time (`s`, `second`, `[ms]`) holds the times,
/// whatever its name (an oscilloscope's `x-axis`), when no column is named as time.
fn time_by_unit(d: &Dialect, ignored: &[usize]) -> Option<usize> {
    d.units.as_ref()?.iter().enumerate().position(|(i, u)| {
        let unit = TimeUnit::parse(u.trim_matches(['[', ']', '(', ')'])).ok();
        !ignored.contains(&i)
            && matches!(
                unit,
                Some(TimeUnit::S | TimeUnit::Ms | TimeUnit::Us | TimeUnit::Ns)
            )
    })
}

/// Serial days since 1899-12-30 of the years 1970–2099, as spreadsheets store date-times.
const SPREADSHEET_DAYS: std::ops::Range<f64> = 25_569.0..73_051.0;

/// A time column whose unit nothing states, holding spreadsheet date-times: a first value
/// among the serial days of 1970–2099 and a first step that, read in seconds, would be a rate
/// above 1 MHz but, read in days, one of 1 mHz–1 MHz (a 1 kHz log steps by 1.16e-8 day).
fn is_spreadsheet_days(d: &Dialect, col: usize) -> bool {
    let value = |row: &[String]| row.get(col).and_then(|c| sniff::number(c, d.decimal_comma));
    let (Some(t0), Some(t1)) = (value(&d.first_row), value(&d.second_row)) else {
        return false;
    };
    let step = t1 - t0;
    SPREADSHEET_DAYS.contains(&t0) && step > 0.0 && step < 1e-6 && step * 86_400.0 >= 1e-6
}

/// The unit of an epoch timestamp from its size alone, where that is unambiguous: the years
/// 2001–2286 are 1e9–1e10 s, 1e12–1e13 ms, 1e15–1e16 µs and 1e18–1e19 ns since 1970, four
/// ranges three decades apart. Elsewhere the unit cannot be told.
fn epoch_unit(v: f64) -> Option<TimeUnit> {
    let v = v.abs();
    [
        (1e9, TimeUnit::S),
        (1e12, TimeUnit::Ms),
        (1e15, TimeUnit::Us),
        (1e18, TimeUnit::Ns),
    ]
    .into_iter()
    .find(|(lo, _)| (*lo..10.0 * lo).contains(&v))
    .map(|(_, u)| u)
}

fn plan_columns(file: &Path, d: &Dialect, opts: &IngestOptions) -> Result<ColumnPlan, SignalError> {
    let header = header_names(file, d, opts)?;
    let mut ignored: Vec<usize> = d.empty_columns.clone();
    ignored.extend(d.metadata_columns.iter().map(|m| m.0));
    ignored.extend(&d.index_columns);
    ignored.sort_unstable();
    check_names(file, &header, &ignored, opts.channels.is_some())?;
    // A column of date-times or clock times is time whatever its name (`Zeit`, `Date/Time`).
    let iso = |i: usize| d.first_row.get(i).and_then(|c| clock::parse(c)).is_some();
    let named = header
        .iter()
        .enumerate()
        .position(|(i, h)| !ignored.contains(&i) && (is_time_column(h) || iso(i)));
    let mut time_col = named.or_else(|| time_by_unit(d, &ignored));
    let mut notes = dialect_notes(file, d, &header);
    if let (None, Some(tc)) = (named, time_col) {
        notes.push(format!(
            "column `{}` is the time: its unit in the units row is a time",
            header[tc]
        ));
    }
    if opts.fs_override
        && let (Some(tc), Some(fs)) = (time_col, opts.fs)
    {
        notes.push(format!(
            "time column `{}` ignored: --fs-override uses --fs {fs} Hz",
            header[tc]
        ));
        ignored.push(tc);
        time_col = None;
    }
    let time_unit = match time_col {
        Some(tc) => Some(time_unit_of(file, d, opts, tc, &header[tc])?),
        None => None,
    };
    if let (Some(tc), Some(u)) = (time_col, time_unit) {
        let epoch = d
            .first_row
            .get(tc)
            .and_then(|c| sniff::number(c, d.decimal_comma))
            .is_some_and(|v| v.abs() > 1e8);
        if epoch && opts.time_unit.is_none() {
            notes.push(format!(
                "time column `{}` read as an epoch timestamp in {} from its size (pass --time-unit to state it)",
                header[tc],
                u.name()
            ));
        } else if u == TimeUnit::Days && opts.time_unit.is_none() {
            notes.push(format!(
                "time column `{}` read as spreadsheet serial days (days since 1899-12-30) from its size and step: in seconds it would be a rate above 1 MHz (pass --time-unit s to read seconds)",
                header[tc]
            ));
        } else if u == TimeUnit::Iso8601 {
            notes.push(format!(
                "time column `{}` read as date-times or clock times (`{}`), in seconds from the first row",
                header[tc],
                d.first_row.get(tc).map_or("", String::as_str)
            ));
        } else if u != TimeUnit::S {
            notes.push(format!("time column `{}` in {}", header[tc], u.name()));
        }
    }
    let mut metadata = Vec::new();
    let mut fs_from_metadata = None;
    for &(c, v) in &d.metadata_columns {
        if let Some(v) = v {
            metadata.push((header[c].clone(), v));
            if is_rate_name(&header[c]) && time_col.is_none() && opts.fs.is_none() && v > 0.0 {
                fs_from_metadata = Some(v);
                notes.push(format!(
                    "sampling rate {v} Hz read from metadata column `{}`",
                    header[c]
                ));
            }
        }
    }
    if let Some((hz, line)) = d.preamble_rate
        && fs_from_metadata.is_none()
        && time_col.is_none()
    {
        match opts.fs {
            None => {
                fs_from_metadata = Some(hz);
                notes.push(format!("sampling rate {hz} Hz read from line {line}"));
            }
            Some(fs) if !opts.fs_override && (fs - hz).abs() > FS_AGREEMENT * fs => {
                let stated = format!("the {hz} Hz that line {line} of {} states", file.display());
                return Err(fs_disagrees(opts.fs_name, fs, &stated));
            }
            Some(_) => {}
        }
    }
    if let Some((u, line)) = d.preamble_unit {
        notes.push(format!(
            "unit {} read from line {line}, for the channels whose header states none",
            u.label()
        ));
    }
    let rate_stated = fs_from_metadata.is_some() || is_rate_column_present(&header, &ignored);
    let selected = select_columns(file, &header, time_col, &ignored, rate_stated, opts)?;
    if let Some((label, line)) = &d.preamble_electrical {
        notes.push(format!(
            "unit {label} read from line {line}, for the channels whose header states none: \
             an electrical unit, their values are kept as they are"
        ));
    }
    let channels = channel_infos(&header, &selected, d, opts);
    notes.extend(electrical_notes(&channels, opts));
    let record = IngestRecord {
        delimiter: d.delimiter.name(),
        decimal: if d.decimal_comma { "," } else { "." },
        skipped_lines: d.skipped_lines,
        time_column: time_col.map(|i| header[i].clone()),
        time_unit,
        ignored_columns: ignored.iter().map(|&i| column_label(&header, i)).collect(),
        metadata,
        jitter: None,
        notes,
        warnings: Vec::new(),
    };
    Ok(ColumnPlan {
        header,
        time_col,
        time_unit,
        selected,
        channels,
        fs_from_metadata,
        record,
    })
}

fn column_label(header: &[String], i: usize) -> String {
    if header[i].is_empty() {
        format!("column {}", i + 1)
    } else {
        header[i].clone()
    }
}

/// One note per way the dialect departs from a plain comma CSV with a header.
pub fn dialect_notes(file: &Path, d: &Dialect, header: &[String]) -> Vec<String> {
    let f = file.display();
    let mut notes = Vec::new();
    if d.delimiter != Delimiter::Comma {
        notes.push(format!("{f}: fields separated by {}", d.delimiter.name()));
    }
    if d.decimal_comma {
        notes.push(format!("{f}: decimal comma"));
    }
    if d.skipped_lines > 0 {
        notes.push(format!(
            "{f}: skipped {} preamble/comment line(s) before line {}",
            d.skipped_lines, d.data_line
        ));
    }
    if d.header.is_none() {
        notes.push(format!("{f}: no header; column names from --columns"));
    }
    if d.units.is_some() {
        notes.push(format!("{f}: line {}: units row read", d.header_line + 1));
    }
    for &c in &d.empty_columns {
        notes.push(format!(
            "{f}: column `{}` is empty: ignored",
            column_label(header, c)
        ));
    }
    for &c in &d.index_columns {
        notes.push(format!(
            "{f}: column `{}` numbers the samples (1 apart in every row of the head): not read as a channel",
            column_label(header, c)
        ));
    }
    for &(c, v) in &d.metadata_columns {
        let what = match v {
            Some(v) => format!("metadata {v}"),
            None => "metadata with several values".into(),
        };
        notes.push(format!(
            "{f}: column `{}` is filled only at the top ({what}): not read as a channel",
            column_label(header, c)
        ));
    }
    notes
}

fn select_columns(
    file: &Path,
    header: &[String],
    time_col: Option<usize>,
    ignored: &[usize],
    rate_stated: bool,
    opts: &IngestOptions,
) -> Result<Vec<usize>, SignalError> {
    let usable = |i: usize| Some(i) != time_col && !ignored.contains(&i) && !header[i].is_empty();
    let available = || {
        (0..header.len())
            .filter(|&i| usable(i))
            .map(|i| header[i].as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let selected: Vec<usize> = match &opts.channels {
        Some(list) => {
            let mut v = Vec::new();
            for name in list {
                let i = header
                    .iter()
                    .position(|h| h == name)
                    .filter(|i| Some(*i) != time_col)
                    .ok_or_else(|| SignalError::NoSuchChannel {
                        file: file.to_path_buf(),
                        name: name.clone(),
                        available: available(),
                    })?;
                v.push(i);
            }
            v
        }
        None => (0..header.len()).filter(|&i| usable(i)).collect(),
    };
    if selected.is_empty() {
        return Err(SignalError::BadHeader {
            file: file.to_path_buf(),
            message: format!(
                "no data channel: the only column{} `{}` {}",
                if header.len() > 1 { "s" } else { "" },
                header.join(","),
                if time_col.is_some() {
                    "is a time column"
                } else {
                    "holds no channel"
                }
            ),
        });
    }
    if time_col.is_none() && opts.fs.is_none() && !rate_stated {
        return Err(SignalError::NoSamplingRate {
            file: file.to_path_buf(),
        });
    }
    if let Some(fs) = opts.fs {
        if !(fs.is_finite() && fs > 0.0) {
            return Err(SignalError::BadParameter {
                name: "fs",
                value: fs.to_string(),
                reason: "must be positive".into(),
            });
        }
        plausible_rate(file, fs, opts.fs_name)?;
    }
    for (name, _) in &opts.channel_units {
        if !header.contains(name) {
            return Err(SignalError::NoSuchChannel {
                file: file.to_path_buf(),
                name: name.clone(),
                available: available(),
            });
        }
    }
    Ok(selected)
}

fn is_rate_column_present(header: &[String], ignored: &[usize]) -> bool {
    ignored.iter().any(|&i| is_rate_name(&header[i]))
}

/// A note for each channel the file states in volts: kept in them while `--units` gives one
/// unit for all, or read unchanged as the acceleration `--units NAME=UNIT` names.
pub(crate) fn electrical_notes(channels: &[ChannelInfo], opts: &IngestOptions) -> Vec<String> {
    let named = |c: &ChannelInfo| opts.channel_units.iter().any(|(n, _)| *n == c.name);
    channels
        .iter()
        .filter_map(|c| {
            unit::volts_note(
                &c.name,
                &c.stated_label,
                c.unit,
                named(c),
                opts.default_unit,
            )
        })
        .collect()
}

fn channel_infos(
    header: &[String],
    selected: &[usize],
    d: &Dialect,
    opts: &IngestOptions,
) -> Vec<ChannelInfo> {
    selected
        .iter()
        .map(|&i| {
            let name = header[i].clone();
            let row_text = d.units.as_ref().map_or("", |u| {
                u[i].trim().trim_matches(['[', ']', '(', ')']).trim()
            });
            let row_unit = Unit::parse(row_text).ok().filter(|u| *u != Unit::AsIs);
            // The unit text the file gives the channel: in its name, its units row, else
            // an electrical unit above the header.
            let stated = match unit::bracketed(&name).unwrap_or(row_text) {
                "" => d.preamble_electrical.as_ref().map_or("", |p| p.0.as_str()),
                text => text,
            };
            let (unit, unit_source) =
                if let Some((_, u)) = opts.channel_units.iter().find(|(n, _)| *n == name) {
                    (*u, UnitSource::Option)
                } else if let Some(u) = Unit::from_name(&name)
                    .or(row_unit)
                    .or(d.preamble_unit.map(|p| p.0))
                {
                    (u, UnitSource::Name)
                } else if unit::is_electrical(stated) {
                    (Unit::AsIs, UnitSource::Name)
                } else if let Some(u) = opts.default_unit {
                    (u, UnitSource::Option)
                } else {
                    (Unit::AsIs, UnitSource::Default)
                };
            let unit_label = match unit {
                Unit::AsIs => unit::kept_label(stated),
                _ => String::new(),
            };
            let stated_label = stated.to_string();
            ChannelInfo {
                name,
                unit,
                unit_source,
                column: i,
                unit_label,
                stated_label,
            }
        })
        .collect()
}

/// Where each needed column of a row goes: `slots[column] = (index in the row, unit factor)`;
/// the time (if any) is index 0.
struct RowLayout {
    file: PathBuf,
    header: Vec<String>,
    slots: Vec<Option<(usize, f64)>>,
    width: usize,
    /// Field delimiter (a space stands for runs of whitespace when `whitespace`).
    delim: u8,
    whitespace: bool,
    decimal_comma: bool,
    /// An ISO 8601 time column: its index and the first row's instant, from which its cells
    /// are counted in seconds.
    iso_time: Option<(usize, iso8601::Instant)>,
}

impl RowLayout {
    /// The value of cell `c` of a row: a number, or seconds from the first row's date-time in
    /// an ISO 8601 time column.
    fn cell(&self, c: usize, bytes: &[u8]) -> Option<f64> {
        match self.iso_time {
            Some((tc, origin)) if tc == c => std::str::from_utf8(bytes)
                .ok()
                .and_then(clock::parse)
                .map(|t| t.since(origin)),
            _ => parse_cell(bytes, self.decimal_comma),
        }
    }
}

/// A time-of-day column (a clock with no date) starts again from zero when a long log runs
/// past midnight; a drop of more than half a day is that, and the rows after it are counted
/// on into the next day. Any other step back stays a non-increasing time.
struct MidnightCrossing {
    applies: bool,
    offset_s: f64,
    previous_s: f64,
    crossings: Vec<u64>,
}

impl MidnightCrossing {
    fn new(d: &Dialect, iso_time: Option<(usize, iso8601::Instant)>) -> MidnightCrossing {
        let applies = iso_time.is_some_and(|(tc, _)| {
            d.first_row
                .get(tc)
                .is_some_and(|c| clock::is_time_of_day(c))
        });
        MidnightCrossing {
            applies,
            offset_s: 0.0,
            previous_s: f64::NEG_INFINITY,
            crossings: Vec::new(),
        }
    }

    /// Seconds from the first row, a day added at every midnight passed.
    fn count_on(&mut self, t_s: f64, line: u64) -> f64 {
        if !self.applies {
            return t_s;
        }
        let mut t = t_s + self.offset_s;
        if t < self.previous_s - 43_200.0 {
            self.offset_s += 86_400.0;
            t += 86_400.0;
            self.crossings.push(line);
        }
        self.previous_s = t;
        t
    }

    fn note(&self, file: &Path) -> Option<String> {
        let first = self.crossings.first()?;
        Some(format!(
            "{}: line {first}: the time of day passes midnight; counted on into the next day ({} midnight(s))",
            file.display(),
            self.crossings.len()
        ))
    }
}

/// The origin of an ISO 8601 time column: the first data row's date-time.
fn iso_origin(
    file: &Path,
    d: &Dialect,
    time_col: Option<usize>,
    unit: Option<TimeUnit>,
) -> Result<Option<(usize, iso8601::Instant)>, SignalError> {
    let (Some(tc), Some(TimeUnit::Iso8601)) = (time_col, unit) else {
        return Ok(None);
    };
    let first = d.first_row.get(tc).map_or("", String::as_str);
    match clock::parse(first) {
        Some(t) => Ok(Some((tc, t))),
        None => Err(SignalError::BadCell {
            file: file.to_path_buf(),
            line: d.data_line,
            column: d
                .header
                .as_ref()
                .and_then(|h| h.get(tc))
                .cloned()
                .unwrap_or_default(),
            text: first.to_string(),
            what: "not a date-time or clock time (YYYY-MM-DDThh:mm:ss[.f][Z|+hh:mm], DD.MM.YYYY hh:mm:ss[,f], MM/DD/YYYY hh:mm:ss[.f] [AM|PM], hh:mm:ss[.f])",
        }),
    }
}

/// Rows parsed from one chunk of the file: values (`width` per row), line numbers, and the
/// error that stopped the chunk, if any (rows before it are kept, so errors come out in file
/// order exactly as a sequential reader would give them).
#[derive(Default)]
struct Parsed {
    vals: Vec<f64>,
    lines: Vec<u64>,
    err: Option<SignalError>,
    /// Byte offset in the chunk of the line that stopped it.
    err_at: usize,
    count: u64,
}

/// Parses one line (no newline) into `out`; `Ok(false)` for a blank line. One pass over the
/// bytes: fields are cut at commas as they come, and only the needed ones are parsed.
fn parse_line(
    line: &[u8],
    line_no: u64,
    l: &RowLayout,
    out: &mut Vec<f64>,
) -> Result<bool, SignalError> {
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    if line.is_empty() {
        return Ok(false);
    }
    if l.whitespace {
        return parse_spaced(line, line_no, l, out);
    }
    let base = out.len();
    out.resize(base + l.width, 0.0);
    let ncols = l.slots.len();
    let mut c = 0usize;
    let mut start = 0usize;
    let mut bad: Option<(usize, usize, usize)> = None;
    loop {
        let end = memchr::memchr(l.delim, &line[start..]).map_or(line.len(), |p| start + p);
        if c < ncols
            && let Some((k, factor)) = l.slots[c]
        {
            match l.cell(c, &line[start..end]) {
                Some(v) => out[base + k] = v * factor,
                None => {
                    if bad.is_none() {
                        bad = Some((c, start, end));
                    }
                }
            }
        }
        c += 1;
        if end == line.len() {
            break;
        }
        start = end + 1;
    }
    if c != ncols {
        out.truncate(base);
        // A line of blanks is a blank line, not a one-field row.
        if c == 1 && line.trim_ascii().is_empty() {
            return Ok(false);
        }
        return Err(SignalError::RaggedRow {
            file: l.file.clone(),
            line: line_no,
            expected: ncols,
            found: c,
        });
    }
    if let Some((col, a, b)) = bad {
        out.truncate(base);
        if ncols == 1 && line.trim_ascii().is_empty() {
            return Ok(false);
        }
        return Err(bad_cell(&l.file, line_no, &l.header[col], &line[a..b]));
    }
    Ok(true)
}

/// A whitespace-separated line: fields are runs of non-blank bytes.
fn parse_spaced(
    line: &[u8],
    line_no: u64,
    l: &RowLayout,
    out: &mut Vec<f64>,
) -> Result<bool, SignalError> {
    let fields: Vec<&[u8]> = line
        .split(|b| matches!(b, b' ' | b'\t'))
        .filter(|f| !f.is_empty())
        .collect();
    if fields.is_empty() {
        return Ok(false);
    }
    if fields.len() != l.slots.len() {
        return Err(SignalError::RaggedRow {
            file: l.file.clone(),
            line: line_no,
            expected: l.slots.len(),
            found: fields.len(),
        });
    }
    let base = out.len();
    out.resize(base + l.width, 0.0);
    for (c, cell) in fields.iter().enumerate() {
        if let Some((k, factor)) = l.slots[c] {
            match l.cell(c, cell) {
                Some(v) => out[base + k] = v * factor,
                None => {
                    out.truncate(base);
                    return Err(bad_cell(&l.file, line_no, &l.header[c], cell));
                }
            }
        }
    }
    Ok(true)
}

/// Fast path for the common line `num,num,...,num` (no blanks, no quotes, every needed cell a
/// finite number, the right field count): parses it in place, fields cut by the number parser
/// itself. Returns the bytes consumed and whether a newline ended the line, or `None` (with
/// `out` untouched) for anything else, which `parse_line` then judges and reports.
fn fast_line(bytes: &[u8], l: &RowLayout, out: &mut Vec<f64>) -> Option<(usize, bool)> {
    if l.whitespace || l.decimal_comma || l.iso_time.is_some() {
        return None;
    }
    let base = out.len();
    out.resize(base + l.width, 0.0);
    let r = (|| {
        let ncols = l.slots.len();
        let mut i = 0usize;
        for c in 0..ncols {
            match l.slots[c] {
                Some((k, factor)) => {
                    let (v, used): (f64, usize) = fast_float2::parse_partial(&bytes[i..]).ok()?;
                    if used == 0 || !v.is_finite() {
                        return None;
                    }
                    out[base + k] = v * factor;
                    i += used;
                }
                None => {
                    i = memchr::memchr2(l.delim, b'\n', &bytes[i..]).map_or(bytes.len(), |q| i + q);
                }
            }
            if c + 1 < ncols {
                if bytes.get(i) != Some(&l.delim) {
                    return None;
                }
                i += 1;
            } else {
                return match (bytes.get(i), bytes.get(i + 1)) {
                    (None, _) => Some((i, false)),
                    (Some(b'\n'), _) => Some((i + 1, true)),
                    (Some(b'\r'), Some(b'\n')) => Some((i + 2, true)),
                    (Some(b'\r'), None) => Some((i + 1, false)),
                    _ => None,
                };
            }
        }
        None
    })();
    if r.is_none() {
        out.truncate(base);
    }
    r
}

/// Parses the lines of `chunk` with line numbers counted from 0 within it (the caller adds the
/// chunk's first line once the line counts of the chunks before it are known, so that no
/// separate pass has to count newlines). `count` is the number of lines seen.
fn parse_chunk(chunk: &[u8], l: &RowLayout) -> Parsed {
    let mut p = Parsed {
        vals: Vec::with_capacity(chunk.len() / 8),
        lines: Vec::with_capacity(chunk.len() / 24),
        err: None,
        err_at: 0,
        count: 0,
    };
    let mut start = 0usize;
    loop {
        let n = p.count;
        p.count += 1;
        if let Some((used, more)) = fast_line(&chunk[start..], l, &mut p.vals) {
            p.lines.push(n);
            if !more {
                break;
            }
            start += used;
            continue;
        }
        let end = memchr::memchr(b'\n', &chunk[start..]).map_or(chunk.len(), |q| start + q);
        match parse_line(&chunk[start..end], n, l, &mut p.vals) {
            Ok(true) => p.lines.push(n),
            Ok(false) => {}
            Err(e) => {
                p.vals.truncate(p.lines.len() * l.width);
                p.err = Some(e);
                p.err_at = start;
                break;
            }
        }
        if end == chunk.len() {
            break;
        }
        start = end + 1;
    }
    p
}

/// The same error placed `offset` lines further down the file.
fn shift_line(e: SignalError, offset: u64) -> SignalError {
    match e {
        SignalError::RaggedRow {
            file,
            line,
            expected,
            found,
        } => SignalError::RaggedRow {
            file,
            line: line + offset,
            expected,
            found,
        },
        SignalError::BadCell {
            file,
            line,
            column,
            text,
            what,
        } => SignalError::BadCell {
            file,
            line: line + offset,
            column,
            text,
            what,
        },
        other => other,
    }
}

/// A quoted block goes through the csv crate (quotes may hide commas); plain blocks, the
/// common case for numeric logs, are split on commas directly.
fn parse_quoted(chunk: &[u8], first_line: u64, l: &RowLayout) -> Parsed {
    let mut p = Parsed::default();
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .delimiter(l.delim)
        .from_reader(chunk);
    let mut rec = csv::ByteRecord::new();
    loop {
        match rdr.read_byte_record(&mut rec) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => {
                p.err = Some(SignalError::Unsupported {
                    file: l.file.clone(),
                    message: e.to_string(),
                });
                break;
            }
        }
        let n = first_line + rec.position().map_or(1, |q| q.line()) - 1;
        if rec.len() == 1 && rec.get(0).is_some_and(|b| b.trim_ascii().is_empty()) {
            continue;
        }
        p.err_at = rec.position().map_or(0, |q| q.byte() as usize);
        if rec.len() != l.slots.len() {
            p.err = Some(SignalError::RaggedRow {
                file: l.file.clone(),
                line: n,
                expected: l.slots.len(),
                found: rec.len(),
            });
            break;
        }
        let base = p.vals.len();
        p.vals.resize(base + l.width, 0.0);
        for (c, cell) in rec.iter().enumerate() {
            if let Some((k, factor)) = l.slots[c] {
                match l.cell(c, cell) {
                    Some(v) => p.vals[base + k] = v * factor,
                    None => {
                        p.vals.truncate(base);
                        p.err = Some(bad_cell(&l.file, n, &l.header[c], cell));
                        return p;
                    }
                }
            }
        }
        p.lines.push(n);
    }
    p
}

/// Bytes read per block: the memory bound of the reader (two blocks at most are alive).
const BLOCK_BYTES: usize = 4 << 20;
/// A line longer than this is not a log row (binary junk past the sniffed head).
const MAX_LINE_BYTES: usize = 64 << 20;

/// Reads the rows after the header in blocks cut at newlines, parses each block's pieces in
/// parallel (rayon), and hands the rows to `feed` in file order.
fn read_rows(
    reader: &mut impl Read,
    l: &RowLayout,
    block: usize,
    first_line: u64,
    feed: &mut impl FnMut(&[f64], &[u64]) -> Result<(), SignalError>,
) -> Result<Option<trailer::Trailer>, SignalError> {
    use rayon::prelude::*;
    let mut next_line: u64 = first_line;
    let mut carry: Vec<u8> = Vec::new();
    let pieces = (rayon::current_num_threads() * 4).max(1);
    loop {
        let mut buf = std::mem::take(&mut carry);
        let have = buf.len();
        buf.resize(have + block, 0);
        let mut got = 0;
        while have + got < buf.len() {
            let n = reader
                .read(&mut buf[have + got..])
                .map_err(|e| io_error(&l.file, e))?;
            if n == 0 {
                break;
            }
            got += n;
        }
        let eof = have + got < buf.len();
        buf.truncate(have + got);
        if buf.is_empty() {
            return Ok(None);
        }
        let cut = if eof {
            buf.len()
        } else {
            match buf.iter().rposition(|&b| b == b'\n') {
                Some(p) => p + 1,
                None if buf.len() > MAX_LINE_BYTES => {
                    return Err(SignalError::Unsupported {
                        file: l.file.clone(),
                        message: format!(
                            "line {next_line} is longer than {MAX_LINE_BYTES} bytes: not a log"
                        ),
                    });
                }
                None => {
                    carry = buf;
                    continue;
                }
            }
        };
        carry = buf[cut..].to_vec();
        buf.truncate(cut);
        let body = buf.strip_suffix(b"\n").unwrap_or(&buf);
        // Pieces end at newlines; each is parsed with its own line numbers from 0, placed in
        // the file once the pieces before it have reported their line counts.
        let mut bounds = vec![0usize];
        for k in 1..pieces {
            let target = body.len() * k / pieces;
            let from = *bounds.last().unwrap_or(&0);
            if target <= from {
                continue;
            }
            if let Some(p) = memchr::memchr(b'\n', &body[target..]) {
                bounds.push(target + p + 1);
            }
        }
        bounds.push(body.len() + 1);
        bounds.dedup();
        let spans: Vec<(usize, usize)> = bounds.windows(2).map(|w| (w[0], w[1] - 1)).collect();
        if body.contains(&b'"') {
            let p = parse_quoted(body, next_line, l);
            feed(&p.vals, &p.lines)?;
            if let Some(e) = p.err {
                return trailer_or(e, &body[p.err_at..], &carry, reader, l);
            }
            next_line += memchr::memchr_iter(b'\n', &buf).count() as u64;
        } else {
            let parsed: Vec<Parsed> = spans
                .par_iter()
                .map(|&(a, b)| parse_chunk(&body[a..b], l))
                .collect();
            for (mut p, &(a, _)) in parsed.into_iter().zip(&spans) {
                let offset = next_line;
                p.lines.iter_mut().for_each(|n| *n += offset);
                feed(&p.vals, &p.lines)?;
                if let Some(e) = p.err {
                    let rest = &body[a + p.err_at..];
                    return trailer_or(shift_line(e, offset), rest, &carry, reader, l);
                }
                next_line += p.count;
            }
            // Pieces are separated by one newline each, counted in `count`; the block's final
            // newline (absent at the end of a file without one) ends the last piece's last line.
            next_line -= 1;
            next_line += u64::from(buf.ends_with(b"\n"));
        }
        if eof {
            return Ok(None);
        }
    }
}

/// The unreadable row's error, unless it and everything after it is a trailer.
fn trailer_or(
    e: SignalError,
    rest: &[u8],
    carry: &[u8],
    reader: &mut impl Read,
    l: &RowLayout,
) -> Result<Option<trailer::Trailer>, SignalError> {
    let line = match &e {
        SignalError::RaggedRow { line, .. } | SignalError::BadCell { line, .. } => *line,
        _ => return Err(e),
    };
    let cells = trailer::Cells {
        delim: l.delim,
        whitespace: l.whitespace,
        decimal_comma: l.decimal_comma,
    };
    match trailer::find(rest, carry, reader, &cells) {
        Some(t) => Ok(Some(trailer::Trailer { line, ..t })),
        None => Err(e),
    }
}

/// Reads a whole CSV log into memory (for FRF, sweep and signature work on short records).
pub fn read_csv(path: &Path, opts: &IngestOptions) -> Result<Log, SignalError> {
    let mut data: Vec<Vec<f64>> = Vec::new();
    let info = stream_csv(path, opts, |row| {
        if data.is_empty() {
            data = vec![Vec::new(); row.len()];
        }
        for (d, v) in data.iter_mut().zip(row) {
            d.push(*v);
        }
    })?;
    if data.is_empty() {
        data = vec![Vec::new(); info.channels.len()];
    }
    Ok(Log { info, data })
}
