//! The eleven header records of dataset 58 and the 58b marker line.
//!
//! Records 6-7 are read by whitespace splitting, which their fixed formats allow; records 8-11
//! (`I10,3I5,2(1X,A20)`) by column, since their labels may hold blanks ("Acceleration, m/s2").

use super::{AxisInfo, err};
use crate::error::SignalError;
use std::path::Path;

/// The binary layout a `58b` marker line announces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct BinaryLayout {
    pub little_endian: bool,
    pub ascii_lines: usize,
    pub bytes: usize,
}

fn field<T: std::str::FromStr>(
    file: &Path,
    line: u64,
    tokens: &[&str],
    k: usize,
    what: &str,
) -> Result<T, SignalError> {
    field_with(file, line, (tokens, k, what), |t| t.parse().ok())
}

/// A real field as Fortran writes it (a `D` exponent, or an exponent of three digits whose
/// `E` was dropped: see [`super::fortran`]).
fn real_field(
    file: &Path,
    line: u64,
    tokens: &[&str],
    k: usize,
    what: &str,
) -> Result<f64, SignalError> {
    field_with(file, line, (tokens, k, what), super::fortran::number)
}

/// Field `k` (named `what`) of a header line, read by `parse`.
fn field_with<T>(
    file: &Path,
    line: u64,
    (tokens, k, what): (&[&str], usize, &str),
    parse: impl Fn(&str) -> Option<T>,
) -> Result<T, SignalError> {
    let t = tokens
        .get(k)
        .ok_or_else(|| err(file, line, format!("missing field {} ({what})", k + 1)))?;
    parse(t).ok_or_else(|| {
        err(
            file,
            line,
            format!("field {} ({what}): cannot parse `{t}`", k + 1),
        )
    })
}

/// The `58b` marker line: `58b  byte-order  fp-format  ascii-lines  bytes  0 0 0 0`.
pub(super) fn binary_layout(
    file: &Path,
    line: u64,
    text: &str,
) -> Result<BinaryLayout, SignalError> {
    let t: Vec<&str> = text.split_whitespace().collect();
    let what = |s: &str| format!("58b marker line: {s}");
    let order: i64 = field(file, line, &t, 1, &what("byte ordering"))?;
    let fp: i64 = field(file, line, &t, 2, &what("floating-point format"))?;
    let ascii_lines: usize = field(file, line, &t, 3, &what("number of ASCII header lines"))?;
    let bytes: usize = field(file, line, &t, 4, &what("number of data bytes"))?;
    let little_endian = match order {
        1 => true,
        2 => false,
        o => {
            return Err(err(
                file,
                line,
                format!("58b byte ordering {o} (expected 1 little-endian or 2 big-endian)"),
            ));
        }
    };
    if fp != 2 {
        return Err(err(
            file,
            line,
            format!("58b floating-point format {fp}: only 2 (IEEE 754) is read"),
        ));
    }
    if ascii_lines != 11 {
        return Err(err(
            file,
            line,
            format!("58b announces {ascii_lines} ASCII header lines; dataset 58 has 11"),
        ));
    }
    Ok(BinaryLayout {
        little_endian,
        ascii_lines,
        bytes,
    })
}

/// Records 8-11: data type, then the axis label and the units label.
pub(super) fn axis(line: &str) -> AxisInfo {
    let data_type = line
        .split_whitespace()
        .next()
        .and_then(|t| t.parse().ok())
        .unwrap_or(0);
    let column = |a: usize, b: usize| line.get(a..b.min(line.len())).map(str::trim);
    let aligned = line.len() > 47 && line.as_bytes()[25] == b' ' && line.as_bytes()[46] == b' ';
    let (label, unit) = if aligned {
        (column(26, 46), column(47, 67))
    } else {
        // Hand-written files do not always keep the columns: axis label, then units last.
        let t: Vec<&str> = line.split_whitespace().skip(4).collect();
        (t.first().copied(), (t.len() > 1).then(|| t[t.len() - 1]))
    };
    let clean = |s: Option<&str>| match s {
        Some(s) if !s.eq_ignore_ascii_case("none") => s.to_string(),
        _ => String::new(),
    };
    AxisInfo {
        data_type,
        label: clean(label),
        unit: clean(unit),
    }
}

/// Record 6 (function identification): function type, response and reference entity, node
/// and direction.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Record6 {
    /// 1 time response, 4 FRF, 9 PSD, 12 spectrum, ... (field 1).
    pub function_type: i64,
    pub response_entity: String,
    pub response_node: i64,
    pub response_direction: i64,
    pub reference_entity: String,
    pub reference_node: i64,
    pub reference_direction: i64,
}

