//! Dialect sniffing: from the head of a text log, decides the delimiter, the decimal mark,
//! which lines before the data are preamble (comments, `key: value` blocks, LabVIEW headers),
//! the header and an optional units row, and which columns are empty or hold metadata only.
//! Every decision is recorded so that the caller can print it once and put it in the JSON.

/// Bytes of the file looked at to decide the dialect.
pub const HEAD_BYTES: usize = 1 << 20;
/// Lines of the head looked at (data rows after the first are only used for column checks).
const HEAD_LINES: usize = 400;
/// Data lines at the end of the head used to choose the delimiter.
const TAIL_LINES: usize = 20;

/// How fields are separated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delimiter {
    Comma,
    Semicolon,
    Tab,
    /// Runs of spaces or tabs.
    Whitespace,
}

impl Delimiter {
    pub fn byte(self) -> u8 {
        match self {
            Delimiter::Comma => b',',
            Delimiter::Semicolon => b';',
            Delimiter::Tab => b'\t',
            Delimiter::Whitespace => b' ',
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Delimiter::Comma => "comma",
            Delimiter::Semicolon => "semicolon",
            Delimiter::Tab => "tab",
            Delimiter::Whitespace => "whitespace",
        }
    }
}

/// What the sniffer found.
#[derive(Debug, Clone, PartialEq)]
pub struct Dialect {
    pub delimiter: Delimiter,
    pub decimal_comma: bool,
    /// Column names (empty names for unnamed columns); `None` for a headerless file.
    pub header: Option<Vec<String>>,
    /// Line of the header (1-based), if any.
    pub header_line: u64,
    /// Units row under the header, one entry per column.
    pub units: Option<Vec<String>>,
    /// Byte offset and line (1-based) of the first data row.
    pub data_offset: usize,
    pub data_line: u64,
    /// Lines before the first data row that are neither the header nor blank.
    pub skipped_lines: u64,
    /// Columns empty in every data row of the head.
    pub empty_columns: Vec<usize>,
    /// Columns filled only in the first rows: (column, the one value if there is one).
    pub metadata_columns: Vec<(usize, Option<f64>)>,
    /// Columns that number the samples (`count`, `Sample #`: consecutive integers in the head).
    pub index_columns: Vec<usize>,
    /// Fields per data row.
    pub width: usize,
    /// First data row's fields (for checks on the time column).
    pub first_row: Vec<String>,
    /// Second data row's fields (the time column's first step), empty if there is none.
    pub second_row: Vec<String>,
    /// A sampling rate stated above the header (`Sample rate: 2048 Hz`): Hz and its line.
    pub preamble_rate: Option<(f64, u64)>,
    /// A unit stated above the header for every channel (`# Units: g`), and its line.
    pub preamble_unit: Option<(super::unit::Unit, u64)>,
    /// An electrical unit stated above the header for every channel (`Vertical Units,V`),
    /// as written, and its line.
    pub preamble_electrical: Option<(String, u64)>,
}

fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with('#') || t.starts_with('%') || t.starts_with("//")
}

/// Splits one line into trimmed fields, quotes removed.
pub fn split_fields(line: &str, d: Delimiter) -> Vec<String> {
    if d == Delimiter::Whitespace {
        return line.split_whitespace().map(str::to_string).collect();
    }
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .delimiter(d.byte())
        .from_reader(line.as_bytes());
    let mut rec = csv::StringRecord::new();
    match rdr.read_record(&mut rec) {
        Ok(true) => rec.iter().map(|s| s.trim().to_string()).collect(),
        _ => line
            .split(d.byte() as char)
            .map(|s| s.trim().to_string())
            .collect(),
    }
}

/// A number in the file's decimal mark.
pub fn number(cell: &str, decimal_comma: bool) -> Option<f64> {
    let t = cell.trim();
    let v: f64 = if decimal_comma {
        t.replace(',', ".").parse().ok()?
    } else {
        t.parse().ok()?
    };
    v.is_finite().then_some(v)
}

/// Lines without a number at the end of a file (`End of data`) are a trailer, not the data's
/// layout: the delimiter and width are told from the lines above them (the row reader skips
/// the trailer with a note).
fn drop_trailer(content: &mut Vec<usize>, lines: &[(usize, &str)]) {
    let holds_number = |line: &str| {
        line.split([',', ';', '\t', ' '])
            .any(|c| super::trailer::is_number_cell(c.as_bytes(), &[false, true]))
    };
    let trailer = content
        .iter()
        .rev()
        .take_while(|&&i| !holds_number(lines[i].1))
        .count();
    if trailer <= super::trailer::MAX_TRAILER_LINES && trailer < content.len() {
        content.truncate(content.len() - trailer);
    }
}

