//! The raw data of a TDMS segment: whole chunks, each holding every data object's values once,
//! one object after another, interleaved value by value, or (DAQmx) in each acquisition
//! buffer's rows. Values are appended to their objects across segments.

use super::daqmx::{self, DaqmxIndex};
use super::segments::{
    Data, RawIndex, Segment, State, TOC_BIG_ENDIAN, TOC_DAQMX_RAW_DATA, TOC_INTERLEAVED, object_mut,
};
use super::values::{Cursor, DataType, real_value, timestamp_ticks};

/// The objects holding data in this segment, with their indexes.
fn data_objects(st: &State) -> Vec<(String, RawIndex)> {
    st.list
        .iter()
        .filter(|l| l.has_data)
        .filter_map(|l| l.index.clone().map(|ix| (l.path.clone(), ix)))
        .collect()
}

/// Reads the raw data of one segment: whole chunks, each holding every data object's values
/// once (one after another, or interleaved value by value).
pub(super) fn raw_data(bytes: &[u8], seg: &Segment, st: &mut State) -> Result<(), String> {
    let objs = data_objects(st);
    if seg.toc & TOC_DAQMX_RAW_DATA != 0 {
        return daqmx_raw_data(bytes, seg, &objs, st);
    }
    let mut chunk: u64 = 0;
    for (path, ix) in &objs {
        let b = ix.bytes().ok_or_else(|| {
            format!(
                "object `{path}` holds {}, whose size is unknown",
                ix.data_type.describe()
            )
        })?;
        chunk = chunk
            .checked_add(b)
            .ok_or_else(|| "the chunk size overflows".to_string())?;
    }
    let avail = (seg.end - seg.data_start) as u64;
    if chunk == 0 {
        return Ok(());
    }
    if seg.cut_short {
        st.notes.push(format!(
            "segment {} (byte {}) is the last and its length was never written (the writer stopped): read to the end of the file",
            seg.number, seg.start
        ));
    }
    let chunks = avail / chunk;
    let rest = avail % chunk;
    if rest != 0 {
        st.notes.push(format!(
            "segment {} (byte {}): its last {rest} bytes of raw data are not a whole chunk of {chunk} bytes: not read",
            seg.number, seg.start
        ));
    }
    let big = seg.toc & TOC_BIG_ENDIAN != 0;
    let mut c = Cursor::new(bytes, seg.data_start, seg.end, big);
    let interleaved = seg.toc & TOC_INTERLEAVED != 0;
    for _ in 0..chunks {
        if interleaved {
            interleaved_chunk(&mut c, &objs, st, seg.number)?;
        } else {
            for (path, ix) in &objs {
                let n = ix.bytes().unwrap_or(0) as usize;
                let block = c.take(n)?;
                append(st, path, ix, block, big, seg.number);
            }
        }
    }
    Ok(())
}

/// One interleaved chunk: value k of every object, then value k + 1, ...
fn interleaved_chunk(
    c: &mut Cursor,
    objs: &[(String, RawIndex)],
    st: &mut State,
    segment: usize,
) -> Result<(), String> {
    let count = objs[0].1.count;
    if let Some((path, _)) = objs.iter().find(|(_, ix)| ix.count != count) {
        return Err(format!(
            "interleaved data, but `{path}` holds another number of values than `{}`",
            objs[0].0
        ));
    }
    let sizes: Vec<usize> = objs
        .iter()
        .map(|(path, ix)| match (ix.text_bytes, ix.data_type.size()) {
            (None, Some(s)) => Ok(s),
            _ => Err(format!(
                "interleaved data, but `{path}` holds {}, which cannot be interleaved",
                ix.data_type.describe()
            )),
        })
        .collect::<Result<_, _>>()?;
    let row: usize = sizes.iter().sum();
    let bytes = usize::try_from(count)
        .ok()
        .and_then(|n| n.checked_mul(row))
        .ok_or_else(|| "the chunk size overflows".to_string())?;
    let block = c.take(bytes)?;
    for (k, (path, ix)) in objs.iter().enumerate() {
        let offset: usize = sizes[..k].iter().sum();
        let mut values = Vec::with_capacity(count as usize * sizes[k]);
        for r in 0..count as usize {
            let at = r * row + offset;
            values.extend_from_slice(&block[at..at + sizes[k]]);
        }
        append(st, path, ix, &values, c.big, segment);
    }
    Ok(())
}

