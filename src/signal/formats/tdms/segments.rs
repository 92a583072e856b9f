//! The segments of a TDMS file: the 28-byte lead-in, the metadata (the object list, carried
//! from segment to segment, raw data indexes and properties) and the raw data, contiguous or
//! interleaved, in chunks. Layout from NI, "TDMS File Format Internal Structure".

use std::collections::HashMap;

use super::daqmx::{self, DaqmxIndex};
use super::raw;
use super::values::{Cursor, DataType, PropValue};

const TOC_META_DATA: u32 = 1 << 1;
const TOC_NEW_OBJ_LIST: u32 = 1 << 2;
const TOC_RAW_DATA: u32 = 1 << 3;
pub(super) const TOC_INTERLEAVED: u32 = 1 << 5;
pub(super) const TOC_BIG_ENDIAN: u32 = 1 << 6;
pub(super) const TOC_DAQMX_RAW_DATA: u32 = 1 << 7;

const LEAD_IN: usize = 28;
/// Raw data index headers with a meaning of their own.
const NO_DATA: u32 = 0xFFFF_FFFF;
const SAME_AS_BEFORE: u32 = 0;

/// How many values of which type an object holds per chunk of a segment.
#[derive(Debug, Clone, PartialEq)]
pub struct RawIndex {
    pub data_type: DataType,
    pub count: u64,
    /// Bytes per chunk, for strings (the index states it).
    pub text_bytes: Option<u64>,
    /// Where a DAQmx channel's values sit in the buffers' rows.
    pub daqmx: Option<DaqmxIndex>,
}

impl RawIndex {
    pub(super) fn bytes(&self) -> Option<u64> {
        if self.daqmx.is_some() {
            return None;
        }
        match self.text_bytes {
            Some(b) => Some(b),
            None => self.count.checked_mul(self.data_type.size()? as u64),
        }
    }
}

/// An object of the current object list.
#[derive(Debug, Clone)]
pub(super) struct Listed {
    pub(super) path: String,
    pub(super) index: Option<RawIndex>,
    pub(super) has_data: bool,
}

/// The values an object holds, over all segments.
#[derive(Debug, Clone, PartialEq)]
pub enum Data {
    None,
    Reals(Vec<f64>),
    /// Timestamps in 2^-64 s.
    Times(Vec<i128>),
    /// Values not read as a channel (strings, booleans, complex): what they are.
    Skipped(String),
}

/// A group, a channel or the file object: its path, properties and values.
#[derive(Debug, Clone)]
pub struct Object {
    pub path: String,
    pub properties: Vec<(String, PropValue)>,
    pub data: Data,
    /// The segment where its data type changed, if it did (its values are then not read).
    pub type_changed: Option<String>,
    /// The scale id of a DAQmx channel's scaler: its values are unscaled until the scaling
    /// stated in the properties is applied.
    pub daqmx_scale_id: Option<u32>,
}

/// A whole file read: its objects in the order they first appear, and notes.
pub struct Parsed {
    pub objects: Vec<Object>,
    pub segments: usize,
    pub version: u32,
    pub big_endian: bool,
    pub notes: Vec<String>,
}

/// Where a segment lies and how it is laid out.
pub(super) struct Segment {
    pub(super) number: usize,
    pub(super) start: usize,
    pub(super) toc: u32,
    pub(super) data_start: usize,
    pub(super) end: usize,
    pub(super) cut_short: bool,
}

/// State carried from segment to segment.
#[derive(Default)]
pub(super) struct State {
    pub(super) list: Vec<Listed>,
    /// The raw data index each object was last given, for a later "same as before".
    pub(super) indexes: HashMap<String, RawIndex>,
    pub(super) objects: Vec<Object>,
    pub(super) seen_metadata: bool,
    pub(super) notes: Vec<String>,
}

/// Reads every segment of a TDMS file. Errors name the segment and the byte.
pub fn parse(bytes: &[u8]) -> Result<Parsed, String> {
    let mut st = State::default();
    let (mut pos, mut number, mut version, mut big) = (0, 0, 0, false);
    while pos < bytes.len() {
        number += 1;
        let seg = match lead_in(bytes, pos, number)? {
            Some((seg, v, b)) => {
                (version, big) = (v, b);
                seg
            }
            None => {
                st.notes.push(format!(
                    "the last {} bytes, from byte {pos}, are not a whole segment lead-in: not read",
                    bytes.len() - pos
                ));
                break;
            }
        };
        let at = |e: String| format!("segment {} (byte {}): {e}", seg.number, seg.start);
        if seg.toc & TOC_META_DATA != 0 {
            metadata(bytes, &seg, &mut st).map_err(at)?;
            st.seen_metadata = true;
        } else if !st.seen_metadata {
            return Err(at(
                "no metadata, and no segment before it that has some".into()
            ));
        }
        if seg.toc & TOC_RAW_DATA != 0 {
            raw::raw_data(bytes, &seg, &mut st).map_err(at)?;
        }
        pos = seg.end;
    }
    if number == 0 {
        return Err("empty file".into());
    }
    Ok(Parsed {
        objects: st.objects,
        segments: number,
        version,
        big_endian: big,
        notes: st.notes,
    })
}

