//! The PSD workflow: Welch PSD of every channel of a log (or a UFF58 PSD read as is), the
//! strongest peaks of each, and the control channel against a reference profile.

use crate::error::Error;
use crate::signal::{
    ChannelPsd, IngestOptions, LogPsd, Peak, PeakOptions, ToleranceReport, ToleranceSpec,
    WelchOptions, find_peaks, psd_of_file, tolerance_bands,
};
use std::path::Path;

pub struct PsdRequest<'a> {
    pub log: &'a Path,
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    /// Peaks kept per channel, searched above the first line; `None`: no peak search.
    pub peaks: Option<usize>,
    pub tolerance: Option<ToleranceCheck>,
}

/// A channel checked against a profile.
pub struct ToleranceCheck {
    /// The channel checked (default: the first).
    pub control: Option<String>,
    pub profile: Vec<(f64, f64)>,
    pub spec: ToleranceSpec,
}

pub struct PsdRun {
    pub psd: LogPsd,
    /// Per channel, in the order of `psd.channels`.
    pub peaks: Vec<Vec<Peak>>,
    /// The checked channel's name and its tolerance report.
    pub tolerance: Option<(String, ToleranceReport)>,
}

impl PsdRun {
    /// The first channel, which gives the frequency grid every channel shares.
    pub fn first(&self) -> &ChannelPsd {
        &self.psd.channels[0]
    }
}

pub fn run(req: &PsdRequest) -> Result<PsdRun, Error> {
    let psd = psd_of_file(req.log, &req.ingest, &req.welch)?;
    let tolerance = match &req.tolerance {
        Some(check) => {
            let ch = checked_channel(&psd, check.control.as_deref())?;
            let rep = tolerance(ch, &check.profile, &check.spec)?;
            Some((ch.name.clone(), rep))
        }
        None => None,
    };
    let first = psd
        .channels
        .first()
        .ok_or_else(|| Error::Other("no channel".into()))?;
    let peak_opts = req.peaks.map(|max_peaks| PeakOptions {
        max_peaks,
        f_min_hz: first.psd.df,
        ..Default::default()
    });
    let peaks = psd
        .channels
        .iter()
        .map(|c| match &peak_opts {
            Some(o) if !is_constant(c) => find_peaks(&c.psd.frequencies(), &c.psd.values, o),
            _ => Vec::new(),
        })
        .collect();
    Ok(PsdRun {
        psd,
        peaks,
        tolerance,
    })
}

/// A channel whose fluctuation is round-off of its level (a temperature or a gyro at rest
/// logged as a constant): its spectrum is noise of the arithmetic, and has no peaks to report.
pub fn is_constant(c: &ChannelPsd) -> bool {
    c.rms.is_some_and(|rms| c.grms <= 1e-12 * rms) || c.grms == 0.0
}

/// One channel's PSD against a profile, over the profile's band.
pub fn tolerance(
    ch: &ChannelPsd,
    profile: &[(f64, f64)],
    spec: &ToleranceSpec,
) -> Result<ToleranceReport, Error> {
    Ok(tolerance_bands(
        &ch.psd.frequencies(),
        &ch.psd.values,
        profile,
        spec,
    )?)
}

fn checked_channel<'a>(psd: &'a LogPsd, name: Option<&str>) -> Result<&'a ChannelPsd, Error> {
    let Some(name) = name else {
        return psd
            .channels
            .first()
            .ok_or_else(|| Error::Other("no channel".into()));
    };
    psd.channels.iter().find(|c| c.name == name).ok_or_else(|| {
        let names: Vec<&str> = psd.channels.iter().map(|c| c.name.as_str()).collect();
        Error::Other(format!(
            "--control `{name}`: no such channel (available: {})",
            names.join(", ")
        ))
    })
}

/// The third-octave band levels (IEC 61260-1 base-10 bands) of every channel of a PSD run,
/// channel by channel in the run's order: what `psd --out` writes to `third_octave.csv`.
pub fn third_octave_bands(res: &crate::signal::LogPsd) -> Vec<(String, crate::signal::Band)> {
    res.channels
        .iter()
        .flat_map(|c| {
            let f = c.psd.frequencies();
            crate::signal::octave_bands(&f, &c.psd.values, 3)
                .into_iter()
                .map(|b| (c.name.clone(), b))
                .collect::<Vec<_>>()
        })
        .collect()
}