/// Whether every non-empty field is a number, and at least one is.
fn numeric_row(fields: &[String], decimal_comma: bool) -> bool {
    let mut any = false;
    for f in fields {
        if f.is_empty() {
            continue;
        }
        if number(f, decimal_comma).is_none() && super::clock::parse(f).is_none() {
            return false;
        }
        any = true;
    }
    any
}

fn count_fields(line: &str, d: Delimiter) -> usize {
    match d {
        Delimiter::Whitespace => line.split_whitespace().count(),
        _ => line.bytes().filter(|&b| b == d.byte()).count() + 1,
    }
}

/// The delimiter every data line of the tail agrees on; tab and semicolon before comma, since
/// a decimal comma also counts the same on every line.
fn choose_delimiter(tail: &[&str]) -> Delimiter {
    for d in [Delimiter::Tab, Delimiter::Semicolon, Delimiter::Comma] {
        let counts: Vec<usize> = tail.iter().map(|l| count_fields(l, d)).collect();
        if counts.first().is_some_and(|&c| c > 1) && counts.iter().all(|&c| c == counts[0]) {
            return d;
        }
    }
    let counts: Vec<usize> = tail
        .iter()
        .map(|l| count_fields(l, Delimiter::Whitespace))
        .collect();
    if counts.first().is_some_and(|&c| c > 1) && counts.iter().all(|&c| c == counts[0]) {
        return Delimiter::Whitespace;
    }
    Delimiter::Comma
}

/// A decimal comma: some cell of the tail reads as a number once its comma is a point, and no
/// cell holds a point.
fn decimal_comma(tail: &[&str], d: Delimiter) -> bool {
    if d == Delimiter::Comma {
        return false;
    }
    let cells: Vec<String> = tail.iter().flat_map(|l| split_fields(l, d)).collect();
    let has_comma_number = cells
        .iter()
        .any(|c| c.contains(',') && number(c, true).is_some());
    let has_point = cells
        .iter()
        .any(|c| c.contains('.') && number(c, false).is_some());
    has_comma_number && !has_point
}

/// Reads the head of the file and decides the dialect. `None` when the head shows no clear
/// structure (no numeric row): the caller then reads the first line as the header, as plain
/// CSV, and the row parser reports what is wrong where.
pub fn sniff_dialect(head: &[u8], eof: bool) -> Option<Dialect> {
    let bom = if head.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    let text = String::from_utf8_lossy(&head[bom..]);
    let mut lines: Vec<(usize, &str)> = Vec::new();
    let mut pos = bom;
    let mut rest: &str = &text;
    while let Some(nl) = rest.find('\n') {
        let line = &rest[..nl];
        lines.push((pos, line.strip_suffix('\r').unwrap_or(line)));
        pos += nl + 1;
        rest = &rest[nl + 1..];
        if lines.len() == HEAD_LINES {
            break;
        }
    }
    if eof && !rest.is_empty() && lines.len() < HEAD_LINES {
        lines.push((pos, rest.strip_suffix('\r').unwrap_or(rest)));
    }
    // A lossy decode may shift offsets; only trust them when the head is valid UTF-8.
    if std::str::from_utf8(&head[bom..]).is_err() && text.len() != head.len() - bom {
        return None;
    }
    let mut content: Vec<usize> = (0..lines.len())
        .filter(|&i| !lines[i].1.trim().is_empty() && !is_comment(lines[i].1))
        .collect();
    if eof {
        drop_trailer(&mut content, &lines);
    }
    let tail: Vec<&str> = content
        .iter()
        .rev()
        .take(TAIL_LINES)
        .rev()
        .map(|&i| lines[i].1)
        .collect();
    if tail.is_empty() {
        return None;
    }
    let delimiter = choose_delimiter(&tail);
    let dec = decimal_comma(&tail, delimiter);
    let width = count_fields(tail[tail.len() - 1], delimiter);
    let first = content.iter().position(|&i| {
        let f = split_fields(lines[i].1, delimiter);
        f.len() == width && numeric_row(&f, dec)
    })?;
    let data_idx = content[first];
    let above: Vec<usize> = content[..first].to_vec();
    let (header, header_idx, units) = header_above(&lines, &above, delimiter, dec, width)?;
    // Comments and preamble lines count; blank lines do not.
    let nonblank = lines[..data_idx]
        .iter()
        .filter(|l| !l.1.trim().is_empty())
        .count() as u64;
    let skipped = nonblank - u64::from(header.is_some()) - u64::from(units.is_some());
    let rows: Vec<Vec<String>> = content[first..]
        .iter()
        .map(|&i| split_fields(lines[i].1, delimiter))
        .filter(|f| f.len() == width)
        .collect();
    let (empty_columns, metadata_columns) = column_use(&rows, width, dec);
    let index_columns = header
        .as_ref()
        .map(|h| index_columns(h, &rows, dec))
        .unwrap_or_default();
    let preamble_end = header_idx.unwrap_or(data_idx);
    let preamble_rate = (0..preamble_end).find_map(|i| {
        super::preamble_rate::rate_of_line(lines[i].1, dec).map(|hz| (hz, i as u64 + 1))
    });
    let preamble_unit = (0..preamble_end)
        .find_map(|i| super::preamble_unit::unit_of_line(lines[i].1).map(|u| (u, i as u64 + 1)));
    let preamble_electrical = (0..preamble_end).find_map(|i| {
        super::preamble_unit::electrical_of_line(lines[i].1).map(|u| (u, i as u64 + 1))
    });
    Some(Dialect {
        delimiter,
        decimal_comma: dec,
        header,
        header_line: header_idx.map_or(0, |i| i as u64 + 1),
        units,
        data_offset: lines[data_idx].0,
        data_line: data_idx as u64 + 1,
        skipped_lines: skipped,
        empty_columns,
        metadata_columns,
        index_columns,
        width,
        first_row: rows.first().cloned().unwrap_or_default(),
        second_row: rows.get(1).cloned().unwrap_or_default(),
        preamble_rate,
        preamble_unit,
        preamble_electrical,
    })
}

