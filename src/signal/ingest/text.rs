//! The text encoding of a log, so that every reader sees UTF-8 with `\n` line ends whatever the
//! lab's software wrote: Excel's "Unicode text" is UTF-16 with a byte-order mark, Windows
//! programs write units such as `m/s²` or `µm` in the ANSI code page (Windows-1252, where ² is
//! the single byte 0xB2), and some instruments end lines with a carriage return alone.
//!
//! Hand-written: std decodes UTF-16 (`char::decode_utf16`) and Windows-1252 is one table of 32
//! entries; a streaming reader keeps the log reader's flat memory on large files.

use std::io::Read;
use std::path::Path;

/// How a text log is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    Utf8,
    Utf16Le,
    Utf16Be,
    /// The Windows ANSI code page of Western Europe and America (a superset of Latin-1's
    /// printable characters).
    Windows1252,
}

/// What the head of a file says about its text form.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextForm {
    pub encoding: Encoding,
    /// Whether a byte-order mark told the encoding.
    pub bom: bool,
    /// Lines end with a carriage return alone (classic Mac OS, some instruments).
    pub cr_lines: bool,
}

impl TextForm {
    /// UTF-8 with `\n` line ends: the bytes are read as they are.
    pub fn is_plain(&self) -> bool {
        self.encoding == Encoding::Utf8 && !self.cr_lines
    }

    /// The stderr/JSON note for a file that is not plain UTF-8.
    pub fn note(&self, file: &Path) -> Option<String> {
        let f = file.display();
        let how = match (self.encoding, self.bom) {
            (Encoding::Utf8, _) => None,
            (Encoding::Utf16Le, true) => Some("UTF-16LE (byte-order mark)"),
            (Encoding::Utf16Be, true) => Some("UTF-16BE (byte-order mark)"),
            (Encoding::Utf16Le, false) => Some("UTF-16LE (no byte-order mark: every other byte 0)"),
            (Encoding::Utf16Be, false) => Some("UTF-16BE (no byte-order mark: every other byte 0)"),
            (Encoding::Windows1252, _) => Some("Windows-1252 (not valid UTF-8)"),
        };
        let mut parts: Vec<String> = how
            .map(|h| format!("text encoded as {h}"))
            .into_iter()
            .collect();
        if self.cr_lines {
            parts.push("lines end with a carriage return alone".into());
        }
        (!parts.is_empty()).then(|| format!("{f}: {}", parts.join("; ")))
    }
}

/// Bytes of the head that decide a UTF-16 encoding without a byte-order mark.
const UTF16_PROBE: usize = 512;

/// Tells the text form from the first bytes of a file (a few KB are enough).
pub fn detect(head: &[u8]) -> TextForm {
    let (encoding, bom) = if head.starts_with(b"\xEF\xBB\xBF") {
        (Encoding::Utf8, true)
    } else if head.starts_with(b"\xFF\xFE") && !head.starts_with(b"\xFF\xFE\0\0") {
        (Encoding::Utf16Le, true)
    } else if head.starts_with(b"\xFE\xFF") {
        (Encoding::Utf16Be, true)
    } else if let Some(e) = utf16_by_zeros(head) {
        (e, false)
    } else if is_single_byte_text(head) {
        (Encoding::Windows1252, false)
    } else {
        (Encoding::Utf8, false)
    };
    let mut form = TextForm {
        encoding,
        bom,
        cr_lines: false,
    };
    let mut decoded = Vec::new();
    Decoder::new(form).push(head, true, &mut decoded);
    form.cr_lines = decoded.contains(&b'\r') && !decoded.contains(&b'\n');
    form
}

/// UTF-16 of mostly ASCII text without a byte-order mark: one byte of every pair is zero.
fn utf16_by_zeros(head: &[u8]) -> Option<Encoding> {
    let probe = &head[..head.len().min(UTF16_PROBE) & !1];
    let pairs = probe.len() / 2;
    if pairs < 4 {
        return None;
    }
    let zeros = |odd: usize| {
        probe
            .iter()
            .skip(odd)
            .step_by(2)
            .filter(|&&b| b == 0)
            .count()
    };
    let (even, odd) = (zeros(0), zeros(1));
    let mostly = |z: usize| z * 10 >= pairs * 9;
    let hardly = |z: usize| z * 10 <= pairs;
    if mostly(odd) && hardly(even) {
        Some(Encoding::Utf16Le)
    } else if mostly(even) && hardly(odd) {
        Some(Encoding::Utf16Be)
    } else {
        None
    }
}

