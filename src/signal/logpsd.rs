//! PSD of every selected channel of a log file: the `psd` command's analysis, reusable by the
//! `qualify` pipeline. A CSV log is streamed through [`WelchStream`] (memory flat in the file
//! length); a UFF58 file gives either time histories (function type 1, sent through Welch) or
//! spectra already computed by a controller (function type 9, PSD), taken as they are, as is
//! a text table of spectral densities over frequency (a controller's CSV export).

use super::bands::rms_of;
use super::formats::{LogFormat, detect, read_log};
use super::ingest::Log;
use super::ingest::{IngestOptions, LogInfo, Unit, stream_csv};
use super::psd_table::{TableChannel, read_psd_table};
use super::uff::{ordinate_unit, read_uff58};
use super::welch::{Psd, WelchOptions, WelchStream, welch};
use crate::error::SignalError;
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// Where the spectrum of a channel came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PsdSource {
    /// Welch on a CSV time history.
    CsvWelch,
    /// Welch on a UFF58 time history.
    UffWelch,
    /// Welch on a log read whole (LabVIEW .lvm, MATLAB .mat, TDMS, WAV).
    Welch,
    /// A PSD record read from UFF58 as it is.
    UffPsd,
    /// A PSD read as it is from a text table of spectral densities (a controller's export).
    TablePsd,
}

