//! DAQmx raw data in TDMS, as NI-DAQmx logging writes it: each channel's raw data index lists
//! its scalers (where its unscaled values sit in the rows of an acquisition card's buffer), and
//! each buffer's rows are read whole. The scaling to physical units is in `scaling`.

use super::values::{Cursor, DataType, real_value};

/// Raw data index headers of DAQmx channels.
pub const FORMAT_CHANGING: u32 = 0x1269;
pub const DIGITAL_LINE: u32 = 0x126A;

/// Where one of a channel's raw values sits in its buffer's rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaler {
    pub data_type: DataType,
    pub buffer: usize,
    pub byte_offset: usize,
    /// The bit within the byte, for a digital line.
    pub bit: Option<u8>,
    pub scale_id: u32,
}

/// A DAQmx channel's raw data index: its scalers and the row width of every buffer.
#[derive(Debug, Clone, PartialEq)]
pub struct DaqmxIndex {
    pub scalers: Vec<Scaler>,
    pub widths: Vec<usize>,
}

/// DAQmx scaler type codes (not the TDMS ones).
fn scaler_type(code: u32) -> Result<DataType, String> {
    Ok(match code {
        0 => DataType::U8,
        1 => DataType::I8,
        2 => DataType::U16,
        3 => DataType::I16,
        4 => DataType::U32,
        5 => DataType::I32,
        6 => DataType::U64,
        7 => DataType::I64,
        8 => DataType::F32,
        9 => DataType::F64,
        other => return Err(format!("DAQmx scaler type {other} is not a number type")),
    })
}

/// Reads the DAQmx part of a raw data index (after its header): the channel's data type, its
/// number of values per chunk and its scalers.
pub fn read_index(
    c: &mut Cursor,
    header: u32,
    path: &str,
) -> Result<(DataType, u64, DaqmxIndex), String> {
    let (data_type, count) = c.index_head(path)?;
    let n = c.u32()?;
    let mut scalers = Vec::new();
    for _ in 0..n {
        let data_type = scaler_type(c.u32()?).map_err(|e| format!("object `{path}`: {e}"))?;
        let buffer = c.u32()? as usize;
        let offset = c.u32()? as usize;
        let (byte_offset, bit) = if header == DIGITAL_LINE {
            c.take(1)?;
            (offset / 8, Some((offset % 8) as u8))
        } else {
            c.u32()?;
            (offset, None)
        };
        let scale_id = c.u32()?;
        scalers.push(Scaler {
            data_type,
            buffer,
            byte_offset,
            bit,
            scale_id,
        });
    }
    let widths = (0..c.u32()?)
        .map(|_| c.u32().map(|w| w as usize))
        .collect::<Result<Vec<_>, _>>()?;
    for s in &scalers {
        let size = s.data_type.size().unwrap_or(0);
        match widths.get(s.buffer) {
            Some(w) if s.byte_offset + size <= *w => {}
            _ => {
                return Err(format!(
                    "object `{path}`: a DAQmx scaler reads {size} bytes at byte {} of buffer {}, outside its rows (widths {widths:?})",
                    s.byte_offset, s.buffer
                ));
            }
        }
    }
    Ok((data_type, count, DaqmxIndex { scalers, widths }))
}

/// Rows and width of every buffer of a DAQmx segment; every channel must state the same
/// widths.
pub fn buffers(objs: &[(&str, u64, &DaqmxIndex)]) -> Result<Vec<(u64, usize)>, String> {
    let Some((first, _, ix)) = objs.first() else {
        return Ok(Vec::new());
    };
    let mut dims: Vec<(u64, usize)> = ix.widths.iter().map(|&w| (0, w)).collect();
    for (path, count, ix) in objs {
        if ix.widths != objs[0].2.widths {
            return Err(format!(
                "DAQmx buffer widths of `{path}` ({:?}) differ from those of `{first}` ({:?})",
                ix.widths, objs[0].2.widths
            ));
        }
        for s in &ix.scalers {
            dims[s.buffer].0 = dims[s.buffer].0.max(*count);
        }
    }
    Ok(dims)
}

/// Reads one chunk: every buffer's rows, and from them every channel's values (the first
/// scaler's; a channel with several is refused by the caller).
pub fn read_chunk(
    c: &mut Cursor,
    objs: &[(&str, u64, &DaqmxIndex)],
    dims: &[(u64, usize)],
) -> Result<Vec<Vec<f64>>, String> {
    let mut out = vec![Vec::new(); objs.len()];
    for (b, &(rows, width)) in dims.iter().enumerate() {
        let bytes = usize::try_from(rows)
            .ok()
            .and_then(|r| r.checked_mul(width))
            .ok_or_else(|| "the DAQmx buffer size overflows".to_string())?;
        let block = c.take(bytes)?;
        for (k, (_, _, ix)) in objs.iter().enumerate() {
            let Some(s) = ix.scalers.first().filter(|s| s.buffer == b) else {
                continue;
            };
            let size = s.data_type.size().unwrap_or(0);
            out[k].extend(block.chunks_exact(width.max(1)).map(|row| {
                let v = real_value(
                    s.data_type,
                    &row[s.byte_offset..s.byte_offset + size],
                    c.big,
                );
                match s.bit {
                    Some(bit) => ((v as u64 >> bit) & 1) as f64,
                    None => v,
                }
            }));
        }
    }
    Ok(out)
}
