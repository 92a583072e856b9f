//! Universal File Format dataset 58 (function at a node), ASCII form: time histories and
//! spectra exported by shaker controllers and modal acquisition systems, e.g. the VibControl PSD
//! in `data/realdata/pyuff-vibcontrol-psd`.
//!
//! Hand-written: no maintained Rust crate reads UFF (pyuff is Python). The layout follows the
//! SDRC/Siemens UFF58 description: 11 header records, then the data in fixed-width fields. Fields
//! are read by whitespace splitting, which the fixed formats (E13.5, E20.12 with a leading blank)
//! allow. Other datasets in the file are skipped; the binary variant `58b` is refused.

use crate::error::SignalError;
use std::path::{Path, PathBuf};

/// One UFF58 record.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct UffRecord {
    /// Line of the `58` marker in the file (1-based).
    pub line: u64,
    pub id1: String,
    pub id4: String,
    /// 1 time response, 4 FRF, 9 PSD, 12 spectrum, ... (UFF58 record 6 field 1).
    pub function_type: i64,
    pub response_entity: String,
    pub ordinate_label: String,
    pub abscissa: Vec<f64>,
    /// Real part (or the value of a real record).
    pub re: Vec<f64>,
    /// Imaginary part; empty for a real record.
    pub im: Vec<f64>,
    pub even_spacing: bool,
}

impl UffRecord {
    pub fn is_complex(&self) -> bool {
        !self.im.is_empty()
    }

    /// Spacing of an evenly spaced abscissa, checked to 1e-6 relative.
    pub fn uniform_step(&self) -> Option<f64> {
        if self.abscissa.len() < 2 {
            return None;
        }
        let d = (self.abscissa[self.abscissa.len() - 1] - self.abscissa[0])
            / (self.abscissa.len() - 1) as f64;
        let ok = d > 0.0
            && self
                .abscissa
                .windows(2)
                .all(|w| ((w[1] - w[0]) - d).abs() <= 1e-6 * d.abs().max(f64::MIN_POSITIVE));
        ok.then_some(d)
    }
}

fn err(file: &Path, line: u64, message: impl Into<String>) -> SignalError {
    SignalError::Uff {
        file: file.to_path_buf(),
        line,
        message: message.into(),
    }
}

/// Reads every dataset-58 record of an ASCII UFF file.
pub fn read_uff58(path: &Path) -> Result<Vec<UffRecord>, SignalError> {
    let bytes = std::fs::read(path).map_err(|e| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("cannot read: {e}"),
    })?;
    parse_uff58(path, &bytes)
}

/// Parses UFF58 records from the bytes of a file named `path` (used in messages only).
pub fn parse_uff58(path: &Path, bytes: &[u8]) -> Result<Vec<UffRecord>, SignalError> {
    let file: PathBuf = path.to_path_buf();
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(SignalError::EmptyFile { file });
    }
    if let Some(offset) = bytes.iter().position(|&b| b == 0) {
        return Err(SignalError::BinaryFile {
            file,
            offset,
            byte: 0,
        });
    }
    // Header text may carry stray Latin-1 bytes (the VibControl "g²/Hz" does): decode lossily.
    let text = String::from_utf8_lossy(bytes);
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0usize;
    while i < lines.len() {
        if lines[i].trim() != "-1" {
            i += 1;
            continue;
        }
        // A delimiter; the next line names the dataset.
        let Some(kind) = lines.get(i + 1).map(|l| l.trim()) else {
            break;
        };
        let marker_line = (i + 2) as u64;
        if kind == "-1" {
            i += 1;
            continue;
        }
        let is58 = kind.split_whitespace().next() == Some("58");
        if kind.starts_with("58b") || (is58 && kind.len() > 2 && kind.contains('b')) {
            return Err(err(
                &file,
                marker_line,
                "binary UFF58 (58b) is not supported; export ASCII UFF58",
            ));
        }
        if !is58 {
            // Skip to the closing delimiter of the foreign dataset.
            let mut j = i + 2;
            while j < lines.len() && lines[j].trim() != "-1" {
                j += 1;
            }
            i = j + 1;
            continue;
        }
        let (rec, next) = parse_record(&file, &lines, i + 2, marker_line)?;
        out.push(rec);
        i = next;
    }
    if out.is_empty() {
        return Err(err(
            &file,
            1,
            "no dataset 58 found (expected a line `    -1` then `    58`)",
        ));
    }
    Ok(out)
}

fn field<T: std::str::FromStr>(
    file: &Path,
    line: u64,
    tokens: &[&str],
    k: usize,
    what: &str,
) -> Result<T, SignalError> {
    let t = tokens
        .get(k)
        .ok_or_else(|| err(file, line, format!("missing field {} ({what})", k + 1)))?;
    t.parse::<T>().map_err(|_| {
        err(
            file,
            line,
            format!("field {} ({what}): cannot parse `{t}`", k + 1),
        )
    })
}

