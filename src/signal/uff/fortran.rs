//! The numbers of a dataset-58 ASCII data block as Fortran writers put them down.
//!
//! The UFF58 description fixes the format of the data lines by record 7: ordinate data types 2
//! and 5 (single) `6E13.5`; types 4 and 6 (double), evenly spaced, `4E20.12`; type 4 unevenly
//! spaced `2(E13.5,E20.12)`, type 6 unevenly spaced `E13.5,2E20.12`. Most writers leave a blank
//! between fields, so the values are read as whitespace-separated numbers; two habits of older
//! writers (HBM catman among them) break that, and are read by the fixed columns instead:
//! - Fortran's `Ew.d` drops the `E` of an exponent of three digits to keep the width:
//!   `0.12345-100` is 0.12345e-100;
//! - C's `%13.5e` of such a value fills all 13 columns (`-1.23456e-100`), so it touches the
//!   field before it.

/// Widths of the fields of one data line, and the format's name for messages.
pub(super) fn line_format(ordinate_type: i64, even: bool) -> (&'static [usize], &'static str) {
    match (ordinate_type, even) {
        (4 | 6, true) => (&[20; 4], "4E20.12"),
        (4, false) => (&[13, 20, 13, 20], "2(E13.5,E20.12)"),
        (6, false) => (&[13, 20, 20], "E13.5,2E20.12"),
        // Types 2 and 5; record 7 refuses any other type before the data is read.
        _ => (&[13; 6], "6E13.5"),
    }
}

/// A number as Fortran writes it: what Rust reads (`1.5E-03`, `-2.5`), a `D` exponent
/// (`1.5D-03`), or an exponent whose `E` was dropped (`0.12345-100`). `None` for anything
/// else, including two numbers run together (`1.0E+01-2.0E+01`).
pub(super) fn number(tok: &str) -> Option<f64> {
    if let Ok(v) = tok.parse::<f64>() {
        return Some(v);
    }
    let (mantissa, exponent) = split(tok)?;
    format!("{mantissa}e{exponent}").parse().ok()
}

/// The mantissa and the exponent (0 when none) of a number token, each checked to be
/// digits: a sign, digits with at most one point, then `E`/`D` and a signed exponent or a
/// sign and the exponent.
pub(super) fn split(tok: &str) -> Option<(&str, i32)> {
    let sign = usize::from(tok.starts_with(['+', '-']));
    let body = &tok[sign..];
    let letter = body.find(['e', 'E', 'd', 'D']);
    // A sign after the first digit starts an exponent written without its letter.
    let at = letter.or_else(|| body.get(1..)?.find(['+', '-']).map(|i| i + 1));
    let (mantissa, exponent) = match at {
        Some(i) => {
            let rest = &body[i..];
            let rest = if letter.is_some() { &rest[1..] } else { rest };
            (&tok[..sign + i], exponent_of(rest)?)
        }
        None => (tok, 0),
    };
    let digits = &mantissa[sign..];
    let points = digits.matches('.').count();
    let all_digits = digits.chars().all(|c| c.is_ascii_digit() || c == '.');
    (all_digits && points <= 1 && digits.len() > points).then_some((mantissa, exponent))
}

/// A signed exponent of digits only.
fn exponent_of(text: &str) -> Option<i32> {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

/// A field of a data line that is not a number: its place and text.
#[derive(Debug, PartialEq)]
pub(super) struct BadField {
    /// 1-based.
    pub field: usize,
    /// First and last column (1-based) of the field.
    pub columns: (usize, usize),
    pub text: String,
}

/// The numbers of one data line, each with its token: split at blanks, or, when a token is
/// not a number (fields that touch), cut at the fixed `widths` (repeated along the line). A
/// blank field ends the line's values; text after it, or a field that is not a number, is a
/// [`BadField`].
pub(super) fn tokens<'a>(line: &'a str, widths: &[usize]) -> Result<Vec<(&'a str, f64)>, BadField> {
    let split: Option<Vec<(&str, f64)>> = line
        .split_whitespace()
        .map(|t| number(t).map(|v| (t, v)))
        .collect();
    if let Some(values) = split {
        return Ok(values);
    }
    let mut out = Vec::new();
    let mut start = 0;
    let mut blank_seen = false;
    for (k, width) in widths.iter().cycle().enumerate() {
        if start >= line.len() {
            break;
        }
        let end = (start + width).min(line.len());
        let bad = |text: &str| BadField {
            field: k + 1,
            columns: (start + 1, end),
            text: text.to_string(),
        };
        let text = line
            .get(start..end)
            .ok_or_else(|| bad(&line[start..]))?
            .trim();
        if text.is_empty() {
            blank_seen = true;
        } else {
            match number(text).filter(|_| !blank_seen) {
                Some(v) => out.push((text, v)),
                None => return Err(bad(text)),
            }
        }
        start = end;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::{BadField, line_format, number, split, tokens};

    /// Fortran's forms, each to the value written (exact decimal values, compared to the f64
    /// the same digits give with an `e`).
    #[test]
    fn fortran_numbers_read_with_or_without_their_exponent_letter() {
        assert_eq!(number("1.5E-03"), Some(1.5e-3));
        assert_eq!(number("-2.5"), Some(-2.5));
        assert_eq!(number("1.5D-03"), Some(1.5e-3));
        assert_eq!(number("0.12345-100"), Some(0.12345e-100));
        assert_eq!(number("-0.12345+101"), Some(-0.12345e101));
        assert_eq!(number("-1.23456e-100"), Some(-1.23456e-100));
        assert_eq!(split("0.12345-100"), Some(("0.12345", -100)));
        for bad in [
            "1.0E+01-2.0E+01",
            "0.12345-100-0.5",
            "1.2.3",
            "E+01",
            "-",
            "1e",
            "x1",
        ] {
            assert_eq!(number(bad), None, "{bad}");
        }
    }

    /// The data line formats of the UFF58 description, by ordinate type and spacing.
    #[test]
    fn the_line_format_follows_record_7() {
        assert_eq!(line_format(2, true).1, "6E13.5");
        assert_eq!(line_format(5, false).1, "6E13.5");
        assert_eq!(line_format(4, true), (&[20usize; 4][..], "4E20.12"));
        assert_eq!(line_format(6, true).1, "4E20.12");
        assert_eq!(line_format(4, false).0, [13, 20, 13, 20]);
        assert_eq!(line_format(6, false).0, [13, 20, 20]);
    }

    /// Touching 13-column fields are cut at the columns; a short last line ends at its last
    /// field; a field that is no number is named with its columns.
    #[test]
    fn touching_fields_are_cut_at_the_declared_widths() {
        let texts = |r: Result<Vec<(&'static str, f64)>, BadField>| {
            r.map(|t| t.into_iter().map(|(s, _)| s).collect::<Vec<_>>())
        };
        let w = [13; 6];
        let line = "-1.23456e-100-2.00000e-100 3.00000e+00";
        assert_eq!(
            texts(tokens(line, &w)),
            Ok(vec!["-1.23456e-100", "-2.00000e-100", "3.00000e+00"])
        );
        let mixed = [13, 20];
        let line = " 1.00000e-100-2.000000000000e-100";
        assert_eq!(
            texts(tokens(line, &mixed)),
            Ok(vec!["1.00000e-100", "-2.000000000000e-100"])
        );
        let line = "-1.23456e-100 2.0000x+00";
        assert_eq!(
            texts(tokens(line, &w)),
            Err(BadField {
                field: 2,
                columns: (14, 24),
                text: "2.0000x+00".into()
            })
        );
    }
}