/// Appends a block of one object's values (contiguous, in the file's byte order).
fn append(st: &mut State, path: &str, ix: &RawIndex, block: &[u8], big: bool, segment: usize) {
    let o = object_mut(st, path);
    let dt = ix.data_type;
    let size = dt.size().unwrap_or(0);
    let same_kind = match (&o.data, dt) {
        (Data::None, _) => true,
        (Data::Reals(_), t) => t.is_real(),
        (Data::Times(_), DataType::Timestamp) => true,
        (Data::Skipped(t), u) => *t == u.describe(),
        _ => false,
    };
    if !same_kind && o.type_changed.is_none() {
        o.type_changed = Some(format!(
            "its data type changes to {} in segment {segment}",
            dt.describe()
        ));
    }
    if o.type_changed.is_some() {
        return;
    }
    match dt {
        t if t.is_real() => {
            let values = block.chunks_exact(size).map(|b| real_value(t, b, big));
            match &mut o.data {
                Data::Reals(v) => v.extend(values),
                _ => o.data = Data::Reals(values.collect()),
            }
        }
        DataType::Timestamp => {
            let ticks = block.chunks_exact(size).map(|b| timestamp_ticks(b, big));
            match &mut o.data {
                Data::Times(v) => v.extend(ticks),
                _ => o.data = Data::Times(ticks.collect()),
            }
        }
        other => o.data = Data::Skipped(other.describe()),
    }
}

/// Reads the raw data of a DAQmx segment: whole chunks of every buffer's rows.
fn daqmx_raw_data(
    bytes: &[u8],
    seg: &Segment,
    objs: &[(String, RawIndex)],
    st: &mut State,
) -> Result<(), String> {
    let mut daq = Vec::new();
    for (path, ix) in objs {
        match &ix.daqmx {
            Some(d) => daq.push((path.as_str(), ix.count, d)),
            None => {
                return Err(format!(
                    "DAQmx raw data, but `{path}` has a plain raw data index"
                ));
            }
        }
    }
    let dims = daqmx::buffers(&daq)?;
    let chunk = dims
        .iter()
        .try_fold(0u64, |sum, &(rows, width)| {
            rows.checked_mul(width as u64)
                .and_then(|b| sum.checked_add(b))
        })
        .ok_or_else(|| "the chunk size overflows".to_string())?;
    let avail = (seg.end - seg.data_start) as u64;
    if chunk == 0 {
        return Ok(());
    }
    if !avail.is_multiple_of(chunk) {
        st.notes.push(format!(
            "segment {} (byte {}): its last {} bytes of DAQmx data are not a whole chunk of {chunk} bytes: not read",
            seg.number,
            seg.start,
            avail % chunk
        ));
    }
    let mut c = Cursor::new(
        bytes,
        seg.data_start,
        seg.end,
        seg.toc & TOC_BIG_ENDIAN != 0,
    );
    for _ in 0..avail / chunk {
        let values = daqmx::read_chunk(&mut c, &daq, &dims)?;
        for ((path, _, d), v) in daq.iter().zip(values) {
            append_daqmx(st, path, d, v, seg.number);
        }
    }
    Ok(())
}

/// Appends a DAQmx channel's unscaled values; a channel of several scalers is not read.
fn append_daqmx(st: &mut State, path: &str, d: &DaqmxIndex, values: Vec<f64>, segment: usize) {
    let o = object_mut(st, path);
    if o.type_changed.is_some() {
        return;
    }
    let id = d.scalers.first().map(|s| s.scale_id);
    if d.scalers.len() != 1 {
        o.data = Data::Skipped(format!("{} DAQmx scalers", d.scalers.len()));
        return;
    }
    match (&mut o.data, o.daqmx_scale_id) {
        (Data::None, _) => {
            o.data = Data::Reals(values);
            o.daqmx_scale_id = id;
        }
        (Data::Reals(v), Some(before)) if Some(before) == id => v.extend(values),
        _ => o.type_changed = Some(format!("its DAQmx scaler changes in segment {segment}")),
    }
}