/// What function type `t` of record 6 (field 1) is, as the UFF58 description names it
/// (`2` auto spectrum, `9` power spectral density), for messages about a record not read.
pub fn function_type_name(t: i64) -> &'static str {
    const NAMES: [&str; 28] = [
        "general or unknown",
        "time response",
        "auto spectrum",
        "cross spectrum",
        "frequency response function",
        "transmissibility",
        "coherence",
        "auto correlation",
        "cross correlation",
        "power spectral density",
        "energy spectral density",
        "probability density function",
        "spectrum",
        "cumulative frequency distribution",
        "peaks valley",
        "stress/cycles",
        "strain/cycles",
        "orbit",
        "mode indicator function",
        "force pattern",
        "partial power",
        "partial coherence",
        "eigenvalue",
        "eigenvector",
        "shock response spectrum",
        "finite impulse response filter",
        "multiple coherence",
        "order function",
    ];
    usize::try_from(t)
        .ok()
        .and_then(|k| NAMES.get(k))
        .copied()
        .unwrap_or("not a function type of the UFF58 description")
}

/// Record 6, format `I5,I10,I5,I10,1X,A10,I10,I4,1X,A10,I10,I4`: the entity names are read by
/// column (they may hold blanks, "Mic 01"), the numbers around them by splitting.
pub(super) fn record6(file: &Path, line: u64, text: &str) -> Result<Record6, SignalError> {
    let t: Vec<&str> = text.split_whitespace().collect();
    let function_type: i64 = field(file, line, &t, 0, "function type")?;
    let col = |a: usize, b: usize| text.get(a..b.min(text.len())).unwrap_or("").trim();
    let num = |a: usize, b: usize| col(a, b).parse::<i64>().unwrap_or(0);
    let name = |s: &str| {
        if s.eq_ignore_ascii_case("none") {
            String::new()
        } else {
            s.to_string()
        }
    };
    Ok(Record6 {
        function_type,
        response_entity: name(col(31, 41)),
        response_node: num(41, 51),
        response_direction: num(51, 55),
        reference_entity: name(col(56, 66)),
        reference_node: num(66, 76),
        reference_direction: num(76, 80),
    })
}

/// Record 7 (data form): ordinate type, number of points, spacing, first abscissa, increment.
pub(super) struct Record7 {
    pub ordinate_type: i64,
    pub points: usize,
    pub even: bool,
    pub x0: f64,
    pub dx: f64,
}

pub(super) fn record7(file: &Path, line: u64, text: &str) -> Result<Record7, SignalError> {
    let t: Vec<&str> = text.split_whitespace().collect();
    let ordinate_type: i64 = field(file, line, &t, 0, "ordinate data type")?;
    let points: usize = field(file, line, &t, 1, "number of data values")?;
    let spacing: i64 = field(file, line, &t, 2, "abscissa spacing")?;
    let x0 = real_field(file, line, &t, 3, "abscissa minimum")?;
    let dx = real_field(file, line, &t, 4, "abscissa increment")?;
    if !matches!(ordinate_type, 2 | 4 | 5 | 6) {
        return Err(err(
            file,
            line,
            format!("ordinate data type {ordinate_type} (expected 2, 4, 5 or 6)"),
        ));
    }
    let even = match spacing {
        1 => true,
        0 => false,
        other => {
            return Err(err(
                file,
                line,
                format!("abscissa spacing {other} (expected 0 or 1)"),
            ));
        }
    };
    if even && !(dx.is_finite() && dx > 0.0) {
        return Err(err(
            file,
            line,
            format!("abscissa increment {dx} must be positive"),
        ));
    }
    Ok(Record7 {
        ordinate_type,
        points,
        even,
        x0,
        dx,
    })
}

#[cfg(test)]
mod tests {
    use super::record7;
    use std::path::Path;

    /// Record 7 as Fortran writers put it down (3I10,3E13.5): the E form, the D form, and an
    /// exponent of three digits with its E dropped, each read to the value written.
    #[test]
    fn record_7_reads_every_fortran_real_form() {
        let file = Path::new("r.uff");
        let cases = [
            (
                "         4     16384         1  0.00000E+00  9.76563E-05",
                0.0,
                9.76563e-5,
            ),
            (
                "         2      1024         1  1.00000D-01  5.00000D-04",
                0.1,
                5e-4,
            ),
            (
                "         2      1024         1  0.00000E+00  0.10000-100",
                0.0,
                0.1e-100,
            ),
        ];
        for (text, x0, dx) in cases {
            let r7 = record7(file, 7, text).unwrap();
            assert_eq!((r7.x0, r7.dx), (x0, dx), "{text}");
        }
        let bad = record7(file, 7, "         2      1024         1  0.0  fast")
            .err()
            .unwrap()
            .to_string();
        assert!(
            bad.contains("r.uff") && bad.contains("abscissa increment"),
            "{bad}"
        );
    }
}