type HeaderFound = Option<(Option<Vec<String>>, Option<usize>, Option<Vec<String>>)>;

/// The header is the nearest non-numeric line above the data with as many fields (a trailing
/// delimiter may add one empty name); a second such line right under it is a units row.
fn header_above(
    lines: &[(usize, &str)],
    above: &[usize],
    d: Delimiter,
    dec: bool,
    width: usize,
) -> HeaderFound {
    let fits = |i: usize| -> Option<Vec<String>> {
        let mut f = split_fields(lines[i].1, d);
        while f.len() > width && f.last().is_some_and(|s| s.is_empty()) {
            f.pop();
        }
        while f.len() < width && d != Delimiter::Whitespace && f.len() + 1 == width {
            f.push(String::new());
        }
        // A name is never a number: a line holding one is a bad data row, not a header.
        let any_number = f.iter().any(|c| !c.is_empty() && c.parse::<f64>().is_ok())
            || f.iter().any(|c| number(c, dec).is_some());
        (f.len() == width && !any_number).then_some(f)
    };
    let Some(&last) = above.last() else {
        return Some((None, None, None));
    };
    let Some(lower) = fits(last) else {
        // As wide as the data but not a header: a broken row, which the plain reader reports.
        if count_fields(lines[last].1, d) == width {
            return None;
        }
        return Some((None, None, None));
    };
    if above.len() >= 2 {
        let prev = above[above.len() - 2];
        // A preamble line stating the rate (`Sample rate: 1000 Hz`) is never the header.
        let states_rate = super::preamble_rate::rate_of_line(lines[prev].1, dec).is_some();
        if prev + 1 == last
            && !states_rate
            && let Some(upper) = fits(prev).or_else(|| numbered_names(lines[prev].1, d, width))
            && looks_like_units(&lower)
            && !(fits(prev).is_some() && preamble_pair(lines, above, &upper, &lower, d))
        {
            return Some((Some(upper), Some(prev), Some(lower)));
        }
    }
    Some((Some(lower), Some(last), None))
}

/// Whether the line above a header-like `lower` row is the last of a preamble's key/value
/// lines rather than a header over a units row: `lower` names a time column (`Second`,
/// `Time`) while `upper` names none, and the line above `upper` is split into as many fields
/// as `upper` (one more `key,value` line of the block). A Siglent SDS2000X+ export ends its
/// preamble with `Software Version,1.3.7R5,` right above its `Second,Value` header.
fn preamble_pair(
    lines: &[(usize, &str)],
    above: &[usize],
    upper: &[String],
    lower: &[String],
    d: Delimiter,
) -> bool {
    let time_named = |row: &[String]| row.iter().any(|c| super::is_time_column(c));
    if !time_named(lower) || time_named(upper) || above.len() < 3 {
        return false;
    }
    let trimmed = |line: &str| {
        let mut f = split_fields(line, d);
        while f.last().is_some_and(|c| c.trim().is_empty()) {
            f.pop();
        }
        f.len()
    };
    let key_value = above[above.len() - 3];
    let prev = above[above.len() - 2];
    key_value + 1 == prev && trimmed(lines[key_value].1) == trimmed(lines[prev].1)
}