/// The lead-in at `pos`; `None` when fewer than 28 bytes are left.
fn lead_in(
    bytes: &[u8],
    pos: usize,
    number: usize,
) -> Result<Option<(Segment, u32, bool)>, String> {
    if bytes.len() - pos < LEAD_IN {
        return Ok(None);
    }
    let here = |e: &str| format!("segment {number} (byte {pos}): {e}");
    match &bytes[pos..pos + 4] {
        b"TDSm" => {}
        b"TDSh" => {
            return Err(here(
                "a TDMS index (`.tdms_index`) holds no data: pass the `.tdms` file",
            ));
        }
        other => {
            return Err(here(&format!(
                "starts with {:?}, not the tag `TDSm`",
                String::from_utf8_lossy(other)
            )));
        }
    }
    // The table of contents is little-endian; its big-endian flag rules the rest.
    let toc = u32::from_le_bytes(bytes[pos + 4..pos + 8].try_into().unwrap_or_default());
    let big = toc & TOC_BIG_ENDIAN != 0;
    let mut c = Cursor::new(bytes, pos + 8, pos + LEAD_IN, big);
    let version = c.u32()?;
    let next = c.u64()?;
    let raw = c.u64()?;
    let body = pos + LEAD_IN;
    let left = (bytes.len() - body) as u64;
    // An unfinished last segment (the writer stopped) states all ones, or more than is there.
    let (end, cut_short) = if next == u64::MAX || next > left {
        (bytes.len(), true)
    } else {
        (body + next as usize, false)
    };
    if raw > (end - body) as u64 {
        return Err(here(&format!(
            "its metadata would end at byte {}, past the segment's end at byte {end}",
            body as u64 + raw
        )));
    }
    let seg = Segment {
        number,
        start: pos,
        toc,
        data_start: body + raw as usize,
        end,
        cut_short,
    };
    Ok(Some((seg, version, big)))
}

/// Reads a segment's metadata into the object list and the objects.
fn metadata(bytes: &[u8], seg: &Segment, st: &mut State) -> Result<(), String> {
    let big = seg.toc & TOC_BIG_ENDIAN != 0;
    let mut c = Cursor::new(bytes, seg.start + LEAD_IN, seg.data_start, big);
    if seg.toc & TOC_NEW_OBJ_LIST != 0 {
        st.list.clear();
    }
    let count = c.u32()?;
    for _ in 0..count {
        let path = c.string()?;
        let header = c.u32()?;
        let before = st.list.iter().position(|l| l.path == path);
        let known = before
            .and_then(|i| st.list[i].index.clone())
            .or_else(|| st.indexes.get(&path).cloned());
        let (index, has_data) = match header {
            NO_DATA => (known, false),
            SAME_AS_BEFORE => match known {
                Some(ix) => (Some(ix), true),
                None => {
                    return Err(format!(
                        "object `{path}` reuses the previous raw data index, but has none before"
                    ));
                }
            },
            daqmx::FORMAT_CHANGING | daqmx::DIGITAL_LINE => {
                let (data_type, count, ix) = daqmx::read_index(&mut c, header, &path)?;
                let index = RawIndex {
                    data_type,
                    count,
                    text_bytes: None,
                    daqmx: Some(ix),
                };
                (Some(index), true)
            }
            _ => (Some(raw_index(&mut c, &path)?), true),
        };
        if let Some(ix) = &index {
            st.indexes.insert(path.clone(), ix.clone());
        }
        let entry = Listed {
            path: path.clone(),
            index,
            has_data,
        };
        match before {
            Some(i) => st.list[i] = entry,
            None => st.list.push(entry),
        }
        let n_props = c.u32()?;
        let props = (0..n_props)
            .map(|_| c.property())
            .collect::<Result<Vec<_>, _>>()?;
        merge_properties(object_mut(st, &path), props);
    }
    Ok(())
}

fn raw_index(c: &mut Cursor, path: &str) -> Result<RawIndex, String> {
    let (data_type, count) = c.index_head(path)?;
    let text_bytes = match data_type {
        DataType::Text => Some(c.u64()?),
        _ => None,
    };
    Ok(RawIndex {
        data_type,
        count,
        text_bytes,
        daqmx: None,
    })
}

pub(super) fn object_mut<'s>(st: &'s mut State, path: &str) -> &'s mut Object {
    let i = match st.objects.iter().position(|o| o.path == path) {
        Some(i) => i,
        None => {
            st.objects.push(Object {
                path: path.to_string(),
                properties: Vec::new(),
                data: Data::None,
                type_changed: None,
                daqmx_scale_id: None,
            });
            st.objects.len() - 1
        }
    };
    &mut st.objects[i]
}

fn merge_properties(o: &mut Object, props: Vec<(String, PropValue)>) {
    for (name, value) in props {
        match o.properties.iter_mut().find(|(n, _)| *n == name) {
            Some(p) => p.1 = value,
            None => o.properties.push((name, value)),
        }
    }
}