/// Not UTF-8 (an invalid sequence, not just one cut by the end of the head) and free of NUL
/// bytes: a single-byte code page. Files with NUL bytes stay with the binary check.
fn is_single_byte_text(head: &[u8]) -> bool {
    match std::str::from_utf8(head) {
        Ok(_) => false,
        Err(e) => e.error_len().is_some() && !head.contains(&0),
    }
}

/// Windows-1252's characters for 0x80–0x9F (the five undefined bytes map to the C1 controls of
/// the same value, as WHATWG's decoder does); every other byte is its Latin-1 code point.
const CP1252_HIGH: [char; 32] = [
    '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8d}', 'Ž', '\u{8f}',
    '\u{90}', '‘', '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9d}', 'ž', 'Ÿ',
];

fn cp1252(b: u8) -> char {
    match b {
        0x80..=0x9F => CP1252_HIGH[usize::from(b - 0x80)],
        _ => char::from(b),
    }
}

/// Incremental decoding to UTF-8: bytes arrive in chunks that may cut a character.
struct Decoder {
    form: TextForm,
    /// Raw bytes of a character cut by the end of the last chunk.
    pending: Vec<u8>,
    /// The byte-order mark is dropped once, at the start.
    started: bool,
    /// The last byte written was a CR that became a line end (a following LF is dropped).
    after_cr: bool,
}

impl Decoder {
    fn new(form: TextForm) -> Self {
        Decoder {
            form,
            pending: Vec::new(),
            started: false,
            after_cr: false,
        }
    }

    /// Decodes `chunk` (after any bytes held back) onto `out`; `last` flushes what is held.
    fn push(&mut self, chunk: &[u8], last: bool, out: &mut Vec<u8>) {
        let mut bytes = std::mem::take(&mut self.pending);
        bytes.extend_from_slice(chunk);
        let start = out.len();
        let mut text = String::new();
        match self.form.encoding {
            Encoding::Utf8 => out.extend_from_slice(&bytes),
            Encoding::Windows1252 => text.extend(bytes.iter().map(|&b| cp1252(b))),
            Encoding::Utf16Le | Encoding::Utf16Be => self.utf16(&bytes, last, &mut text),
        }
        out.extend_from_slice(text.as_bytes());
        if !self.started && out.len() > start {
            self.started = true;
            if self.form.encoding != Encoding::Utf8
                && out[start..].starts_with("\u{feff}".as_bytes())
            {
                out.drain(start..start + 3);
            }
        }
        if self.form.cr_lines {
            self.cr_to_lf(out, start);
        }
    }

    fn utf16(&mut self, bytes: &[u8], last: bool, text: &mut String) {
        let be = self.form.encoding == Encoding::Utf16Be;
        let mut units: Vec<u16> = bytes
            .chunks_exact(2)
            .map(|p| {
                if be {
                    u16::from_be_bytes([p[0], p[1]])
                } else {
                    u16::from_le_bytes([p[0], p[1]])
                }
            })
            .collect();
        let mut keep = bytes.len() % 2;
        // A high surrogate at the end waits for its partner in the next chunk.
        if !last && units.last().is_some_and(|u| (0xD800..0xDC00).contains(u)) {
            units.pop();
            keep += 2;
        }
        if last {
            keep = 0;
        }
        self.pending = bytes[bytes.len() - keep..].to_vec();
        text.extend(char::decode_utf16(units).map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER)));
    }

    /// A CR alone ends a line: it becomes LF, and a LF right after it is dropped.
    fn cr_to_lf(&mut self, out: &mut Vec<u8>, start: usize) {
        let mut w = start;
        for r in start..out.len() {
            let b = out[r];
            if b == b'\n' && self.after_cr {
                self.after_cr = false;
                continue;
            }
            self.after_cr = b == b'\r';
            out[w] = if b == b'\r' { b'\n' } else { b };
            w += 1;
        }
        out.truncate(w);
    }
}

/// A reader that yields a text file as UTF-8 with `\n` line ends.
pub struct TextReader<R: Read> {
    inner: R,
    decoder: Decoder,
    out: Vec<u8>,
    at: usize,
    done: bool,
}

impl<R: Read> TextReader<R> {
    pub fn new(inner: R, form: TextForm) -> Self {
        TextReader {
            inner,
            decoder: Decoder::new(form),
            out: Vec::new(),
            at: 0,
            done: false,
        }
    }
}

