//! WAV files (RIFF `WAVE`), as portable recorders and some data-acquisition systems export
//! logs: PCM integers of 8, 16, 24 or 32 bits or IEEE floats of 32 or 64 bits, plain or
//! `WAVE_FORMAT_EXTENSIBLE`, channels interleaved frame by frame. A WAV states its rate but no
//! unit and no calibration: integers are read as fractions of full scale (÷ 2^(bits − 1); 8-bit
//! PCM is offset by 128), floats as they are, and every channel is kept as it is (`--units`
//! names a unit when the values are in one).
//!
//! Hand-written: the chunk layout is small and fully specified (Microsoft, "Multiple Channel
//! Audio Data and WAVE Files"), and a malformed file must give an error, never a panic.

use super::table::{Rate, Series, Table};
use crate::error::SignalError;
use std::path::Path;

const PCM: u16 = 1;
const IEEE_FLOAT: u16 = 3;
const EXTENSIBLE: u16 = 0xFFFE;

/// `RIFF` … `WAVE`, or the 64-bit `RF64`/`BW64` forms (refused with a reason).
pub fn looks_like_wav(head: &[u8]) -> bool {
    head.len() >= 12
        && matches!(&head[0..4], b"RIFF" | b"RF64" | b"BW64")
        && &head[8..12] == b"WAVE"
}

/// What the `fmt ` chunk says.
#[derive(Debug, Clone, Copy)]
struct Format {
    float: bool,
    channels: usize,
    rate: u32,
    block_align: usize,
    bits: usize,
}

fn u16_at(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Reads the `fmt ` chunk body (at byte `at` of the file, for messages).
fn format(body: &[u8], at: usize) -> Result<Format, String> {
    if body.len() < 16 {
        return Err(format!(
            "the `fmt ` chunk at byte {at} holds {} bytes, fewer than 16",
            body.len()
        ));
    }
    let mut tag = u16_at(body, 0);
    if tag == EXTENSIBLE {
        if body.len() < 26 {
            return Err(format!(
                "the extensible `fmt ` chunk at byte {at} is cut short"
            ));
        }
        // The sub-format GUID starts with the format tag it stands for.
        tag = u16_at(body, 24);
    }
    let f = Format {
        float: tag == IEEE_FLOAT,
        channels: u16_at(body, 2) as usize,
        rate: u32_at(body, 4),
        block_align: u16_at(body, 12) as usize,
        bits: u16_at(body, 14) as usize,
    };
    let sample_ok = match (tag, f.bits) {
        (PCM, 8 | 16 | 24 | 32) | (IEEE_FLOAT, 32 | 64) => true,
        (PCM | IEEE_FLOAT, _) => false,
        (other, _) => {
            return Err(format!(
                "format tag {other} (compressed audio: µ-law, A-law, ADPCM, ...): export the \
                 log as PCM or float WAV"
            ));
        }
    };
    if !sample_ok {
        return Err(format!(
            "{} samples of {} bits",
            if f.float { "float" } else { "PCM" },
            f.bits
        ));
    }
    if f.channels == 0 || f.rate == 0 || f.block_align != f.channels * f.bits / 8 {
        return Err(format!(
            "the `fmt ` chunk at byte {at} states {} channel(s) at {} Hz with {}-byte frames of \
             {}-bit samples, which do not agree",
            f.channels, f.rate, f.block_align, f.bits
        ));
    }
    Ok(f)
}

/// One sample as a real number: a fraction of full scale for integers.
fn sample(b: &[u8], f: &Format) -> f64 {
    match (f.float, f.bits) {
        (true, 32) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        (true, _) => f64::from_le_bytes(b[..8].try_into().unwrap_or_default()),
        (false, 8) => (b[0] as f64 - 128.0) / 128.0,
        (false, 16) => i16::from_le_bytes([b[0], b[1]]) as f64 / 32768.0,
        (false, 24) => (i32::from_le_bytes([0, b[0], b[1], b[2]]) >> 8) as f64 / 8_388_608.0,
        (false, _) => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64 / 2_147_483_648.0,
    }
}

/// A chunk: its id, the byte where its body starts, and the body.
type Chunk<'a> = ([u8; 4], usize, &'a [u8]);

/// A chunk id as text: printable ASCII as it is, any other byte as `\xNN`.
fn printable(id: &[u8]) -> String {
    id.iter()
        .map(|&b| {
            if b.is_ascii_graphic() || b == b' ' {
                char::from(b).to_string()
            } else {
                format!("\\x{b:02X}")
            }
        })
        .collect()
}

