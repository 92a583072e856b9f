//! Frequency response functions from an input (force, drive) and an output (response) channel:
//! H1 = Gxy/Gxx, H2 = Gyy/Gyx, coherence γ² = |Gxy|²/(Gxx·Gyy), from Welch spectra averaged
//! over the segments of one or several records (e.g. the 5 hammer hits of
//! `data/realdata/pyfrf-impact`), and resonance picking on |H1| with half-power Q.

use super::peaks::{PeakOptions, find_peaks, half_power_band};
use super::welch::{WelchOptions, welch_multi};
use crate::error::SignalError;
use realfft::num_complex::Complex64;
use serde::Serialize;

/// Averaged spectra and the estimators built from them.
#[derive(Debug, Clone, PartialEq)]
pub struct Frf {
    pub fs: f64,
    pub df: f64,
    pub nperseg: usize,
    /// Segments averaged over all records.
    pub segments: usize,
    pub gxx: Vec<f64>,
    pub gyy: Vec<f64>,
    pub gxy: Vec<Complex64>,
}

impl Frf {
    pub fn frequencies(&self) -> Vec<f64> {
        (0..self.gxx.len()).map(|k| k as f64 * self.df).collect()
    }

    pub fn h1(&self) -> Vec<Complex64> {
        self.gxy.iter().zip(&self.gxx).map(|(g, x)| g / x).collect()
    }

    pub fn h2(&self) -> Vec<Complex64> {
        self.gyy
            .iter()
            .zip(&self.gxy)
            .map(|(y, g)| y / g.conj())
            .collect()
    }

