//! A log file to shock response spectra: reads the selected channels (CSV, LabVIEW
//! .lvm or MATLAB .mat through [`crate::signal::formats::read_log`], or UFF58 time histories), removes each channel's offset,
//! finds its peak and computes its spectrum. The `srs` command's analysis.

use super::{Offset, SrsOptions, SrsPoint, natural_frequencies, peak, pre_shock_mean, srs};
use crate::error::SignalError;
use crate::signal::formats::read_log;
use crate::signal::ingest::{IngestOptions, IngestRecord};
use crate::signal::uff::{looks_like_uff, read_uff58};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The spectrum of one channel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelSrs {
    pub name: String,
    /// Unit of the record and of the spectrum ("g" for accelerations, else "as-is").
    pub unit: String,
    /// Unit of the pseudo-velocity: "m/s" for a record in g, else "as-is*s".
    pub pv_unit: String,
    /// The offset subtracted before the spectrum (0 with `Offset::None`).
    pub offset_removed: f64,
    /// Largest |acceleration| after offset removal, and its time from the first sample.
    pub peak: f64,
    pub peak_time_s: f64,
    pub samples: usize,
    pub srs: Vec<SrsPoint>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogSrs {
    pub file: PathBuf,
    pub fs_hz: f64,
    pub options: SrsOptions,
    /// Zero samples appended for the residual spectrum (one damped period of fmin).
    pub residual_samples: usize,
    pub channels: Vec<ChannelSrs>,
    /// The reader's decisions about a text, LabVIEW or MATLAB log (none for a UFF file,
    /// whose records state everything).
    pub ingest: Option<IngestRecord>,
    /// What a UFF file's records were read as where that departs from the options (a record
    /// in volts kept in volts under `--units g`), for stderr.
    #[serde(skip)]
    pub notes: Vec<String>,
}

/// Reads `path` and computes the spectrum of every selected channel.
pub fn srs_of_file(
    path: &Path,
    ingest: &IngestOptions,
    opts: &SrsOptions,
) -> Result<LogSrs, SignalError> {
    let (fs_hz, records, record, notes) = read_records(path, ingest)?;
    let opts = &opts.resolved_for(fs_hz);
    opts.validate()?;
    let freqs = natural_frequencies(opts.fmin_hz, opts.fmax_hz, opts.per_octave);
    let channels = records
        .into_iter()
        .map(|(name, unit, x)| channel_srs(path, name, unit, x, fs_hz, &freqs, opts))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(LogSrs {
        file: path.to_path_buf(),
        fs_hz,
        options: *opts,
        residual_samples: super::residual_samples(opts.fmin_hz, opts.q, 1.0 / fs_hz),
        channels,
        ingest: record,
        notes,
    })
}

fn channel_srs(
    path: &Path,
    name: String,
    unit: String,
    mut x: Vec<f64>,
    fs_hz: f64,
    freqs: &[f64],
    opts: &SrsOptions,
) -> Result<ChannelSrs, SignalError> {
    let in_channel = |message: String| SignalError::Channel {
        channel: format!("{name} of {}", path.display()),
        message,
    };
    let offset = match opts.offset {
        Offset::None => 0.0,
        Offset::Mean => x.iter().sum::<f64>() / x.len().max(1) as f64,
        Offset::PreShock => pre_shock_mean(&x, fs_hz).map_err(in_channel)?,
    };
    x.iter_mut().for_each(|v| *v -= offset);
    let mut points = srs(&x, fs_hz, freqs, opts.q).map_err(|e| in_channel(e.to_string()))?;
    // A record in g gives ω·z in g·s: report it in m/s, the unit shock severity is judged in.
    let (pv_unit, pv_factor) = match unit.as_str() {
        "g" => ("m/s".to_string(), crate::units::G),
        other => (format!("{other}*s"), 1.0),
    };
    points
        .iter_mut()
        .for_each(|p| p.pseudo_velocity *= pv_factor);
    let (pk, i) = peak(&x);
    Ok(ChannelSrs {
        name,
        unit,
        pv_unit,
        offset_removed: offset,
        peak: pk,
        peak_time_s: i as f64 / fs_hz,
        samples: x.len(),
        srs: points,
    })
}

/// Name, the unit the values are in as results state it, values.
type Records = Vec<(String, String, Vec<f64>)>;

/// The selected channels of a CSV log or a UFF58 file, in the reported unit, the rate, the
/// reader's record (text logs) and notes (UFF).
fn read_records(
    path: &Path,
    ingest: &IngestOptions,
) -> Result<(f64, Records, Option<IngestRecord>, Vec<String>), SignalError> {
    if looks_like_uff(path) {
        let (fs, records, notes) = read_uff_records(path, ingest)?;
        return Ok((fs, records, None, notes));
    }
    let log = read_log(path, ingest)?;
    let records = log
        .info
        .channels
        .iter()
        .zip(log.data)
        .map(|(c, x)| (c.name.clone(), c.reported_unit(), x))
        .collect();
    Ok((log.info.fs_hz, records, Some(log.info.ingest), Vec::new()))
}

fn read_uff_records(
    path: &Path,
    ingest: &IngestOptions,
) -> Result<(f64, Records, Vec<String>), SignalError> {
    let records = read_uff58(path)?;
    let mut out = Vec::new();
    let mut kept = Vec::new();
    let mut fs: Option<(f64, String)> = None;
    let names = crate::signal::uff::channel_names(&records);
    for (r, name) in records.iter().zip(names.iter().cloned()) {
        if ingest.channels.as_ref().is_some_and(|l| !l.contains(&name)) {
            continue;
        }
        let uff_err = |message: String| SignalError::Uff {
            file: path.to_path_buf(),
            line: r.line,
            message,
        };
        if r.function.function_type != 1 || r.is_complex() {
            return Err(uff_err(format!(
                "record `{name}` is function type {}, not a real time history (1): no shock spectrum of it",
                r.function.function_type
            )));
        }
        let step = r.spacing().map_err(uff_err)?;
        if let Some((first_fs, first_name)) = &fs
            && !crate::signal::uff::same_rate(*first_fs, step)
        {
            return Err(uff_err(format!(
                "record `{name}` is sampled at {} Hz and `{first_name}` at {first_fs} Hz: one \
                 run analyses one rate; name the channels of one rate with --channels",
                1.0 / step
            )));
        }
        if fs.is_none() {
            fs = Some((1.0 / step, name.clone()));
        }
        let unit = crate::signal::uff::ordinate_unit(&r.ordinate_label, ingest, &name);
        let k = unit.to_report_factor();
        let unit_text = unit.reported_with(&r.ordinate_label);
        kept.push((name.clone(), r));
        out.push((name, unit_text, r.re.iter().map(|v| v * k).collect()));
    }
    check_uff_selection(path, ingest, &out, &names)?;
    let (fs, _) = fs.ok_or_else(|| SignalError::HeaderOnly {
        file: path.to_path_buf(),
    })?;
    let named: Vec<(&String, &crate::signal::uff::UffRecord)> =
        kept.iter().map(|(n, r)| (n, *r)).collect();
    let notes = crate::signal::uff::electrical_notes(&named, ingest);
    Ok((fs, out, notes))
}

/// Every channel asked for must have been found.
fn check_uff_selection(
    path: &Path,
    ingest: &IngestOptions,
    found: &Records,
    names: &[String],
) -> Result<(), SignalError> {
    let Some(list) = &ingest.channels else {
        return Ok(());
    };
    match list.iter().find(|n| !found.iter().any(|(m, _, _)| m == *n)) {
        Some(missing) => Err(SignalError::NoSuchChannel {
            file: path.to_path_buf(),
            name: missing.clone(),
            available: names.join(", "),
        }),
        None => Ok(()),
    }
}