impl<R: Read> Read for TextReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.decoder.form.is_plain() {
            return self.inner.read(buf);
        }
        while self.at == self.out.len() && !self.done {
            let mut raw = vec![0u8; buf.len().clamp(4096, 1 << 16)];
            let n = self.inner.read(&mut raw)?;
            self.done = n == 0;
            self.out.clear();
            self.at = 0;
            self.decoder.push(&raw[..n], self.done, &mut self.out);
        }
        let n = buf.len().min(self.out.len() - self.at);
        buf[..n].copy_from_slice(&self.out[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// Opens a text file for reading as UTF-8 with `\n` line ends, with its form.
pub fn open(path: &Path) -> std::io::Result<(TextReader<std::fs::File>, TextForm)> {
    let mut head = Vec::new();
    std::fs::File::open(path)?
        .take(8192)
        .read_to_end(&mut head)?;
    let form = detect(&head);
    Ok((TextReader::new(std::fs::File::open(path)?, form), form))
}

/// A whole text file as UTF-8 with `\n` line ends (invalid UTF-8 left to the caller's parser).
pub fn read_all(path: &Path) -> std::io::Result<Vec<u8>> {
    let (mut reader, _) = open(path)?;
    let mut out = Vec::new();
    reader.read_to_end(&mut out)?;
    Ok(out)
}

/// Text already in memory as a string, its whole length deciding the encoding (a stray
/// code-page byte anywhere makes it Windows-1252).
pub fn decode(bytes: &[u8]) -> String {
    let mut out = Vec::new();
    Decoder::new(detect(bytes)).push(bytes, true, &mut out);
    String::from_utf8(out).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(bytes: &[u8], chunk: usize) -> (String, TextForm) {
        let form = detect(bytes);
        let mut reader = TextReader::new(
            ChunkedReader {
                bytes,
                at: 0,
                chunk,
            },
            form,
        );
        let mut out = Vec::new();
        reader.read_to_end(&mut out).unwrap();
        (String::from_utf8(out).unwrap(), form)
    }

    /// Hands out at most `chunk` bytes per read, to cut characters between reads.
    struct ChunkedReader<'a> {
        bytes: &'a [u8],
        at: usize,
        chunk: usize,
    }

    impl Read for ChunkedReader<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = buf.len().min(self.chunk).min(self.bytes.len() - self.at);
            buf[..n].copy_from_slice(&self.bytes[self.at..self.at + n]);
            self.at += n;
            Ok(n)
        }
    }

    const TEXT: &str = "Time [s]\tA [m/s²]\tB [µm] 𝑥\r\n0.0\t1.5\t2\r\n";

    fn utf16(text: &str, be: bool) -> Vec<u8> {
        text.encode_utf16()
            .flat_map(|u| if be { u.to_be_bytes() } else { u.to_le_bytes() })
            .collect()
    }

    #[test]
    fn utf16_with_and_without_a_byte_order_mark_reads_as_the_same_text() {
        for chunk in [1, 3, 7, 4096] {
            for be in [false, true] {
                let bom: &[u8] = if be { b"\xFE\xFF" } else { b"\xFF\xFE" };
                let with = [bom, &utf16(TEXT, be)].concat();
                let (text, form) = decode(&with, chunk);
                assert_eq!(text, TEXT, "chunk {chunk}, big-endian {be}");
                assert!(form.bom);
                let (text, form) = decode(&utf16(TEXT, be), chunk);
                assert_eq!(text, TEXT, "chunk {chunk}, big-endian {be}, no BOM");
                assert!(!form.bom);
                let want = if be {
                    Encoding::Utf16Be
                } else {
                    Encoding::Utf16Le
                };
                assert_eq!(form.encoding, want);
            }
        }
    }

    #[test]
    fn windows_1252_units_and_cr_line_ends_read_as_unicode() {
        // `m/s²`, `µm`, `°C` and an en dash as a Windows program writes them.
        let bytes = b"Time [s];A [m/s\xB2];B [\xB5m];T [\xB0C] \x96 x\r0,0;1,5;2;3\r";
        let (text, form) = decode(bytes, 5);
        assert_eq!(text, "Time [s];A [m/s²];B [µm];T [°C] – x\n0,0;1,5;2;3\n");
        assert_eq!(form.encoding, Encoding::Windows1252);
        assert!(form.cr_lines);
    }

    #[test]
    fn plain_utf8_and_binary_heads_are_left_as_they_are() {
        let plain = detect(TEXT.as_bytes());
        assert!(plain.is_plain());
        assert_eq!(decode(TEXT.as_bytes(), 3).0, TEXT);
        // A UTF-8 character cut by the end of the head is not a code-page byte.
        let cut = &TEXT.as_bytes()[..TEXT.find('²').unwrap() + 1];
        assert!(detect(cut).is_plain());
        // NUL bytes that do not pair up as UTF-16 stay for the binary check.
        assert!(detect(b"\x00\x01\x02\x03\xff\xfe\x00\x00binary\x00\xb2").is_plain());
    }
}