    pub fn coherence(&self) -> Vec<f64> {
        self.gxy
            .iter()
            .zip(self.gxx.iter().zip(&self.gyy))
            .map(|(g, (x, y))| {
                let d = x * y;
                if d > 0.0 {
                    (g.norm_sqr() / d).min(1.0)
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// Averages the cross and auto spectra of `(input, output)` records, weighting each record by
/// its number of segments, so that the result is the mean over every segment of every record.
pub fn frf(records: &[(&[f64], &[f64])], fs: f64, opts: &WelchOptions) -> Result<Frf, SignalError> {
    let mut acc: Option<Frf> = None;
    for (x, y) in records {
        if x.len() != y.len() {
            return Err(SignalError::Invalid(format!(
                "input and output records differ in length ({} and {} samples)",
                x.len(),
                y.len()
            )));
        }
        let r = welch_multi(&[x, y], &[(0, 1)], fs, opts)?;
        let k = r.cross[0].segments as f64;
        match acc.as_mut() {
            None => {
                acc = Some(Frf {
                    fs,
                    df: r.auto[0].df,
                    nperseg: opts.nperseg,
                    segments: r.cross[0].segments,
                    gxx: r.auto[0].values.iter().map(|v| v * k).collect(),
                    gyy: r.auto[1].values.iter().map(|v| v * k).collect(),
                    gxy: r.cross[0].values.iter().map(|v| v * k).collect(),
                });
            }
            Some(a) => {
                a.segments += r.cross[0].segments;
                a.gxx
                    .iter_mut()
                    .zip(&r.auto[0].values)
                    .for_each(|(s, v)| *s += v * k);
                a.gyy
                    .iter_mut()
                    .zip(&r.auto[1].values)
                    .for_each(|(s, v)| *s += v * k);
                a.gxy
                    .iter_mut()
                    .zip(&r.cross[0].values)
                    .for_each(|(s, v)| *s += v * k);
            }
        }
    }
    let mut a = acc.ok_or_else(|| SignalError::Invalid("no record to average".into()))?;
    let total = a.segments as f64;
    a.gxx.iter_mut().for_each(|v| *v /= total);
    a.gyy.iter_mut().for_each(|v| *v /= total);
    a.gxy.iter_mut().for_each(|v| *v /= total);
    Ok(a)
}

/// A resonance read from |H|.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Resonance {
    pub frequency_hz: f64,
    /// |H| at the interpolated maximum.
    pub magnitude: f64,
    /// Half-power quality factor; `None` when a side of the peak never falls to −3 dB.
    pub q: Option<f64>,
    /// Coherence at the line of the maximum.
    pub coherence: f64,
    pub phase_deg: f64,
    /// Prominence over the neighbouring minima, dB; `None` for a sweep track's resonance,
    /// which is the maximum of the whole track rather than one peak among others.
    pub prominence_db: Option<f64>,
}

/// Resonances on the magnitude of `h` (e.g. [`Frf::h1`]), strongest `opts.max_peaks` of those
/// with the required prominence (20 dB per decade is forced: |H| is an amplitude).
pub fn resonances(
    freqs: &[f64],
    h: &[Complex64],
    coherence: &[f64],
    opts: &PeakOptions,
) -> Vec<Resonance> {
    let mag: Vec<f64> = h.iter().map(|z| z.norm()).collect();
    let o = PeakOptions {
        db_per_decade: 20.0,
        ..opts.clone()
    };
    find_peaks(freqs, &mag, &o)
        .into_iter()
        .map(|p| {
            let q = half_power_band(freqs, &mag, p.line, p.value)
                .map(|(lo, hi)| p.frequency_hz / (hi - lo));
            Resonance {
                frequency_hz: p.frequency_hz,
                magnitude: p.value,
                q,
                coherence: coherence.get(p.line).copied().unwrap_or(0.0),
                phase_deg: h[p.line].arg().to_degrees(),
                prominence_db: Some(p.prominence_db),
            }
        })
        .collect()
}

/// Above this magnitude a sample's square, summed over a segment, overflows the spectra.
const MAX_SAMPLE: f64 = 1e100;

/// A channel whose samples are all equal has no spectrum: H1 = Gxy/Gxx would be 0/0 on every
/// line; a sample too large to square makes the spectra infinite. Either is refused with the
/// file and the channel rather than written as NaN or inf.
fn check_live(log: &super::ingest::Log, name: &str, k: usize) -> Result<(), SignalError> {
    let d = &log.data[k];
    if let Some(v) = d.iter().find(|v| v.is_nan() || v.abs() > MAX_SAMPLE) {
        return Err(SignalError::Unsupported {
            file: log.info.file.clone(),
            message: format!(
                "channel `{name}` holds the sample {v:e}, beyond ±{MAX_SAMPLE:e}: its spectrum would overflow"
            ),
        });
    }
    let first = d.first().copied().unwrap_or(0.0);
    if d.iter().all(|&v| v == first) {
        return Err(SignalError::Unsupported {
            file: log.info.file.clone(),
            message: format!(
                "channel `{name}` is constant ({first} in every sample): a dead channel has no spectrum, so no FRF"
            ),
        });
    }
    Ok(())
}

/// Reads the `input` and `output` channels of every log (each read with `ingest`; all must
/// share one sampling rate within 1e-6), refusing one channel named as both, a dead channel
/// and a sample too large for the spectra.
/// The unit of H = output / input as the FRF is computed: each channel's reported unit (g for
/// an acceleration, whatever the file's), or, for values kept as they are, the unit its name
/// states in brackets (`Force [N]` → N), else `as-is`.
pub fn h_unit(log: &super::ingest::Log, input: &str, output: &str) -> String {
    let label = |name: &str| {
        let channel = log.info.channels.iter().find(|c| c.name == name);
        match channel {
            Some(c) => c.reported_unit(),
            None => super::ingest::unit::bracketed(name)
                .unwrap_or("as-is")
                .to_string(),
        }
    };
    format!("{}/{}", label(output), label(input))
}

pub fn read_frf_logs(
    paths: &[std::path::PathBuf],
    input: &str,
    output: &str,
    ingest: &super::ingest::IngestOptions,
) -> Result<Vec<super::ingest::Log>, SignalError> {
    if input == output {
        return Err(SignalError::Channel {
            channel: input.to_string(),
            message: "named as both --input and --output: an FRF of a channel on itself is 1 on every line; name the response channel as --output".into(),
        });
    }
    let mut ing = ingest.clone();
    ing.channels = Some(vec![input.to_string(), output.to_string()]);
    let logs: Vec<super::ingest::Log> = paths
        .iter()
        .map(|p| super::formats::read_log(p, &ing))
        .collect::<Result<_, _>>()?;
    let fs = logs
        .first()
        .map(|l| l.info.fs_hz)
        .ok_or_else(|| SignalError::Invalid("no log given".into()))?;
    for l in &logs {
        if (l.info.fs_hz - fs).abs() > 1e-6 * fs {
            return Err(SignalError::Unsupported {
                file: l.info.file.clone(),
                message: format!(
                    "sampling rate {} Hz differs from {} Hz of the first log",
                    l.info.fs_hz, fs
                ),
            });
        }
    }
    for l in &logs {
        check_live(l, input, 0)?;
        check_live(l, output, 1)?;
    }
    Ok(logs)
}

/// The FRF of logs read by [`read_frf_logs`] (input in `data[0]`, output in `data[1]`);
/// `input` names the channel in a too-long-segment error.
pub fn frf_of_logs(
    logs: &[super::ingest::Log],
    input: &str,
    opts: &WelchOptions,
) -> Result<Frf, SignalError> {
    let records: Vec<(&[f64], &[f64])> = logs
        .iter()
        .map(|l| (l.data[0].as_slice(), l.data[1].as_slice()))
        .collect();
    let fs = logs.first().map_or(0.0, |l| l.info.fs_hz);
    let result = frf(&records, fs, opts);
    match logs.first() {
        Some(first) => result.map_err(|e| e.in_channel(input, &first.info.file)),
        None => result,
    }
}

/// FRF between channels `input` and `output` averaged over the records of several CSV logs.
pub fn frf_of_files(
    paths: &[std::path::PathBuf],
    input: &str,
    output: &str,
    ingest: &super::ingest::IngestOptions,
    opts: &WelchOptions,
) -> Result<Frf, SignalError> {
    let logs = read_frf_logs(paths, input, output, ingest)?;
    frf_of_logs(&logs, input, opts)
}
