//! Which format a log file is in, and reading any of them into a [`Log`]: CSV-like text
//! ([`crate::signal::ingest`], streamed), UFF58/58b time histories ([`crate::signal::uff`]),
//! LabVIEW `.lvm` ([`lvm`]), MATLAB level 4 and 5 `.mat` ([`mat`]), NI TDMS ([`tdms`]) and WAV
//! ([`wav`]). The format is told by the file's first bytes, never by its extension.

pub mod lvm;
pub mod mat;
pub mod scope;
pub mod table;
pub mod tdms;
pub mod wav;

use crate::error::SignalError;
use crate::signal::ingest::{IngestOptions, Log, Unit, read_csv};
use crate::signal::uff::{channel_names, looks_like_uff, ordinate_unit, read_uff, same_rate};
use std::io::Read;
use std::path::Path;
use table::{Rate, Series, Table, table_to_log};

/// The format of a log file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogFormat {
    /// Delimited text (comma, semicolon, tab, whitespace).
    Csv,
    /// Universal File Format, dataset 58 (ASCII or 58b).
    Uff,
    /// LabVIEW Measurement file.
    Lvm,
    /// MATLAB MAT-file.
    Mat,
    /// NI TDMS file.
    Tdms,
    /// WAV (RIFF WAVE) file.
    Wav,
    /// Tektronix oscilloscope spreadsheet CSV.
    Tektronix,
    /// Rigol oscilloscope CSV.
    Rigol,
}

/// Tells the format from the first bytes of the file (a file that cannot be opened is taken as
/// CSV, whose reader then reports the error).
pub fn detect(path: &Path) -> LogFormat {
    let mut head = [0u8; 128];
    let n = std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .unwrap_or(0);
    let head = &head[..n];
    if mat::looks_like_mat(head) {
        LogFormat::Mat
    } else if tdms::looks_like_tdms(head) {
        LogFormat::Tdms
    } else if wav::looks_like_wav(head) {
        LogFormat::Wav
    } else if lvm::looks_like_lvm(head) {
        LogFormat::Lvm
    } else if scope::looks_like_tektronix(head) {
        LogFormat::Tektronix
    } else if scope::looks_like_rigol(head) {
        LogFormat::Rigol
    } else if looks_like_uff(path) {
        LogFormat::Uff
    } else {
        LogFormat::Csv
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, SignalError> {
    std::fs::read(path).map_err(|e| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("cannot read: {e}"),
    })
}

/// Reads a log of any format into memory, with the selection, units and rate of `opts`.
pub fn read_log(path: &Path, opts: &IngestOptions) -> Result<Log, SignalError> {
    match detect(path) {
        LogFormat::Csv => read_csv(path, opts),
        LogFormat::Lvm => table_to_log(path, lvm::read_lvm(path, &read_bytes(path)?)?, opts),
        LogFormat::Mat => table_to_log(path, mat::read_mat(path, &read_bytes(path)?)?, opts),
        LogFormat::Wav => table_to_log(path, wav::read_wav(path, &read_bytes(path)?)?, opts),
        LogFormat::Tektronix => {
            table_to_log(path, scope::read_tektronix(path, &read_bytes(path)?)?, opts)
        }
        LogFormat::Rigol => table_to_log(path, scope::read_rigol(path, &read_bytes(path)?)?, opts),
        LogFormat::Tdms => {
            let wanted = opts.channels.as_deref();
            table_to_log(
                path,
                tdms::read_tdms(path, &read_bytes(path)?, wanted)?,
                opts,
            )
        }
        LogFormat::Uff => table_to_log(path, uff_table(path, opts)?, opts),
    }
}

/// A UFF file with no time history to read: the error is at the line of its first record,
/// lists each record not read with its line and why (`ignored`), and names the command that
/// reads what it holds.
fn no_time_history(
    path: &Path,
    records: &[crate::signal::uff::UffRecord],
    ignored: &[String],
) -> SignalError {
    let has = |t: i64| records.iter().any(|r| r.function.function_type == t);
    let hint = if has(4) {
        "; FRFs (function type 4) are fitted as measured by `satqual ema FILE`"
    } else if has(9) {
        "; PSDs (function type 9) are read by `satqual psd FILE`"
    } else {
        ""
    };
    SignalError::Uff {
        file: path.to_path_buf(),
        line: records.first().map_or(1, |r| r.line),
        message: format!(
            "no real, evenly spaced time history (UFF58 function type 1) to read: {}{hint}",
            ignored.join("; ")
        ),
    }
}

/// The time histories (function type 1, real, evenly spaced) of a UFF file as columns; their
/// unit is the record's units field.
fn uff_table(path: &Path, opts: &IngestOptions) -> Result<Table, SignalError> {
    let file = read_uff(path)?;
    let mut series = Vec::new();
    let mut ignored = Vec::new();
    let mut rate = Rate::Unknown;
    let names = channel_names(&file.records);
    for (r, name) in file.records.iter().zip(names) {
        let step = r.spacing();
        match (r.function.function_type, r.is_complex(), step) {
            (1, false, Err(why)) => ignored.push(format!("`{name}` (line {}: {why})", r.line)),
            (1, false, Ok(step)) => {
                if let Rate::Stated(fs, _) = rate
                    && !same_rate(fs, step)
                {
                    ignored.push(format!(
                        "`{name}` (line {}: a step of {step} s, not 1/{fs} s)",
                        r.line
                    ));
                    continue;
                }
                if matches!(rate, Rate::Unknown) {
                    rate = Rate::Stated(1.0 / step, format!("the abscissa increment of `{name}`"));
                }
                // A record kept as it is hands on its units field (`V`, `Pa`), which the
                // table keeps as its label.
                let unit_label = match ordinate_unit(&r.ordinate_label, opts, &name) {
                    Unit::AsIs => r.ordinate_label.as_str(),
                    unit => unit.label(),
                };
                series.push(Series {
                    name,
                    unit_label: unit_label.to_string(),
                    values: r.re.clone(),
                });
            }
            // Refused when the record is parsed; named here should that ever change.
            (1, true, _) => ignored.push(format!(
                "`{name}` (line {}: a time history of complex values)",
                r.line
            )),
            _ => ignored.push(format!(
                "`{name}` (line {}: {}, not a time history)",
                r.line,
                r.function_kind()
            )),
        }
    }
    if series.is_empty() {
        return Err(no_time_history(path, &file.records, &ignored));
    }
    Ok(Table {
        format: "uff",
        delimiter: "none (UFF)",
        decimal: ".",
        series,
        rate,
        ignored,
        unreadable: Vec::new(),
        notes: file.note(path).into_iter().collect(),
        warnings: Vec::new(),
    })
}
