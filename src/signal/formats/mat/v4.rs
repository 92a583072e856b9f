//! MATLAB Level 4 MAT-files (`save -v4`, `scipy.io.savemat(..., format='4')`): matrices one
//! after another, each a header of five 32-bit integers — type MOPT, mrows, ncols, imagf,
//! namlen — then the name (namlen bytes with its closing NUL), then the real part column by
//! column, then the imaginary part when imagf is 1. There is no file header: the file is told
//! by its first matrix header.
//!
//! MOPT = 1000 M + 100 O + 10 P + T (MathWorks, "MAT-File Format", Level 4 MAT-files): M the
//! number format (0 IEEE little-endian, 1 IEEE big-endian; 2 VAX D, 3 VAX G, 4 Cray, refused),
//! O always 0, P the precision of the values (0 f64, 1 f32, 2 i32, 3 i16, 4 u16, 5 u8), T the
//! matrix type (0 numeric, 1 text, 2 sparse). The header integers are in the byte order M
//! names, so the order in which MOPT reads as such a number is the file's.

use super::elements::Value;

/// Longest name accepted: MATLAB names are at most 63 characters (plus the NUL); a larger
/// namlen is a file that is not a MAT-file or is damaged.
const MAX_NAMLEN: usize = 64;

/// One matrix header, in native integers.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Header {
    big_endian: bool,
    /// M of MOPT.
    format: i32,
    /// P of MOPT: bytes per value and how to read them.
    precision: i32,
    /// T of MOPT.
    kind: i32,
    rows: usize,
    cols: usize,
    imaginary: bool,
    namlen: usize,
}

/// The five integers of a header in one byte order, if they make a header.
fn header_in(bytes: &[u8], big_endian: bool) -> Option<Header> {
    let int = |k: usize| -> Option<i32> {
        let b: [u8; 4] = bytes.get(4 * k..4 * k + 4)?.try_into().ok()?;
        Some(if big_endian {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        })
    };
    let mopt = int(0)?;
    let (m, o, p, t) = (mopt / 1000, mopt / 100 % 10, mopt / 10 % 10, mopt % 10);
    let valid = (0..=4).contains(&m) && o == 0 && p <= 5 && t <= 2 && mopt >= 0;
    let imagf = int(3)?;
    let namlen = usize::try_from(int(4)?).ok()?;
    let rows = usize::try_from(int(1)?).ok()?;
    let cols = usize::try_from(int(2)?).ok()?;
    let plausible = matches!(imagf, 0 | 1) && (2..=MAX_NAMLEN).contains(&namlen);
    (valid && plausible).then_some(Header {
        big_endian,
        format: m,
        precision: p,
        kind: t,
        rows,
        cols,
        imaginary: imagf == 1,
        namlen,
    })
}

/// The header at the start of `bytes`: little-endian when MOPT reads as one that way, else
/// big-endian.
fn header(bytes: &[u8]) -> Option<Header> {
    header_in(bytes, false).or_else(|| header_in(bytes, true))
}

/// The name of a matrix: printable ASCII closed by a NUL.
fn name(bytes: &[u8], h: &Header) -> Option<String> {
    let raw = bytes.get(20..20 + h.namlen)?;
    let (text, nul) = raw.split_at(h.namlen - 1);
    let printable = text.iter().all(|b| b.is_ascii_graphic());
    (nul == [0] && printable).then(|| String::from_utf8_lossy(text).into_owned())
}

/// Whether the bytes start with a Level 4 matrix header and its name. Text cannot: its bytes
/// make integers far above any MOPT in either byte order.
pub fn looks_like_mat4(head: &[u8]) -> bool {
    header(head).is_some_and(|h| name(head, &h).is_some())
}

/// Bytes per value of precision P.
fn width(precision: i32) -> usize {
    match precision {
        0 => 8,
        1 | 2 => 4,
        3 | 4 => 2,
        _ => 1,
    }
}

/// One value of precision P in the file's byte order.
fn value(b: &[u8], precision: i32, big_endian: bool) -> f64 {
    macro_rules! read {
        ($t:ty) => {{
            let a = b.try_into().unwrap_or_default();
            f64::from(if big_endian {
                <$t>::from_be_bytes(a)
            } else {
                <$t>::from_le_bytes(a)
            })
        }};
    }
    match precision {
        0 => read!(f64),
        1 => read!(f32),
        2 => read!(i32),
        3 => read!(i16),
        4 => read!(u16),
        _ => f64::from(b[0]),
    }
}

/// Every matrix of a Level 4 file, in file order, as (name, value); a matrix that is not a
/// real numeric one is a [`Value::Other`] saying why it is not read.
pub fn read_mat4(bytes: &[u8]) -> Result<Vec<(String, Value)>, String> {
    let mut out = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let k = out.len() + 1;
        let rest = &bytes[at..];
        let (entry, used) = matrix(rest).map_err(|e| format!("matrix {k} (byte {at}): {e}"))?;
        out.push(entry);
        at += used;
    }
    Ok(out)
}

