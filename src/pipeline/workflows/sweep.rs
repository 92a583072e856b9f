//! The sine-sweep tracking workflow: each response's amplitude and phase per unit drive
//! against the instantaneous drive frequency, and its dominant resonance.

use crate::error::Error;
use crate::signal::sweep::q_resolution_note;
use crate::signal::{
    IngestOptions, Resonance, SweepOptions, SweepTrack, not_a_sweep, read_log, sweep_resonance,
    track_sweep,
};
use std::path::Path;

pub struct SweepRequest<'a> {
    pub log: &'a Path,
    /// The drive channel: its phase is the tracking reference.
    pub control: &'a str,
    /// Response channels; `None`: every channel but the control.
    pub responses: Option<Vec<String>>,
    pub ingest: IngestOptions,
    pub options: SweepOptions,
}

pub struct SweepRun {
    pub fs_hz: f64,
    /// The response channels tracked, in the order of `track.h`.
    pub responses: Vec<String>,
    pub track: SweepTrack,
    /// Per response, its dominant resonance inside the tracked band.
    pub resonances: Vec<Option<Resonance>>,
    /// The reader's decisions about the log.
    pub ingest: crate::signal::ingest::IngestRecord,
    /// Resonances whose Q the tracking cannot resolve, one line each.
    pub notes: Vec<String>,
}

pub fn run(req: &SweepRequest) -> Result<SweepRun, Error> {
    let log = read_log(req.log, &req.ingest)?;
    let drive = log.channel(req.control)?;
    let names: Vec<String> = match &req.responses {
        Some(v) => v.clone(),
        None => log
            .info
            .channels
            .iter()
            .map(|c| c.name.clone())
            .filter(|n| n != req.control)
            .collect(),
    };
    if names.is_empty() {
        return Err(Error::Other(format!(
            "{}: no response channel besides `{}`",
            req.log.display(),
            req.control
        )));
    }
    let resp: Vec<&[f64]> = names
        .iter()
        .map(|n| log.channel(n))
        .collect::<Result<_, _>>()?;
    let track = track_sweep(drive, &resp, log.info.fs_hz, &req.options)?;
    if let Some(why) = not_a_sweep(&track, req.options.block_s) {
        return Err(Error::Other(format!(
            "{}: no sine sweep detected on the control channel `{}`: {why}; `sweep` tracks a swept-sine drive, use `frf` for random, multi-tone or impact inputs",
            req.log.display(),
            req.control
        )));
    }
    let resonances: Vec<Option<Resonance>> = (0..names.len())
        .map(|r| sweep_resonance(&track, r))
        .collect();
    let notes = (names.iter().zip(&resonances))
        .filter_map(|(name, r)| {
            let note = q_resolution_note(&track, r.as_ref()?, &req.options)?;
            Some(format!("`{name}`: {note}"))
        })
        .collect();
    Ok(SweepRun {
        notes,
        fs_hz: log.info.fs_hz,
        responses: names,
        track,
        resonances,
        ingest: log.info.ingest,
    })
}