impl PsdSource {
    /// A spectrum read from the file, not computed from a time history.
    pub fn is_read_spectrum(self) -> bool {
        matches!(self, PsdSource::UffPsd | PsdSource::TablePsd)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct ChannelPsd {
    pub name: String,
    /// Unit of the spectrum's amplitude ("g" for accelerations, else "as-is").
    pub unit: String,
    pub psd: Psd,
    /// √∫PSD df over all lines.
    pub grms: f64,
    /// Time-domain RMS (mean included); `None` for a spectrum read from a file.
    pub rms: Option<f64>,
    pub samples: u64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct LogPsd {
    pub source: PsdSource,
    pub fs_hz: f64,
    pub info: Option<LogInfo>,
    pub channels: Vec<ChannelPsd>,
    /// The reader's decisions when no [`LogInfo`] carries them (a PSD table's dialect).
    pub notes: Vec<String>,
}

/// The most spectral lines a PSD read from a UFF58 file may span from 0 Hz (16.7 million, 128
/// MB of values): a record whose start frequency is a huge multiple of its spacing is refused
/// rather than zero-filled.
pub const MAX_PSD_LINES: usize = 1 << 24;

/// Refuses a channel whose spectrum or RMS is not finite: samples near 1e154 or above
/// overflow when squared, and such a number must never reach an output.
fn finite_channels(path: &Path, channels: Vec<ChannelPsd>) -> Result<Vec<ChannelPsd>, SignalError> {
    for c in &channels {
        let finite = c.grms.is_finite()
            && c.rms.is_none_or(f64::is_finite)
            && c.psd.values.iter().all(|v| v.is_finite());
        if !finite {
            return Err(SignalError::Unsupported {
                file: path.to_path_buf(),
                message: format!(
                    "channel `{}`: the spectrum is not finite (values too large to square: keep |x| below 1e150)",
                    c.name
                ),
            });
        }
    }
    Ok(channels)
}

/// Computes (or, for UFF PSD records, reads) the PSD of the selected channels of `path`.
pub fn psd_of_file(
    path: &Path,
    ingest: &IngestOptions,
    opts: &WelchOptions,
) -> Result<LogPsd, SignalError> {
    opts.validate()?;
    match detect(path) {
        LogFormat::Uff => return psd_of_uff(path, ingest, opts),
        LogFormat::Lvm
        | LogFormat::Mat
        | LogFormat::Tdms
        | LogFormat::Wav
        | LogFormat::Tektronix
        | LogFormat::Rigol => {
            return psd_of_log(read_log(path, ingest)?, opts);
        }
        LogFormat::Csv => {
            if let Some((table, notes)) = read_psd_table(path, ingest)? {
                return Ok(LogPsd {
                    notes,
                    ..psd_of_table(path, table)?
                });
            }
        }
    }
    // Names are known only once the header is read: the stream is built on the first row.
    let mut stream: Option<WelchStream> = None;
    let mut sumsq: Vec<f64> = Vec::new();
    let mut init_err: Option<SignalError> = None;
    let info = stream_csv(path, ingest, |row| {
        if stream.is_none() && init_err.is_none() {
            let names: Vec<String> = (0..row.len()).map(|i| i.to_string()).collect();
            match WelchStream::new(&names, &[], opts) {
                Ok(s) => stream = Some(s),
                Err(e) => init_err = Some(e),
            }
            sumsq = vec![0.0; row.len()];
        }
        if let Some(s) = stream.as_mut() {
            s.push_row(row);
        }
        for (a, v) in sumsq.iter_mut().zip(row) {
            *a += v * v;
        }
    })?;
    if let Some(e) = init_err {
        return Err(e);
    }
    let stream = stream.ok_or_else(|| SignalError::HeaderOnly {
        file: path.to_path_buf(),
    })?;
    let first = info.channels.first().map_or("", |c| c.name.as_str());
    let result = stream
        .finish(info.fs_hz)
        .map_err(|e| e.in_channel(first, path))?;
    let n = info.samples.max(1) as f64;
    let channels = info
        .channels
        .iter()
        .zip(result.auto)
        .zip(&sumsq)
        .map(|((c, psd), s)| ChannelPsd {
            name: c.name.clone(),
            unit: c.reported_unit(),
            grms: rms_of(&psd.frequencies(), &psd.values),
            psd,
            rms: Some((s / n).sqrt()),
            samples: info.samples,
        })
        .collect();
    let channels = finite_channels(path, channels)?;
    Ok(LogPsd {
        source: PsdSource::CsvWelch,
        fs_hz: info.fs_hz,
        info: Some(info),
        channels,
        notes: Vec::new(),
    })
}

/// A channel whose PSD was read from the file (no time history: no RMS, no samples).
fn read_spectrum(name: String, unit: Unit, psd: Psd) -> ChannelPsd {
    ChannelPsd {
        name,
        unit: unit.reported().into(),
        grms: rms_of(&psd.frequencies(), &psd.values),
        psd,
        rms: None,
        samples: 0,
    }
}

/// The PSDs of a table, as they are.
fn psd_of_table(path: &Path, table: Vec<TableChannel>) -> Result<LogPsd, SignalError> {
    let channels: Vec<ChannelPsd> = table
        .into_iter()
        .map(|TableChannel { name, unit, psd }| read_spectrum(name, unit, psd))
        .collect();
    let channels = finite_channels(path, channels)?;
    Ok(LogPsd {
        source: PsdSource::TablePsd,
        fs_hz: channels.first().map_or(0.0, |c| c.psd.fs),
        info: None,
        channels,
        notes: Vec::new(),
    })
}

/// Welch on every channel of a log read whole (LabVIEW .lvm, MATLAB .mat, TDMS, WAV).
fn psd_of_log(log: Log, opts: &WelchOptions) -> Result<LogPsd, SignalError> {
    let fs = log.info.fs_hz;
    let channels: Vec<ChannelPsd> = log
        .info
        .channels
        .par_iter()
        .zip(&log.data)
        .map(|(c, x)| {
            let psd = welch(x, fs, opts).map_err(|e| e.in_channel(&c.name, &log.info.file))?;
            let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt();
            Ok(ChannelPsd {
                name: c.name.clone(),
                unit: c.reported_unit(),
                grms: rms_of(&psd.frequencies(), &psd.values),
                psd,
                rms: Some(rms),
                samples: x.len() as u64,
            })
        })
        // Collected whole first: the error reported is the first channel's in order, not
        // whichever a thread met first.
        .collect::<Vec<Result<_, SignalError>>>()
        .into_iter()
        .collect::<Result<_, _>>()?;
    let channels = finite_channels(&log.info.file, channels)?;
    Ok(LogPsd {
        source: PsdSource::Welch,
        fs_hz: fs,
        info: Some(log.info),
        channels,
        notes: Vec::new(),
    })
}

/// `psd` reads a UFF file's time histories (function type 1) or its PSDs (9), one kind per
/// run: a record of another type, or of the other kind than the first record chosen, is an
/// error at its line.
fn check_one_kind(
    path: &Path,
    chosen: &[&(String, &super::uff::UffRecord)],
) -> Result<(), SignalError> {
    let Some((first_name, first)) = chosen.first().map(|c| (&c.0, c.1)) else {
        return Ok(());
    };
    let odd = chosen.iter().find(|(_, r)| {
        !matches!(r.function.function_type, 1 | 9)
            || r.function.function_type != first.function.function_type
    });
    let Some((name, r)) = odd.map(|c| (&c.0, c.1)) else {
        return Ok(());
    };
    let message = if matches!(r.function.function_type, 1 | 9) {
        format!(
            "record `{name}` is {} and `{first_name}` (line {}) {}: one run reads time \
             histories (1) or PSDs (9), not both; name the records of one kind with --channels",
            r.function_kind(),
            first.line,
            first.function_kind()
        )
    } else {
        let ema = if r.function.function_type == 4 {
            " (FRFs are fitted as measured by `satqual ema FILE`)"
        } else {
            ""
        };
        format!(
            "record `{name}` is {}: `psd` reads time histories (function type 1) or PSDs \
             (9){ema}",
            r.function_kind()
        )
    };
    Err(SignalError::Uff {
        file: path.to_path_buf(),
        line: r.line,
        message,
    })
}

fn psd_of_uff(
    path: &Path,
    ingest: &IngestOptions,
    opts: &WelchOptions,
) -> Result<LogPsd, SignalError> {
    let records = read_uff58(path)?;
    let named: Vec<(String, &super::uff::UffRecord)> = super::uff::channel_names(&records)
        .into_iter()
        .zip(&records)
        .collect();
    let chosen: Vec<&(String, &super::uff::UffRecord)> = match &ingest.channels {
        Some(list) => list
            .iter()
            .map(|n| {
                named
                    .iter()
                    .find(|(m, _)| m == n)
                    .ok_or_else(|| SignalError::NoSuchChannel {
                        file: path.to_path_buf(),
                        name: n.clone(),
                        available: named
                            .iter()
                            .map(|(m, _)| m.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                    })
            })
            .collect::<Result<_, _>>()?,
        None => named.iter().collect(),
    };
    check_one_kind(path, &chosen)?;
    let kept: Vec<(&String, &super::uff::UffRecord)> =
        chosen.iter().map(|(n, r)| (n, *r)).collect();
    let notes = super::uff::electrical_notes(&kept, ingest);
    let all_psd = chosen.iter().all(|(_, r)| r.function.function_type == 9);
    let channels: Vec<ChannelPsd> = chosen
        .par_iter()
        .map(|(name, r)| {
            let step = r.spacing().map_err(|message| SignalError::Uff {
                file: path.to_path_buf(),
                line: r.line,
                message,
            })?;
            let unit = ordinate_unit(&r.ordinate_label, ingest, name);
            let k = unit.to_report_factor();
            if all_psd {
                // A PSD scales with the square of the amplitude unit.
                let first = r.abscissa[0];
                let offset = (first / step).round();
                if (first - offset * step).abs() > 1e-6 * step || offset < 0.0 {
                    return Err(SignalError::Uff {
                        file: path.to_path_buf(),
                        line: r.line,
                        message: format!("the PSD starts at {first} Hz, not on a multiple of its {step} Hz spacing"),
                    });
                }
                // The lines below the first are zero-filled: a start far above the spacing
                // (a mutated header) would ask for an absurd allocation.
                let lines = offset + r.re.len() as f64;
                let limit = ingest.max_psd_lines;
                if lines > limit as f64 {
                    return Err(SignalError::Uff {
                        file: path.to_path_buf(),
                        line: r.line,
                        message: format!("the PSD starts at {first} Hz with a {step} Hz spacing: {lines:e} spectral lines from 0 Hz, above the limit of {limit}; if the record is meant, raise --max-psd-lines"),
                    });
                }
                if let Some(v) = r.re.iter().find(|v| **v < 0.0) {
                    return Err(SignalError::Uff {
                        file: path.to_path_buf(),
                        line: r.line,
                        message: format!("the PSD record holds a negative level {v}: a power spectral density is never negative"),
                    });
                }
                let mut values = vec![0.0; offset as usize];
                values.extend(r.re.iter().map(|v| v * k * k));
                Ok(read_spectrum(name.clone(), unit, Psd::from_lines(step, values)))
            } else {
                let x: Vec<f64> = r.re.iter().map(|v| v * k).collect();
                let psd = welch(&x, 1.0 / step, opts).map_err(|e| e.in_channel(name, path))?;
                let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt();
                Ok(ChannelPsd {
                    name: name.clone(),
                    unit: unit.reported_with(&r.ordinate_label),
                    grms: rms_of(&psd.frequencies(), &psd.values),
                    psd,
                    rms: Some(rms),
                    samples: x.len() as u64,
                })
            }
        })
        // The first failing record in order, whatever the thread count.
        .collect::<Vec<Result<_, _>>>()
        .into_iter()
        .collect::<Result<_, _>>()?;
    let channels = finite_channels(path, channels)?;
    let fs_hz = channels.first().map_or(0.0, |c| c.psd.fs);
    Ok(LogPsd {
        source: if all_psd {
            PsdSource::UffPsd
        } else {
            PsdSource::UffWelch
        },
        fs_hz,
        info: None,
        channels,
        notes,
    })
}
