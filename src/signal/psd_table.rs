//! PSDs exported as a delimited text table, as random-vibration controllers write them: a
//! frequency column, then one column per channel in a spectral-density unit stated in its
//! name, its bracket or the units row (`Control (g²/Hz)`, `psd_g2_per_Hz`, `ch1 [(m/s²)²/Hz]`).
//! The lines must be evenly spaced (to the digits the frequencies are printed with); the
//! levels are taken as they are, as for a UFF58 PSD record. The dialect is the log reader's.

use super::ema::frf_table::names_frf_part;
use super::ingest::freq_table::{data_rows, is_frequency_column, sniff_head};
use super::ingest::sniff::Dialect;
use super::ingest::{IngestOptions, Unit, time_column_unit};
use super::welch::Psd;
use super::welch::round_to_micro;
use crate::error::SignalError;
use std::path::Path;

/// One channel's PSD read from a table, in g²/Hz for an acceleration.
pub struct TableChannel {
    pub name: String,
    pub unit: Unit,
    pub psd: Psd,
}

/// One PSD column of a table: its name, its index and the unit of its amplitude.
#[derive(Clone)]
struct Column {
    name: String,
    index: usize,
    unit: Unit,
}

fn err(file: &Path, line: u64, message: impl Into<String>) -> SignalError {
    SignalError::AtLine {
        file: file.to_path_buf(),
        line,
        message: message.into(),
    }
}

/// The amplitude unit of a spectral-density unit (`g^2/Hz`, `g²/Hz`, `g2_per_Hz`,
/// `(m/s^2)^2/Hz`, `m^2/s^4/Hz`; `AsIs` for another quantity's, `V^2/Hz`); `None` for
/// anything else.
pub fn psd_amplitude_unit(text: &str) -> Option<Unit> {
    let n: String = text
        .to_lowercase()
        .replace('²', "^2")
        .replace('⁴', "^4")
        .replace("**", "^")
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    let squared = n
        .strip_suffix("/hz")
        .or_else(|| n.strip_suffix("_per_hz"))
        .or_else(|| n.strip_suffix("perhz"))?;
    if matches!(squared, "m^2/s^4" | "m2/s4" | "m^2s^-4") {
        return Some(Unit::MPerS2);
    }
    let amplitude = squared
        .strip_suffix("^2")
        .or_else(|| squared.strip_suffix('2'))?;
    let amplitude = amplitude.trim_start_matches('(').trim_end_matches(')');
    match Unit::parse(amplitude) {
        Ok(u) => Some(u),
        // Another quantity's density (a drive in V²/Hz, a force in N²/Hz): kept as it is.
        Err(_) if !amplitude.is_empty() && amplitude.chars().all(char::is_alphabetic) => {
            Some(Unit::AsIs)
        }
        Err(_) => None,
    }
}

/// The spectral-density unit a column states: its bracket, its name's suffix, or the units row.
fn column_unit(name: &str, units_row: Option<&str>) -> Option<Unit> {
    let bracket = name
        .trim_end()
        .strip_suffix([']', ')'])
        .and_then(|inner| inner.rfind(['[', '(']).map(|i| &inner[i + 1..]));
    let suffixes = name
        .char_indices()
        .filter(|(_, c)| *c == '_' || *c == ' ')
        .map(|(i, _)| &name[i + 1..]);
    bracket
        .into_iter()
        .chain(suffixes)
        .chain(units_row)
        .find_map(psd_amplitude_unit)
}

/// Whether a column's header looks like a spectral density (to tell a PSD table from the
/// other frequency tables, the FRFs that `ema` reads).
fn states_psd_unit(d: &Dialect) -> bool {
    let header = d.header.as_deref().unwrap_or(&[]);
    (1..header.len()).any(|i| {
        let unit_cell = d.units.as_ref().and_then(|u| u.get(i)).map(String::as_str);
        column_unit(&header[i], unit_cell).is_some()
    })
}