/// One matrix at the start of `bytes`, and the bytes it takes.
fn matrix(bytes: &[u8]) -> Result<((String, Value), usize), String> {
    let h = header(bytes).ok_or(
        "not a Level 4 matrix header (five 32-bit integers: MOPT of digits M 0-4, O 0, P 0-5, \
         T 0-2; mrows and ncols >= 0; imagf 0 or 1; namlen 2-64)",
    )?;
    let name = name(bytes, &h).ok_or("its name is not printable text closed by a NUL")?;
    let order = if h.big_endian { 1 } else { 0 };
    if h.format != order {
        return Err(format!(
            "`{name}`: MOPT {} gives the number format {}, which is not IEEE {}-endian as its \
             header reads: only IEEE little-endian (0) and big-endian (1) are read; save with \
             `-v6` or `-v7`",
            1000 * h.format + 10 * h.precision + h.kind,
            h.format,
            if h.big_endian { "big" } else { "little" }
        ));
    }
    let count = h
        .rows
        .checked_mul(h.cols)
        .ok_or("mrows x ncols overflows")?;
    let parts = if h.imaginary { 2 } else { 1 };
    let size = count
        .checked_mul(width(h.precision) * parts)
        .ok_or("the size of its values overflows")?;
    let start = 20 + h.namlen;
    let end = start.checked_add(size).ok_or("its size overflows")?;
    let data = bytes.get(start..end).ok_or_else(|| {
        format!(
            "`{name}` ({}x{}) needs {size} bytes of values, but the file ends {} bytes after its \
             name: the file is cut short",
            h.rows,
            h.cols,
            bytes.len().saturating_sub(start)
        )
    })?;
    Ok(((name, contents(&h, data)), end))
}

/// The value of a matrix from its data bytes: numeric, or why it is not read.
fn contents(h: &Header, data: &[u8]) -> Value {
    if h.kind == 1 {
        return Value::Other("text matrix (MOPT type 1)".into());
    }
    if h.kind == 2 {
        return Value::Other("sparse matrix (MOPT type 2)".into());
    }
    if h.imaginary {
        return Value::Other(
            "complex matrix (imagf 1): its real part alone is not the signal".into(),
        );
    }
    let w = width(h.precision);
    let values = data
        .chunks_exact(w)
        .map(|b| value(b, h.precision, h.big_endian))
        .collect();
    Value::Numeric {
        dims: vec![h.rows, h.cols],
        data: values,
    }
}

#[cfg(test)]
mod tests {
    use super::{Value, looks_like_mat4, read_mat4};

    /// A matrix as `save -v4` writes it: header (MOPT, mrows, ncols, imagf, namlen), name with
    /// its NUL, values.
    fn matrix(
        big: bool,
        mopt: i32,
        dims: (i32, i32),
        imagf: i32,
        name: &str,
        data: &[u8],
    ) -> Vec<u8> {
        let int = |v: i32| {
            if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            }
        };
        let namlen = name.len() as i32 + 1;
        let mut out = Vec::new();
        for v in [mopt, dims.0, dims.1, imagf, namlen] {
            out.extend(int(v));
        }
        out.extend(name.as_bytes());
        out.push(0);
        out.extend(data);
        out
    }

    /// Doubles as a little-endian file holds them.
    fn le_doubles(values: &[f64]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    /// MOPT 0 (IEEE little-endian, double, numeric) and 1010 (big-endian, single): the same
    /// values come back in either order; text, sparse and complex are named, not read.
    #[test]
    fn both_byte_orders_and_precisions_read() {
        let le = le_doubles(&[1.5, -2.25]);
        let be: Vec<u8> = [1.5f32, -2.25]
            .iter()
            .flat_map(|v| v.to_be_bytes())
            .collect();
        let a = matrix(false, 0, (2, 1), 0, "x", &le);
        let b = matrix(true, 1010, (1, 2), 0, "y", &be);
        assert!(looks_like_mat4(&a) && looks_like_mat4(&b));
        assert!(!looks_like_mat4(b"time,acc\n0,1\n1,2\n"));
        for (bytes, name, dims) in [(a, "x", vec![2, 1]), (b, "y", vec![1, 2])] {
            let vars = read_mat4(&bytes).unwrap();
            let want = Value::Numeric {
                dims,
                data: vec![1.5, -2.25],
            };
            assert_eq!(vars, [(name.to_string(), want)]);
        }
        // Text 'ab' as MATLAB writes it (MOPT 1: doubles of the character codes), complex.
        let codes = le_doubles(&[97.0, 98.0]);
        let mut file = matrix(false, 1, (1, 2), 0, "s", &codes);
        file.extend(matrix(false, 0, (1, 1), 1, "z", &le));
        let vars = read_mat4(&file).unwrap();
        assert_eq!(vars[0].1, Value::Other("text matrix (MOPT type 1)".into()));
        assert!(matches!(&vars[1].1, Value::Other(w) if w.starts_with("complex matrix")));
    }

    /// A file cut inside its values, and a VAX number format, are errors naming the matrix.
    #[test]
    fn a_cut_file_and_a_vax_format_are_refused() {
        let le = le_doubles(&[1.5, -2.25]);
        let cut = matrix(false, 0, (3, 1), 0, "acc", &le);
        let e = read_mat4(&cut).unwrap_err();
        assert!(
            e.contains(
                "matrix 1 (byte 0): `acc` (3x1) needs 24 bytes of values, but the file ends 16"
            ),
            "{e}"
        );
        let vax = matrix(false, 2000, (2, 1), 0, "acc", &le);
        let e = read_mat4(&vax).unwrap_err();
        assert!(e.contains("number format 2"), "{e}");
    }
}