/// The chunks of the file, in order.
fn chunks(bytes: &[u8]) -> Result<Vec<Chunk<'_>>, String> {
    let mut out = Vec::new();
    let mut at = 12;
    while at + 8 <= bytes.len() {
        let id = [bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]];
        let size = u32_at(bytes, at + 4) as usize;
        let body = at + 8;
        if &id == b"data" && size == 0 && body < bytes.len() {
            // A writer that stopped before going back to fill in the sizes: the samples follow,
            // but how many were meant is not stated, and the bytes after are not chunks.
            return Err(format!(
                "the `data` chunk at byte {at} is declared empty (size 0) but {} bytes follow \
                 it: the header was never finished (the recording stopped before the writer \
                 filled in the sizes); re-export the file, or repair its header",
                bytes.len() - body
            ));
        }
        let end = body
            .checked_add(size)
            .filter(|&e| e <= bytes.len())
            .ok_or_else(|| {
                format!(
                    "chunk `{}` at byte {at} announces {size} bytes, but the file ends at byte {}",
                    printable(&id),
                    bytes.len()
                )
            })?;
        out.push((id, body, &bytes[body..end]));
        // Chunks are padded to an even length.
        at = end + (size & 1);
    }
    Ok(out)
}

/// Reads a WAV file's channels.
pub fn read_wav(path: &Path, bytes: &[u8]) -> Result<Table, SignalError> {
    let bad = |message: String| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("WAV: {message}"),
    };
    if bytes.len() < 12 {
        return Err(bad("shorter than the 12-byte RIFF header".into()));
    }
    if &bytes[0..4] != b"RIFF" {
        return Err(bad(format!(
            "{} (a WAV above 4 GB) is not read: split the recording",
            printable(&bytes[0..4])
        )));
    }
    let chunks = chunks(bytes).map_err(bad)?;
    let (fmt_at, fmt_body) = chunks
        .iter()
        .find(|(id, ..)| id == b"fmt ")
        .map(|(_, at, b)| (*at, *b))
        .ok_or_else(|| bad("no `fmt ` chunk".into()))?;
    let f = format(fmt_body, fmt_at).map_err(bad)?;
    let (_, data_at, data) = chunks
        .iter()
        .find(|(id, ..)| id == b"data")
        .ok_or_else(|| bad("no `data` chunk".into()))?;
    let frames = data.len() / f.block_align;
    let mut notes = vec![format!(
        "{}: WAV, {} channel(s) of {}-bit {} at {} Hz, {frames} frames; values as they are ({}), no unit stated",
        path.display(),
        f.channels,
        f.bits,
        if f.float { "float" } else { "PCM" },
        f.rate,
        if f.float {
            "floats"
        } else {
            "fractions of full scale"
        }
    )];
    if data.len() % f.block_align != 0 {
        notes.push(format!(
            "{}: the `data` chunk at byte {data_at} ends with {} bytes of a partial frame: not read",
            path.display(),
            data.len() % f.block_align
        ));
    }
    let width = f.bits / 8;
    let series = (0..f.channels)
        .map(|c| Series {
            name: format!("ch{}", c + 1),
            unit_label: String::new(),
            values: data
                .chunks_exact(f.block_align)
                .map(|frame| sample(&frame[c * width..(c + 1) * width], &f))
                .collect(),
        })
        .collect();
    Ok(Table {
        format: "wav",
        delimiter: "none (binary)",
        decimal: ".",
        series,
        rate: Rate::Stated(f.rate as f64, "the WAV `fmt ` chunk".into()),
        ignored: Vec::new(),
        unreadable: Vec::new(),
        notes,
        warnings: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_samples_are_fractions_of_full_scale() {
        let f = |bits| Format {
            float: false,
            channels: 1,
            rate: 1,
            block_align: bits / 8,
            bits,
        };
        assert_eq!(sample(&[0, 0x80], &f(16)), -1.0);
        assert_eq!(
            sample(&[0xFF, 0xFF, 0x7F], &f(24)),
            8_388_607.0 / 8_388_608.0
        );
        assert_eq!(sample(&[0, 0, 0x80], &f(24)), -1.0);
        assert_eq!(sample(&[128], &f(8)), 0.0);
    }
}