/// The PSD columns of the header, with their units; `--units` gives the amplitude unit of
/// columns that state none.
fn columns(path: &Path, d: &Dialect, opts: &IngestOptions) -> Result<Vec<Column>, SignalError> {
    let header = d.header.as_deref().unwrap_or(&[]);
    let mut out = Vec::new();
    for (i, name) in header.iter().enumerate().skip(1) {
        if d.empty_columns.contains(&i) {
            continue;
        }
        let unit_cell = d.units.as_ref().and_then(|u| u.get(i)).map(String::as_str);
        let given = opts.channel_units.iter().find(|(n, _)| n == name);
        let unit = match (given, column_unit(name, unit_cell), opts.default_unit) {
            (Some((_, u)), _, _) => *u,
            (None, Some(u), _) => u,
            (None, None, Some(u)) => u,
            (None, None, None) => {
                return Err(err(
                    path,
                    d.header_line,
                    format!(
                        "column {} `{name}` of a PSD table states no spectral-density unit \
                         (`[g^2/Hz]`, `_g2_per_Hz`, `(m/s^2)^2/Hz`, or a units row); pass \
                         --units g (or --units \"{name}=g\") if its levels are in g²/Hz",
                        i + 1
                    ),
                ));
            }
        };
        out.push(Column {
            name: name.clone(),
            index: i,
            unit,
        });
    }
    match &opts.channels {
        None => Ok(out),
        Some(list) => list
            .iter()
            .map(|n| {
                let i = out.iter().position(|c| &c.name == n).ok_or_else(|| {
                    SignalError::NoSuchChannel {
                        file: path.to_path_buf(),
                        name: n.clone(),
                        available: out
                            .iter()
                            .map(|c| c.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                    }
                })?;
                Ok(out[i].clone())
            })
            .collect(),
    }
}

/// Digits after the decimal mark of the most precise frequency printed.
fn printed_decimals(bytes: &[u8], d: &Dialect) -> i32 {
    let text = String::from_utf8_lossy(&bytes[d.data_offset..]);
    text.lines()
        .filter_map(|l| {
            let first = super::ingest::sniff::split_fields(l, d.delimiter)
                .into_iter()
                .next()?;
            let mantissa = first.split(['e', 'E']).next().unwrap_or("");
            Some(mantissa.rsplit_once(['.', ',']).map_or(0, |(_, f)| f.len()) as i32)
        })
        .max()
        .unwrap_or(0)
}

/// The line spacing and the index of the first line from 0 Hz, when the lines are evenly
/// spaced to the digits they are printed with.
fn uniform_lines(
    path: &Path,
    rows: &[(u64, Vec<f64>)],
    decimals: i32,
) -> Result<(f64, usize), SignalError> {
    let f = |k: usize| rows[k].1[0];
    let n = rows.len();
    if n < 2 {
        return Err(err(path, rows[0].0, "a PSD table needs two lines or more"));
    }
    let df = (f(n - 1) - f(0)) / (n - 1) as f64;
    let slack = (0.5 * 10f64.powi(-decimals)).max(1e-9 * f(n - 1).abs()) * 1.01;
    for k in 0..n {
        let expected = f(0) + k as f64 * df;
        if df.is_nan() || df <= 0.0 || (f(k) - expected).abs() > slack {
            return Err(err(
                path,
                rows[k].0,
                format!(
                    "{} Hz where evenly spaced lines ({} Hz apart from {} Hz) put {} Hz: \
                     the PSD's lines must be evenly spaced and increasing (breakpoints at \
                     uneven frequencies are a profile: pass them with --profile)",
                    f(k),
                    round_to_micro(df),
                    f(0),
                    round_to_micro(expected)
                ),
            ));
        }
    }
    let offset = (f(0) / df).round();
    if offset < 0.0 || (f(0) - offset * df).abs() > slack {
        return Err(err(
            path,
            rows[0].0,
            format!(
                "the PSD starts at {} Hz, not on a multiple of its {df} Hz spacing",
                f(0)
            ),
        ));
    }
    Ok((df, offset as usize))
}

/// A PSD table's channels and the notes on how its dialect was read.
pub type PsdTable = (Vec<TableChannel>, Vec<String>);

/// The PSDs of `path` when it is a text table over frequency (no time column); `None` when
/// it is a time log. A table of FRFs, or one whose columns state no spectral-density unit
/// (and no `--units`), is an error at its header line.
pub fn read_psd_table(path: &Path, opts: &IngestOptions) -> Result<Option<PsdTable>, SignalError> {
    let Some(d) = sniff_head(path) else {
        return Ok(None);
    };
    let header = d.header.as_deref().unwrap_or(&[]);
    if !header.first().is_some_and(|h| is_frequency_column(h))
        || header.iter().any(|h| time_column_unit(h).is_some())
    {
        return Ok(None);
    }
    if header[1..].iter().any(|h| names_frf_part(h)) {
        return Err(err(
            path,
            d.header_line,
            "a table of FRFs over frequency, not of PSDs: `satqual ema FILE` fits it",
        ));
    }
    let unit_given = opts.default_unit.is_some() || !opts.channel_units.is_empty();
    if !states_psd_unit(&d) && !unit_given {
        return Err(err(
            path,
            d.header_line,
            format!(
                "a table over frequency (first column `{}`) whose columns state no spectral-density unit (`[g^2/Hz]`, `_g2_per_Hz`, `(m/s^2)^2/Hz`, or a units row); pass --units g if its levels are PSDs in g²/Hz",
                header[0]
            ),
        ));
    }
    let cols = columns(path, &d, opts)?;
    let bytes =
        crate::signal::ingest::text::read_all(path).map_err(|e| SignalError::Unsupported {
            file: path.to_path_buf(),
            message: format!("cannot read: {e}"),
        })?;
    let rows = data_rows(path, &bytes, &d, "PSD table")?;
    let notes = crate::signal::ingest::freq_table::table_notes(path, &d, header);
    let (df, offset) = uniform_lines(path, &rows, printed_decimals(&bytes, &d))?;
    let lines = offset + rows.len();
    if lines > opts.max_psd_lines {
        return Err(err(
            path,
            rows[0].0,
            format!(
                "{lines} spectral lines from 0 Hz, above the limit of {}; if the table is meant, raise --max-psd-lines",
                opts.max_psd_lines
            ),
        ));
    }
    let mut out = Vec::new();
    for c in cols {
        if let Some((line, r)) = rows.iter().find(|(_, r)| r[c.index] < 0.0) {
            return Err(err(
                path,
                *line,
                format!(
                    "column `{}` holds a negative level {}: a power spectral density is never negative",
                    c.name, r[c.index]
                ),
            ));
        }
        // A PSD scales with the square of the amplitude unit.
        let k = c.unit.to_report_factor();
        let mut values = vec![0.0; offset];
        values.extend(rows.iter().map(|(_, r)| r[c.index] * k * k));
        out.push(TableChannel {
            name: c.name,
            unit: c.unit,
            psd: Psd::from_lines(df, values),
        });
    }
    Ok(Some((out, notes)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectral_density_units_as_controllers_write_them() {
        for (text, unit) in [
            ("g^2/Hz", Unit::G),
            ("G²/Hz", Unit::G),
            ("g2_per_Hz", Unit::G),
            ("g**2/Hz", Unit::G),
            ("(m/s^2)^2/Hz", Unit::MPerS2),
            ("(m/s²)²/Hz", Unit::MPerS2),
            ("m^2/s^4/Hz", Unit::MPerS2),
            ("mg^2/Hz", Unit::MilliG),
        ] {
            assert_eq!(psd_amplitude_unit(text), Some(unit), "{text}");
        }
        for text in ["V^2/Hz", "N²/Hz"] {
            assert_eq!(psd_amplitude_unit(text), Some(Unit::AsIs), "{text}");
        }
        for text in ["g", "Hz", "g rms", "dB/Hz", "1/Hz"] {
            assert_eq!(psd_amplitude_unit(text), None, "{text}");
        }
        assert_eq!(column_unit("Control (G²/Hz)", None), Some(Unit::G));
        assert_eq!(column_unit("psd_g2_per_Hz", None), Some(Unit::G));
        assert_eq!(column_unit("ch1", Some("g^2/Hz")), Some(Unit::G));
        assert_eq!(column_unit("ch1", None), None);
    }
}
