//! NI TDMS files (LabVIEW, DIAdem, NI-DAQmx logging, and the loggers that export to TDMS),
//! versions 4712 and 4713, either byte order, contiguous or interleaved raw data, with the
//! object list and raw data indexes carried from segment to segment.
//!
//! Hand-written: the Rust TDMS crates either return raw bytes only (`tdms`) or read
//! little-endian files only (`tdms-rs`), and a malformed file must give an error here, never
//! a panic. The layout is fully specified by NI ("TDMS File Format Internal Structure").
//!
//! How objects become channels:
//! - every channel `/'group'/'channel'` of real numbers is a channel, named by its channel
//!   name, or `group/channel` where two groups share the name;
//! - its unit is the property `unit_string` (LabVIEW waveforms), `NI_UnitDescription`
//!   (NI-DAQmx) or `unit`;
//! - the sampling rate is the channels' `wf_increment` property (the waveform's sample
//!   interval, s); a channel of another increment is listed as not readable with the others;
//! - a channel of timestamps, or of reals named like a time column (`Time`, `t_ms`), is the
//!   time vector instead;
//! - channels of strings, booleans and complex values are listed as not read, as are
//!   channels whose length differs from the others';
//! - DAQmx raw data (NI-DAQmx logging: unscaled integers in each card's interleaved rows) is
//!   read through each channel's scaler ([`daqmx`]); a scaling chain stated in the properties
//!   (channel, else group, else file) is applied ([`scaling`]), and a channel whose scaling
//!   satqual cannot apply is listed as not read rather than returned in counts.

mod daqmx;
mod raw;
mod scaling;
mod segments;
mod values;

use super::table::{Rate, Series, Table, keep_common_length, most_common_interval, same_interval};
use crate::error::SignalError;
use crate::signal::ingest::time_column_unit;
use segments::{Data, Object};
use std::path::Path;
use values::PropValue;

/// The first bytes of a TDMS segment (`TDSm`) or of its index file (`TDSh`).
pub fn looks_like_tdms(head: &[u8]) -> bool {
    head.starts_with(b"TDSm") || head.starts_with(b"TDSh")
}

/// Channel properties that state a unit, most specific first.
const UNIT_PROPERTIES: [&str; 4] = ["unit_string", "NI_UnitDescription", "unit", "Unit"];

/// One channel object with its display name, and the properties of its group and of the file
/// (a scaling may be stated there).
struct Channel<'a> {
    name: String,
    object: &'a Object,
    group: Option<&'a Object>,
    file: Option<&'a Object>,
}

/// What was found among the channels.
#[derive(Default)]
struct Found {
    series: Vec<Series>,
    increments: Vec<(String, f64)>,
    times: Option<(Vec<f64>, String)>,
    ignored: Vec<String>,
    unreadable: Vec<(String, String)>,
    /// Channels scaled by the NI scaling of their properties, and how.
    scaled: Vec<String>,
}

/// Reads the channels of a TDMS file. The rate is the one the `wanted` channels share (all
/// channels when `None`), so that a slow channel can be read alone at its own rate.
pub fn read_tdms(
    path: &Path,
    bytes: &[u8],
    wanted: Option<&[String]>,
) -> Result<Table, SignalError> {
    let parsed = segments::parse(bytes).map_err(|e| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("TDMS: {e}"),
    })?;
    let channels = channel_objects(&parsed.objects);
    let daqmx = channels
        .iter()
        .filter(|c| c.object.daqmx_scale_id.is_some())
        .count();
    let mut f = Found::default();
    for ch in &channels {
        collect(ch, &mut f);
    }
    let rate = rate(&mut f, wanted);
    keep_common_length(
        &mut f.series,
        &mut f.unreadable,
        f.times.as_ref().map(|(t, name)| (t.len(), name.as_str())),
    );
    let mut notes = vec![format!(
        "{}: TDMS version {}, {}, {} segment(s), {} channel(s) read",
        path.display(),
        parsed.version,
        if parsed.big_endian {
            "big-endian"
        } else {
            "little-endian"
        },
        parsed.segments,
        f.series.len()
    )];
    if daqmx > 0 {
        notes.push(format!(
            "{}: {daqmx} channel(s) of DAQmx raw data",
            path.display()
        ));
    }
    if !f.scaled.is_empty() {
        notes.push(format!(
            "{}: scaled by the NI scaling in their properties: {}",
            path.display(),
            f.scaled.join("; ")
        ));
    }
    notes.extend(
        parsed
            .notes
            .iter()
            .map(|n| format!("{}: {n}", path.display())),
    );
    Ok(Table {
        format: "tdms",
        delimiter: "none (binary)",
        decimal: ".",
        series: f.series,
        rate,
        ignored: f.ignored,
        unreadable: f.unreadable,
        notes,
        warnings: Vec::new(),
    })
}

/// The channel objects (path `/'group'/'channel'`), named by the channel alone unless two
/// groups share it.
fn channel_objects(objects: &[Object]) -> Vec<Channel<'_>> {
    let named: Vec<(Vec<String>, &Object)> = objects
        .iter()
        .map(|o| (path_names(&o.path), o))
        .filter(|(names, _)| names.len() == 2)
        .collect();
    let file = objects.iter().find(|o| o.path == "/");
    let group_of = |g: &str| {
        objects
            .iter()
            .find(|o| path_names(&o.path).as_slice() == [g])
    };
    named
        .iter()
        .map(|(names, object)| {
            let shared = named.iter().filter(|(n, _)| n[1] == names[1]).count() > 1;
            let name = if shared {
                format!("{}/{}", names[0], names[1])
            } else {
                names[1].clone()
            };
            Channel {
                name,
                object,
                group: group_of(&names[0]),
                file,
            }
        })
        .collect()
}

