//! The FRF workflow: H1, H2 and coherence between two channels averaged over every segment of
//! every log given, and the resonances of |H1| with their half-power Q.

use crate::error::Error;
use crate::signal::{Frf, IngestOptions, PeakOptions, Resonance, WelchOptions};
use std::path::PathBuf;

pub struct FrfRequest<'a> {
    pub logs: &'a [PathBuf],
    pub input: &'a str,
    pub output: &'a str,
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    pub peaks: PeakOptions,
    /// Search resonances from the first line above 0 Hz, whatever `peaks.f_min_hz` says: the
    /// DC line of an FRF carries no resonance.
    pub from_first_line: bool,
}

pub struct FrfRun {
    pub frf: Frf,
    pub resonances: Vec<Resonance>,
}

pub fn run(req: &FrfRequest) -> Result<FrfRun, Error> {
    let frf =
        crate::signal::frf_of_files(req.logs, req.input, req.output, &req.ingest, &req.welch)?;
    let f = frf.frequencies();
    let mut peaks = req.peaks.clone();
    if req.from_first_line {
        peaks.f_min_hz = f.get(1).copied().unwrap_or(0.0);
    }
    let resonances = crate::signal::resonances(&f, &frf.h1(), &frf.coherence(), &peaks);
    Ok(FrfRun { frf, resonances })
}