fn parse_record(
    file: &Path,
    lines: &[&str],
    start: usize,
    marker: u64,
) -> Result<(UffRecord, usize), SignalError> {
    let get = |k: usize| -> Result<&str, SignalError> {
        lines.get(start + k).copied().ok_or_else(|| {
            err(
                file,
                (start + k + 1) as u64,
                "file ends inside the UFF58 header",
            )
        })
    };
    let id1 = get(0)?.trim().to_string();
    let id4 = get(3)?.trim().to_string();
    let r6_line = (start + 6) as u64;
    let r6: Vec<&str> = get(5)?.split_whitespace().collect();
    let function_type: i64 = field(file, r6_line, &r6, 0, "function type")?;
    let r6_raw = get(5)?;
    let response_entity = r6_raw.get(30..40).unwrap_or("").trim().to_string();
    // Many exporters leave ID line 4 as `NONE`; the response entity of record 6 then names
    // the channel.
    let id4 = if id4.is_empty() || id4.eq_ignore_ascii_case("none") {
        if response_entity.eq_ignore_ascii_case("none") {
            String::new()
        } else {
            response_entity.clone()
        }
    } else {
        id4
    };
    let r7_line = (start + 7) as u64;
    let r7: Vec<&str> = get(6)?.split_whitespace().collect();
    let ord_type: i64 = field(file, r7_line, &r7, 0, "ordinate data type")?;
    let n: usize = field(file, r7_line, &r7, 1, "number of data values")?;
    let spacing: i64 = field(file, r7_line, &r7, 2, "abscissa spacing")?;
    let x0: f64 = field(file, r7_line, &r7, 3, "abscissa minimum")?;
    let dx: f64 = field(file, r7_line, &r7, 4, "abscissa increment")?;
    // Record 9: four integers, then the axis label and the units label. The unit is the last
    // field: the axis label ("Acceleration", "General") says what, not in which unit.
    let ordinate_label = get(8)?
        .split_whitespace()
        .skip(4)
        .last()
        .unwrap_or("")
        .to_string();
    let complex = match ord_type {
        2 | 4 => false,
        5 | 6 => true,
        other => {
            return Err(err(
                file,
                r7_line,
                format!("ordinate data type {other} (expected 2, 4, 5 or 6)"),
            ));
        }
    };
    let even = match spacing {
        1 => true,
        0 => false,
        other => {
            return Err(err(
                file,
                r7_line,
                format!("abscissa spacing {other} (expected 0 or 1)"),
            ));
        }
    };
    if even && !(dx.is_finite() && dx > 0.0) {
        return Err(err(
            file,
            r7_line,
            format!("abscissa increment {dx} must be positive"),
        ));
    }
    // Values per point in the data block.
    let per_point = usize::from(!even) + if complex { 2 } else { 1 };
    let need = n
        .checked_mul(per_point)
        .ok_or_else(|| err(file, r7_line, "number of data values overflows"))?;
    // Records 8-11 are lines start+7 .. start+10; data from start+11 to the closing -1.
    let mut values: Vec<f64> = Vec::with_capacity(need.min(1 << 24));
    let mut j = start + 11;
    let mut closed = false;
    while j < lines.len() {
        let l = lines[j];
        if l.trim() == "-1" {
            closed = true;
            break;
        }
        for tok in l.split_whitespace() {
            // Fortran may write D exponents.
            let v: f64 = if tok.contains(['D', 'd']) {
                tok.replace(['D', 'd'], "E").parse()
            } else {
                tok.parse()
            }
            .map_err(|_| err(file, (j + 1) as u64, format!("cannot parse number `{tok}`")))?;
            if !v.is_finite() {
                return Err(err(
                    file,
                    (j + 1) as u64,
                    format!("non-finite value `{tok}`"),
                ));
            }
            values.push(v);
        }
        j += 1;
    }
    if !closed {
        return Err(err(
            file,
            (j.min(lines.len())) as u64,
            "dataset 58 is not closed by `-1`",
        ));
    }
    if values.len() != need {
        return Err(err(
            file,
            marker,
            format!(
                "record 7 announces {n} points ({need} values) but the data block holds {}",
                values.len()
            ),
        ));
    }
    let mut abscissa = Vec::with_capacity(n);
    let mut re = Vec::with_capacity(n);
    let mut im = Vec::with_capacity(if complex { n } else { 0 });
    for (k, chunk) in values.chunks_exact(per_point).enumerate() {
        let mut c = chunk.iter();
        let x = if even {
            x0 + k as f64 * dx
        } else {
            *c.next().unwrap_or(&0.0)
        };
        abscissa.push(x);
        re.push(*c.next().unwrap_or(&0.0));
        if complex {
            im.push(*c.next().unwrap_or(&0.0));
        }
    }
    if !even && abscissa.windows(2).any(|w| w[1] <= w[0]) {
        return Err(err(file, marker, "the abscissa does not increase"));
    }
    Ok((
        UffRecord {
            line: marker,
            id1,
            id4,
            function_type,
            response_entity,
            ordinate_label,
            abscissa,
            re,
            im,
            even_spacing: even,
        },
        j + 1,
    ))
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
/// units field (m/s² or g), then the default unit of the read.
pub(crate) fn ordinate_unit(
    label: &str,
    ingest: &crate::signal::ingest::IngestOptions,
    name: &str,
) -> crate::signal::ingest::Unit {
    use crate::signal::ingest::Unit;
    if let Some((_, u)) = ingest.channel_units.iter().find(|(n, _)| n == name) {
        return *u;
    }
    let l = label.to_ascii_lowercase();
    if l.starts_with("m/s") {
        Unit::MPerS2
    } else if l.starts_with('g') {
        Unit::G
    } else {
        ingest.default_unit.unwrap_or(Unit::AsIs)
    }
}