/// The names along an object path: `/'group'/'channel'`, a `'` in a name written twice.
fn path_names(path: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut chars = path.chars().peekable();
    while chars.next() == Some('/') {
        match chars.next() {
            Some('\'') => {}
            // The file object's path is `/` alone.
            None if names.is_empty() => return names,
            _ => return vec![path.to_string()],
        }
        let mut name = String::new();
        loop {
            match chars.next() {
                Some('\'') if chars.peek() == Some(&'\'') => {
                    chars.next();
                    name.push('\'');
                }
                Some('\'') => break,
                Some(ch) => name.push(ch),
                None => return vec![path.to_string()],
            }
        }
        names.push(name);
    }
    names
}

fn number(o: &Object, key: &str) -> Option<f64> {
    o.properties.iter().find_map(|(n, v)| match v {
        PropValue::Number(x) if n == key => Some(*x),
        _ => None,
    })
}

fn unit_label(o: &Object) -> String {
    UNIT_PROPERTIES
        .iter()
        .find_map(|key| {
            o.properties.iter().find_map(|(n, v)| match v {
                PropValue::Text(t) if n == key && !t.trim().is_empty() => Some(t.trim()),
                _ => None,
            })
        })
        .unwrap_or("")
        .to_string()
}

/// Sorts one channel into a series, the time vector, or the list of what is not read.
fn collect(ch: &Channel, f: &mut Found) {
    let o = ch.object;
    if let Some(why) = &o.type_changed {
        f.ignored.push(format!("`{}` ({why})", ch.name));
        return;
    }
    match &o.data {
        Data::None => f.ignored.push(format!("`{}` (no values)", ch.name)),
        Data::Skipped(what) => f.ignored.push(format!("`{}` ({what})", ch.name)),
        Data::Times(ticks) if f.times.is_none() => {
            let t0 = ticks.first().copied().unwrap_or(0);
            let t = ticks
                .iter()
                .map(|&t| (t - t0) as f64 / 2f64.powi(64))
                .collect();
            f.times = Some((t, ch.name.clone()));
        }
        Data::Times(_) => f
            .ignored
            .push(format!("`{}` (a second channel of timestamps)", ch.name)),
        Data::Reals(v) => match time_column_unit(&ch.name) {
            Some(unit) if f.times.is_none() => {
                let k = unit.map_or(1.0, |u| u.seconds());
                f.times = Some((v.iter().map(|x| x * k).collect(), ch.name.clone()));
            }
            _ => {
                let levels: Vec<&[(String, PropValue)]> = [Some(o), ch.group, ch.file]
                    .into_iter()
                    .flatten()
                    .map(|o| o.properties.as_slice())
                    .collect();
                let values = match scaling::apply(&levels, o.daqmx_scale_id, v) {
                    Ok(None) => v.clone(),
                    Ok(Some((scaled, chain))) => {
                        f.scaled.push(format!("`{}` ({chain})", ch.name));
                        scaled
                    }
                    Err(why) => {
                        f.ignored.push(format!("`{}` ({why})", ch.name));
                        return;
                    }
                };
                if let Some(dt) = number(o, "wf_increment").filter(|d| d.is_finite() && *d > 0.0) {
                    f.increments.push((ch.name.clone(), dt));
                }
                f.series.push(Series {
                    name: ch.name.clone(),
                    unit_label: unit_label(o),
                    values,
                });
            }
        },
    }
}

/// The sampling rate: the time vector, else the `wf_increment` most of the wanted channels
/// share, the first channel's on a tie (the channels of another increment are not readable
/// with them), else none.
fn rate(f: &mut Found, wanted: Option<&[String]>) -> Rate {
    if let Some((t, name)) = &f.times {
        return Rate::Times(t.clone(), name.clone());
    }
    let is_wanted = |name: &str| wanted.is_none_or(|w| w.iter().any(|n| n == name));
    let considered: Vec<&(String, f64)> =
        f.increments.iter().filter(|(n, _)| is_wanted(n)).collect();
    let dts: Vec<f64> = considered.iter().map(|(_, d)| *d).collect();
    let Some((dt, i)) = most_common_interval(&dts) else {
        return Rate::Unknown;
    };
    let first = &considered[i].0;
    let from = format!("the wf_increment property of `{first}`");
    let other: Vec<(String, f64)> = f
        .increments
        .iter()
        .filter(|(_, d)| !same_interval(*d, dt))
        .cloned()
        .collect();
    for (name, d) in other {
        f.series.retain(|s| s.name != name);
        f.unreadable.push((
            name,
            format!("sampled at its own rate: wf_increment {d} s against the log's {dt} s"),
        ));
    }
    Rate::Stated(1.0 / dt, from)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_split_into_group_and_channel_names() {
        assert_eq!(path_names("/"), Vec::<String>::new());
        assert_eq!(path_names("/'Group'"), vec!["Group"]);
        assert_eq!(
            path_names("/'Shaker run'/'Acc ''A'' [g]'"),
            vec!["Shaker run", "Acc 'A' [g]"]
        );
        assert_eq!(path_names("/'broken"), vec!["/'broken"]);
    }
}