/// A header above a units row whose channels are numbered (an oscilloscope's `x-axis,1,2`
/// over `second,Volt,Volt`): small whole numbers as names, beside at least one word.
fn numbered_names(line: &str, d: Delimiter, width: usize) -> Option<Vec<String>> {
    let f = split_fields(line, d);
    let numbered = |c: &String| c.len() <= 3 && c.bytes().all(|b| b.is_ascii_digit());
    let words = f.iter().filter(|c| !c.is_empty() && !numbered(c)).count();
    let all_named = f
        .iter()
        .all(|c| !c.is_empty() && (numbered(c) || c.parse::<f64>().is_err()));
    (f.len() == width && words >= 1 && words < width && all_named).then_some(f)
}

/// Units rows hold short unit words: `s`, `g`, `m/s^2`, `[V]`, `(N)`, and the spectral
/// densities of a PSD table (`(m/s^2)^2/Hz`, 12 bytes); at least one of them must be a unit
/// (so that a scope's `TIME,CH1` under a `Label,` line stays the header).
fn looks_like_units(fields: &[String]) -> bool {
    let short_words = fields.iter().all(|f| {
        let t = f.trim_matches(|c| matches!(c, '[' | ']' | '(' | ')'));
        t.len() <= 14 && !t.contains(' ') && t.parse::<f64>().is_err()
    });
    short_words && fields.iter().any(|f| is_unit_word(f))
}

/// Units besides the accelerations and times the readers convert, as exports label columns.
const OTHER_UNITS: [&str; 32] = [
    "v", "mv", "uv", "µv", "volt", "volts", "n", "kn", "lbf", "lb", "pa", "kpa", "mpa", "psi",
    "bar", "mbar", "c", "°c", "degc", "k", "hz", "khz", "rpm", "db", "%", "m", "mm", "um", "µm",
    "in", "rad", "deg",
];

/// A unit: bracketed, a ratio (`g^2/Hz`), an acceleration or time unit, or another known one.
fn is_unit_word(f: &str) -> bool {
    let t = f.trim();
    let bracketed = t.starts_with(['[', '(']) && t.ends_with([']', ')']);
    bracketed
        || (t.contains('/') && t.len() > 2)
        || super::Unit::parse(t).is_ok_and(|u| u != super::Unit::AsIs)
        || super::TimeUnit::parse(t).is_ok()
        || OTHER_UNITS.contains(&t.to_lowercase().as_str())
}

/// Names of a column that numbers the samples, once lower-cased and trimmed of `.`, `_`, `:`.
const INDEX_NAMES: [&str; 16] = [
    "count",
    "counter",
    "index",
    "idx",
    "sample",
    "samples",
    "sample no",
    "sample nr",
    "sample number",
    "sample #",
    "sample index",
    "n",
    "no",
    "nr",
    "#",
    "scan",
];

/// Columns named like a sample counter whose values in the head step by exactly 1: they
/// number the rows, they are not a measured channel.
fn index_columns(header: &[String], rows: &[Vec<String>], dec: bool) -> Vec<usize> {
    let named = |c: usize| {
        let n = header[c].to_lowercase().replace(['.', '_', ':'], " ");
        INDEX_NAMES.contains(&n.split_whitespace().collect::<Vec<_>>().join(" ").as_str())
    };
    let counts = |c: usize| {
        let v: Option<Vec<f64>> = rows.iter().map(|r| number(&r[c], dec)).collect();
        v.is_some_and(|v| {
            v.len() >= 2
                && v.windows(2)
                    .all(|w| w[1] - w[0] == 1.0 && w[0].fract() == 0.0)
        })
    };
    (0..header.len())
        .filter(|&c| named(c) && counts(c))
        .collect()
}

/// Columns empty in every row, and columns filled only in a first run of rows (metadata).
fn column_use(
    rows: &[Vec<String>],
    width: usize,
    dec: bool,
) -> (Vec<usize>, Vec<(usize, Option<f64>)>) {
    let mut empty = Vec::new();
    let mut meta = Vec::new();
    for c in 0..width {
        let filled: Vec<bool> = rows.iter().map(|r| !r[c].is_empty()).collect();
        let n = filled.iter().filter(|&&f| f).count();
        if n == 0 {
            empty.push(c);
            continue;
        }
        let prefix = filled.iter().take_while(|&&f| f).count();
        // Metadata: a top block, then empty for the rest of the head (at least as many rows).
        if prefix == n && n < rows.len() && rows.len() - n >= 2 {
            let values: Vec<Option<f64>> = rows[..n].iter().map(|r| number(&r[c], dec)).collect();
            let one = (n == 1).then(|| values[0]).flatten();
            meta.push((c, one));
        }
    }
    (empty, meta)
}
