//! FRFs exported as a delimited text table: a frequency column, then each FRF as a pair of
//! columns, real and imaginary parts (`acc_re, acc_im`, `Re(acc), Im(acc)`, `acc real, acc
//! imag`) or magnitude and phase with the phase's unit stated (`acc_mag, acc_phase_deg`,
//! `acc magnitude, acc phase [rad]`). The dialect (delimiter, decimal comma, comments and
//! preamble, units row) is the log reader's ([`crate::signal::ingest::sniff`]).

use crate::error::SignalError;
use crate::signal::ingest::freq_table::{data_rows, is_frequency_column, sniff_head};
use crate::signal::ingest::sniff::Dialect;
use realfft::num_complex::Complex64;
use std::path::Path;

/// One FRF of a table: its name and its values.
pub struct TableFrf {
    pub name: String,
    pub h: Vec<Complex64>,
}

/// The FRFs of one table on its frequency lines.
pub struct FrfTable {
    pub freqs: Vec<f64>,
    pub frfs: Vec<TableFrf>,
    pub header_line: u64,
    /// How the file's dialect was read (encoding, delimiter, decimal comma, preamble).
    pub notes: Vec<String>,
}

/// How a column carries its part of an FRF.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Part {
    Re,
    Im,
    Magnitude,
    /// Phase in radians per unit of the column (π/180 for degrees).
    Phase(f64),
}

/// Whether a header cell names a part of an FRF (`acc_re`, `Im(acc)`, `acc_mag`).
pub fn names_frf_part(name: &str) -> bool {
    part_of(name).is_some()
}

/// The FRF a column belongs to and the part it carries, from its header cell.
fn part_of(name: &str) -> Option<(String, Part)> {
    let lower = name.trim().to_lowercase();
    for (prefix, part) in [("re(", Part::Re), ("im(", Part::Im)] {
        if lower.strip_prefix(prefix).is_some_and(|r| r.ends_with(')')) {
            // `Re(` and `)` are ASCII in the name as in its lower case.
            let inner = name.trim();
            return Some((inner[3..inner.len() - 1].trim().to_string(), part));
        }
    }
    let (body, unit) = match lower.rfind(['[', '(']) {
        Some(i) if lower.ends_with([']', ')']) => {
            (&lower[..i], Some(&lower[i + 1..lower.len() - 1]))
        }
        _ => (lower.as_str(), None),
    };
    let body = body.trim_end();
    let phase_scale = |word_unit: Option<&str>| match word_unit.or(unit).map(str::trim) {
        Some("deg" | "°" | "degree" | "degrees") => Some(std::f64::consts::PI / 180.0),
        Some("rad" | "radian" | "radians") => Some(1.0),
        _ => None,
    };
    const SUFFIXES: [(&str, Option<Part>); 10] = [
        ("re", Some(Part::Re)),
        ("real", Some(Part::Re)),
        ("im", Some(Part::Im)),
        ("imag", Some(Part::Im)),
        ("imaginary", Some(Part::Im)),
        ("mag", Some(Part::Magnitude)),
        ("magnitude", Some(Part::Magnitude)),
        ("abs", Some(Part::Magnitude)),
        ("phase", None),
        ("phase_deg", None),
    ];
    for (suffix, part) in SUFFIXES {
        for sep in ['_', ' ', '.'] {
            let tail = format!("{sep}{suffix}");
            let Some(stem) = body.strip_suffix(&tail) else {
                continue;
            };
            let stem_name = original_prefix(name.trim(), stem);
            let part = match part {
                Some(p) => p,
                None if suffix == "phase_deg" => Part::Phase(std::f64::consts::PI / 180.0),
                None => Part::Phase(phase_scale(None).unwrap_or(f64::NAN)),
            };
            return Some((stem_name, part));
        }
    }
    None
}

/// The start of `name` whose lower case is `lower_prefix`, in the name's own case (the lower
/// case itself where the two differ in length).
fn original_prefix(name: &str, lower_prefix: &str) -> String {
    let n = lower_prefix.len();
    match name.get(..n) {
        Some(p) if p.to_lowercase() == lower_prefix => p.trim().to_string(),
        _ => lower_prefix.trim().to_string(),
    }
}

fn err(file: &Path, line: u64, message: impl Into<String>) -> SignalError {
    SignalError::AtLine {
        file: file.to_path_buf(),
        line,
        message: message.into(),
    }
}

/// The FRFs of `path` when it is a text table whose first column is a frequency; `None` when
/// it is not (a time log).
pub fn read_frf_table(path: &Path) -> Result<Option<FrfTable>, SignalError> {
    // The head decides, so that a long time log is not read whole to be told apart.
    let Some((dialect, header)) = table_header(path) else {
        return Ok(None);
    };
    let bytes =
        crate::signal::ingest::text::read_all(path).map_err(|e| SignalError::Unsupported {
            file: path.to_path_buf(),
            message: format!("cannot read: {e}"),
        })?;
    let pairs = pair_columns(path, &dialect, &header)?;
    let rows = data_rows(path, &bytes, &dialect, "FRF table")?;
    let freqs: Vec<f64> = rows.iter().map(|(_, r)| r[0]).collect();
    if let Some(w) = rows.windows(2).find(|w| w[1].1[0] <= w[0].1[0]) {
        return Err(err(
            path,
            w[1].0,
            format!(
                "frequency {} after {}: the lines must increase",
                w[1].1[0], w[0].1[0]
            ),
        ));
    }
    let frfs = pairs
        .into_iter()
        .map(|(name, a, b, kind)| TableFrf {
            name,
            h: rows.iter().map(|(_, r)| value(r[a], r[b], kind)).collect(),
        })
        .collect();
    let notes = crate::signal::ingest::freq_table::table_notes(path, &dialect, &header);
    Ok(Some(FrfTable {
        freqs,
        frfs,
        header_line: dialect.header_line,
        notes,
    }))
}

