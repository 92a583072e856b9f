//! A trailer after the data: some loggers end a log with a line such as `End of data` or
//! `Test stopped by operator`. When every line from the first unreadable row to the end of
//! the file holds no number at all, those lines are that trailer: the data ends before it
//! (with a note) instead of the log being refused. A text line followed by more numbers is
//! still an unreadable row.

use std::io::Read;

/// At most this many non-blank lines make a trailer; more text is not one.
pub const MAX_TRAILER_LINES: usize = 20;
/// At most this much of the file is read past the first unreadable row to decide.
const MAX_TRAILER_BYTES: usize = 64 * 1024;

/// The trailer found: the line it starts on (filled in by the caller), how many non-blank
/// lines it has and the first of them.
#[derive(Debug, Clone)]
pub struct Trailer {
    pub line: u64,
    pub lines: usize,
    pub first: String,
}

impl Trailer {
    pub fn note(&self, file: &std::path::Path) -> String {
        format!(
            "{}: line {}: the data ends; {} trailing line(s) without numbers skipped (`{}`)",
            file.display(),
            self.line,
            self.lines,
            self.first
        )
    }
}

/// How a line's cells are cut and read.
pub struct Cells {
    pub delim: u8,
    pub whitespace: bool,
    pub decimal_comma: bool,
}

/// `rest` (from the unreadable row to the end of the block), then `carry` and whatever the
/// reader still holds: a trailer when all of it is lines without a number.
pub fn find(rest: &[u8], carry: &[u8], reader: &mut impl Read, cells: &Cells) -> Option<Trailer> {
    let mut text = Vec::with_capacity(rest.len() + carry.len() + 1);
    text.extend_from_slice(rest);
    text.push(b'\n');
    text.extend_from_slice(carry);
    if text.len() > MAX_TRAILER_BYTES {
        return None;
    }
    let budget = (MAX_TRAILER_BYTES + 1 - text.len()) as u64;
    reader.take(budget).read_to_end(&mut text).ok()?;
    if text.len() > MAX_TRAILER_BYTES {
        return None;
    }
    let lines: Vec<&[u8]> = text
        .split(|&b| b == b'\n')
        .map(|l| l.trim_ascii())
        .filter(|l| !l.is_empty())
        .collect();
    let no_numbers = lines.iter().all(|l| !has_number(l, cells));
    (!lines.is_empty() && lines.len() <= MAX_TRAILER_LINES && no_numbers).then(|| Trailer {
        line: 0,
        lines: lines.len(),
        first: String::from_utf8_lossy(lines[0]).chars().take(60).collect(),
    })
}

fn has_number(line: &[u8], cells: &Cells) -> bool {
    let commas = [cells.decimal_comma];
    if cells.whitespace {
        line.split(|b| b.is_ascii_whitespace())
            .any(|c| is_number_cell(c, &commas))
    } else {
        line.split(|&b| b == cells.delim)
            .any(|c| is_number_cell(c, &commas))
    }
}

/// Whether a cell reads as a number (in one of the decimal conventions given) or a clock time:
/// what tells a data row from a trailer line, both once the dialect is known and while it is
/// being told.
pub(super) fn is_number_cell(cell: &[u8], decimal_commas: &[bool]) -> bool {
    let t = cell.trim_ascii();
    let t = t.strip_prefix(b"\"").unwrap_or(t);
    let t = t.strip_suffix(b"\"").unwrap_or(t);
    decimal_commas
        .iter()
        .any(|&comma| super::parse_cell(t, comma).is_some())
        || std::str::from_utf8(t).is_ok_and(|s| super::clock::parse(s.trim()).is_some())
}

#[cfg(test)]
mod tests {
    use super::*;

    const COMMA: Cells = Cells {
        delim: b',',
        whitespace: false,
        decimal_comma: false,
    };

    #[test]
    fn text_lines_to_the_end_are_a_trailer() {
        let t = find(
            b"End of data\r",
            b"\n\nStopped by operator,,\n",
            &mut &b""[..],
            &COMMA,
        );
        let t = t.expect("a trailer");
        assert_eq!((t.lines, t.first.as_str()), (2, "End of data"));
    }

    #[test]
    fn numbers_after_the_text_or_in_it_are_not_a_trailer() {
        assert!(find(b"End of data", b"", &mut &b"0.1,2\n"[..], &COMMA).is_none());
        assert!(find(b"Max,1.25", b"", &mut &b""[..], &COMMA).is_none());
        assert!(find(b"x,\"12:00:01\"", b"", &mut &b""[..], &COMMA).is_none());
        let long = vec![b'a'; MAX_TRAILER_BYTES];
        assert!(find(b"End", b"", &mut &long[..], &COMMA).is_none());
    }
}
