//! A byte cursor over a UFF file that hands out text lines and, for the binary dataset 58b,
//! raw byte blocks, keeping the line number an editor would show.

pub(super) struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// Line number (1-based) of the next line to be read.
    line: u64,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8]) -> Cursor<'a> {
        Cursor {
            bytes,
            pos: 0,
            line: 1,
        }
    }

    /// Line number (1-based) of the next line.
    pub fn line(&self) -> u64 {
        self.line
    }

    pub fn at_end(&self) -> bool {
        self.pos >= self.bytes.len()
    }

    /// The next line without its `\n` or `\r\n`: UTF-8, or else Windows-1252, the code page
    /// in which Windows exporters write `m/s²` and the VibControl `g²/Hz` (0xB2).
    pub fn next_line(&mut self) -> Option<String> {
        if self.at_end() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let end = memchr::memchr(b'\n', rest).unwrap_or(rest.len());
        let raw = &rest[..end];
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        self.pos += (end + 1).min(rest.len());
        self.line += 1;
        Some(crate::signal::ingest::text::decode(raw))
    }

    /// The next `n` raw bytes (binary data of a 58b record); line numbering follows the
    /// newline bytes inside them so that later lines keep the number an editor shows.
    pub fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.pos.checked_add(n)?;
        let block = self.bytes.get(self.pos..end)?;
        self.pos = end;
        self.line += memchr::memchr_iter(b'\n', block).count() as u64;
        Some(block)
    }

    /// After a binary block: the rest of its line (normally just the line end).
    pub fn finish_binary_line(&mut self) {
        let rest = &self.bytes[self.pos.min(self.bytes.len())..];
        if rest.starts_with(b"\r\n") {
            self.pos += 2;
            self.line += 1;
        } else if rest.starts_with(b"\n") {
            self.pos += 1;
            self.line += 1;
        }
    }
}