/// The dialect and header of a file whose header starts with a frequency column and names some
/// part of an FRF; `None` for anything else.
fn table_header(path: &Path) -> Option<(Dialect, Vec<String>)> {
    let dialect = sniff_head(path)?;
    let header = dialect.header.clone()?;
    let is_table = header.first().is_some_and(|h| is_frequency_column(h))
        && header[1..].iter().any(|h| part_of(h).is_some());
    is_table.then_some((dialect, header))
}

fn value(a: f64, b: f64, kind: Part) -> Complex64 {
    match kind {
        Part::Phase(scale) => Complex64::from_polar(a, b * scale),
        _ => Complex64::new(a, b),
    }
}

/// The FRFs of the header: (name, first column, second column, how the second reads), the
/// first holding the real part or the magnitude.
fn pair_columns(
    path: &Path,
    dialect: &Dialect,
    header: &[String],
) -> Result<Vec<(String, usize, usize, Part)>, SignalError> {
    let line = dialect.header_line;
    let mut parts: Vec<(usize, String, Part)> = Vec::new();
    for (i, h) in header.iter().enumerate().skip(1) {
        if dialect.empty_columns.contains(&i) {
            continue;
        }
        let Some((name, part)) = part_of(h) else {
            return Err(err(
                path,
                line,
                format!(
                    "column {} `{h}` of an FRF table (first column `{}`) is neither a real or \
                     imaginary part (`X_re`, `X_im`, `Re(X)`) nor a magnitude or phase \
                     (`X_mag`, `X_phase_deg`, `X phase [rad]`)",
                    i + 1,
                    header[0]
                ),
            ));
        };
        if part == Part::Magnitude && h.to_lowercase().contains("db") {
            return Err(err(
                path,
                line,
                format!(
                    "column {} `{h}`: a magnitude in dB does not state its reference; export \
                     the linear magnitude or the real and imaginary parts",
                    i + 1
                ),
            ));
        }
        if let Part::Phase(s) = part
            && s.is_nan()
        {
            return Err(err(
                path,
                line,
                format!(
                    "column {} `{h}`: state the phase's unit (`[deg]` or `[rad]`)",
                    i + 1
                ),
            ));
        }
        parts.push((i, name, part));
    }
    let mut pairs: Vec<(String, usize, usize, Part)> = Vec::new();
    for (i, name, part) in &parts {
        let partner = match part {
            Part::Re => parts.iter().find(|(_, n, p)| n == name && *p == Part::Im),
            Part::Magnitude => parts
                .iter()
                .find(|(_, n, p)| n == name && matches!(p, Part::Phase(_))),
            _ => continue,
        };
        let Some((j, _, kind)) = partner else {
            return Err(err(
                path,
                line,
                format!(
                    "column {} `{}` has no matching imaginary part or phase",
                    i + 1,
                    header[*i]
                ),
            ));
        };
        if pairs.iter().any(|(n, ..)| n == name) {
            return Err(err(path, line, format!("FRF `{name}` is named twice")));
        }
        pairs.push((name.clone(), *i, *j, *kind));
    }
    if pairs.is_empty() {
        return Err(err(path, line, "an FRF table with no FRF column pair"));
    }
    Ok(pairs)
}

#[cfg(test)]
mod tests {
    use super::{Part, part_of};
    use crate::signal::ingest::freq_table::is_frequency_column;

    #[test]
    fn frequency_columns_as_exports_name_them() {
        for n in [
            "f",
            "Freq",
            "frequency_hz",
            "Frequency [Hz]",
            "Frequenz (Hz)",
            "Hz",
        ] {
            assert!(is_frequency_column(n), "{n}");
        }
        for n in ["time", "force", "fs"] {
            assert!(!is_frequency_column(n), "{n}");
        }
    }

    #[test]
    fn parts_as_exports_name_them() {
        let deg = std::f64::consts::PI / 180.0;
        assert_eq!(part_of("acc_re"), Some(("acc".into(), Part::Re)));
        assert_eq!(part_of("Acc 1 imag"), Some(("Acc 1".into(), Part::Im)));
        assert_eq!(part_of("Re(H 2:+Z)"), Some(("H 2:+Z".into(), Part::Re)));
        assert_eq!(part_of("İx_re"), Some(("i̇x".into(), Part::Re)));
        assert_eq!(part_of("a3_mag"), Some(("a3".into(), Part::Magnitude)));
        assert_eq!(
            part_of("a3_phase_deg"),
            Some(("a3".into(), Part::Phase(deg)))
        );
        assert_eq!(
            part_of("a3 phase [rad]"),
            Some(("a3".into(), Part::Phase(1.0)))
        );
        assert_eq!(
            part_of("a3 phase (°)"),
            Some(("a3".into(), Part::Phase(deg)))
        );
        assert!(matches!(part_of("a3 phase"), Some((_, Part::Phase(s))) if s.is_nan()));
        assert_eq!(part_of("force"), None);
        assert_eq!(part_of("acc_re [g/N]"), Some(("acc".into(), Part::Re)));
    }
}
