//! Oscilloscope CSV exports whose layout the general text reader cannot tell from data:
//!
//! - Tektronix (the TDS/TBS "spreadsheet" export, one channel per file): the settings as
//!   `key,value,unit` in the first three columns of the first rows, beside the samples as time
//!   and value in columns four and five, no header line. The channel is named by `Source`, its
//!   unit is `Vertical Units` (an electrical one, `V`, is kept by [`super::table`] and never
//!   taken as g), the rate comes from the time column, which `Sample Interval` must agree
//!   with.
//! - Rigol (DS1000Z and kin): a header `X,CH1,...,Start,Increment`, a second line `Sequence`,
//!   the channels' units, the start time and the sample interval, then rows of a sample number
//!   and the channels' values. The rate is 1 / `Increment`.
//!
//! Hand-written: a few lines of fixed layout each, no crate reads them.

use super::table::{Rate, Series, Table};
use crate::error::SignalError;
use crate::signal::ingest::sniff::number;
use std::path::Path;

/// Whether the bytes start like a Tektronix spreadsheet CSV.
pub fn looks_like_tektronix(head: &[u8]) -> bool {
    let head = head.strip_prefix(b"\xef\xbb\xbf").unwrap_or(head);
    head.starts_with(b"Record Length,")
        && head.split(|&b| b == b'\n').next().is_some_and(|l| {
            let cells: Vec<&[u8]> = l.split(|&b| b == b',').collect();
            cells.len() >= 5
        })
}

fn err(path: &Path, line: usize, message: impl Into<String>) -> SignalError {
    super::table::at_line(path, line, "Tektronix CSV", message)
}

/// Reads the one channel of a Tektronix spreadsheet CSV.
pub fn read_tektronix(path: &Path, bytes: &[u8]) -> Result<Table, SignalError> {
    let text = crate::signal::ingest::text::decode(bytes);
    let mut settings: Vec<(String, String)> = Vec::new();
    let (mut times, mut values) = (Vec::new(), Vec::new());
    for (i, line) in text.lines().enumerate() {
        let cells: Vec<&str> = line
            .trim_end_matches('\r')
            .split(',')
            .map(str::trim)
            .collect();
        if cells.iter().all(|c| c.is_empty()) {
            continue;
        }
        if cells.len() < 5 {
            return Err(err(
                path,
                i + 1,
                format!("{} fields, expected 5 or more", cells.len()),
            ));
        }
        if !cells[0].is_empty() {
            settings.push((cells[0].to_string(), cells[1].to_string()));
        }
        match (number(cells[3], false), number(cells[4], false)) {
            (Some(t), Some(v)) => {
                times.push(t);
                values.push(v);
            }
            _ => {
                let bad = if number(cells[3], false).is_none() {
                    cells[3]
                } else {
                    cells[4]
                };
                return Err(err(path, i + 1, format!("sample `{bad}` is not a number")));
            }
        }
    }
    let setting = |key: &str| {
        settings
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    };
    let announced = setting("Record Length").and_then(|v| number(v, false));
    let mut warnings = Vec::new();
    if let Some(n) = announced.filter(|&n| n > times.len() as f64) {
        warnings.push(format!(
            "{}: the record length says {n} points, but {} samples follow: the file ends early (cut short?); the samples present are analysed",
            path.display(),
            times.len()
        ));
    }
    check_interval(path, setting("Sample Interval"), &times)?;
    let name = setting("Source").filter(|s| !s.is_empty()).unwrap_or("CH");
    Ok(Table {
        format: "tektronix",
        delimiter: "comma",
        decimal: ".",
        series: vec![Series {
            name: name.to_string(),
            unit_label: setting("Vertical Units").unwrap_or("").to_string(),
            values,
        }],
        rate: Rate::Times(times, "time (column 4)".into()),
        ignored: Vec::new(),
        unreadable: Vec::new(),
        notes: vec![format!(
            "{}: Tektronix oscilloscope CSV: settings in columns 1–3, time and `{name}` in columns 4–5",
            path.display()
        )],
        warnings,
    })
}

/// Whether the bytes start like a Rigol oscilloscope CSV.
pub fn looks_like_rigol(head: &[u8]) -> bool {
    let head = head.strip_prefix(b"\xef\xbb\xbf").unwrap_or(head);
    let first = head.split(|&b| b == b'\n').next().unwrap_or(&[]);
    let first = String::from_utf8_lossy(first);
    let cells: Vec<&str> = first.trim_end().split(',').map(str::trim).collect();
    cells.first() == Some(&"X") && cells.windows(2).any(|w| w == ["Start", "Increment"])
}

/// Reads the channels of a Rigol oscilloscope CSV.
pub fn read_rigol(path: &Path, bytes: &[u8]) -> Result<Table, SignalError> {
    let text = crate::signal::ingest::text::decode(bytes);
    let mut lines = text.lines().map(|l| l.trim_end_matches('\r'));
    let cells = |l: &str| -> Vec<String> { l.split(',').map(|c| c.trim().to_string()).collect() };
    let header = cells(lines.next().unwrap_or(""));
    let second = cells(lines.next().unwrap_or(""));
    let start = header
        .iter()
        .position(|h| h == "Start")
        .unwrap_or(header.len());
    let names: Vec<String> = header[1..start].to_vec();
    let increment = second
        .get(start + 1)
        .and_then(|c| number(c, false))
        .filter(|&dt| dt > 0.0)
        .ok_or_else(|| {
            err_rigol(
                path,
                2,
                "no positive `Increment` (the sample interval) under the header",
            )
        })?;
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for (i, line) in lines.enumerate() {
        let row = cells(line);
        if row.iter().all(String::is_empty) {
            continue;
        }
        for (k, column) in values.iter_mut().enumerate() {
            let cell = row.get(k + 1).map_or("", String::as_str);
            let v = number(cell, false).ok_or_else(|| {
                err_rigol(
                    path,
                    i + 3,
                    format!("`{}`: `{cell}` is not a number", names[k]),
                )
            })?;
            column.push(v);
        }
    }
    let series = names
        .iter()
        .zip(values)
        .enumerate()
        .map(|(k, (name, values))| Series {
            name: name.clone(),
            unit_label: second.get(k + 1).cloned().unwrap_or_default(),
            values,
        })
        .collect();
    Ok(Table {
        format: "rigol",
        delimiter: "comma",
        decimal: ".",
        series,
        rate: Rate::Stated(1.0 / increment, "the `Increment` of line 2".into()),
        ignored: vec!["`X` (sample numbers)".into()],
        unreadable: Vec::new(),
        notes: vec![format!(
            "{}: Rigol oscilloscope CSV: {} channel(s), sample interval {increment:e} s from line 2",
            path.display(),
            names.len()
        )],
        warnings: Vec::new(),
    })
}

fn err_rigol(path: &Path, line: usize, message: impl Into<String>) -> SignalError {
    super::table::at_line(path, line, "Rigol CSV", message)
}

/// The stated `Sample Interval` and the time column's mean step agree within 0.1%, or the
/// file contradicts itself.
fn check_interval(path: &Path, stated: Option<&str>, times: &[f64]) -> Result<(), SignalError> {
    let (Some(dt), [first, .., last]) = (stated.and_then(|s| number(s, false)), times) else {
        return Ok(());
    };
    let mean = (last - first) / (times.len() - 1) as f64;
    if (mean - dt).abs() > 1e-3 * dt.abs() {
        return Err(SignalError::Unsupported {
            file: path.to_path_buf(),
            message: format!(
                "Tektronix CSV: `Sample Interval` {dt:e} s disagrees with the time column's mean step {mean:e} s"
            ),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEK: &str = "Record Length,4.000000e+00,Points,-0.001,0.5,\r\n\
        Sample Interval,1.000000e-03,s,0.000,-0.5,\r\n\
        Source,CH2,,0.001,0.25,\r\n\
        Vertical Units,g,,0.002,0.0,\r\n";

    #[test]
    fn settings_name_the_channel_and_its_unit_and_the_times_give_the_rate() {
        assert!(looks_like_tektronix(TEK.as_bytes()));
        let t = read_tektronix(Path::new("t.csv"), TEK.as_bytes()).unwrap();
        assert_eq!(t.series[0].name, "CH2");
        assert_eq!(t.series[0].unit_label, "g");
        assert_eq!(t.series[0].values, [0.5, -0.5, 0.25, 0.0]);
        assert!(matches!(&t.rate, Rate::Times(x, _) if x.len() == 4));
        assert!(t.warnings.is_empty());
    }

    #[test]
    fn a_rigol_export_gives_its_channels_units_and_rate() {
        let text = "X,CH1,CH2,Start,Increment,\r\nSequence,Volt,Volt,-6.000000e-03,2.000000e-06\r\n\
                    0,1.20e-02,3.0e-01,\r\n1,1.60e-02,2.0e-01,\r\n";
        assert!(looks_like_rigol(text.as_bytes()));
        assert!(!looks_like_rigol(b"X,Y\n1,2\n"));
        let t = read_rigol(Path::new("r.csv"), text.as_bytes()).unwrap();
        let names: Vec<&str> = t.series.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["CH1", "CH2"]);
        assert_eq!(t.series[1].values, [0.3, 0.2]);
        assert_eq!(t.series[0].unit_label, "Volt");
        // 1 / 2 µs, the stated interval.
        assert!(matches!(t.rate, Rate::Stated(fs, _) if (fs - 5e5).abs() < 1e-6));
        let bad = text.replace("1.60e-02", "overflow");
        let e = read_rigol(Path::new("r.csv"), bad.as_bytes()).unwrap_err();
        assert!(
            e.to_string()
                .contains("line 4: Rigol CSV: `CH1`: `overflow`"),
            "{e}"
        );
    }

    #[test]
    fn a_contradicting_interval_and_a_short_record_are_told() {
        let bad = TEK.replace("1.000000e-03,s", "2.000000e-03,s");
        let e = read_tektronix(Path::new("t.csv"), bad.as_bytes()).unwrap_err();
        assert!(e.to_string().contains("disagrees"), "{e}");
        let short = TEK.replace("4.000000e+00", "2.500000e+03");
        let t = read_tektronix(Path::new("t.csv"), short.as_bytes()).unwrap();
        assert!(
            t.warnings[0].contains("says 2500 points, but 4 samples follow"),
            "{:?}",
            t.warnings
        );
    }
}
