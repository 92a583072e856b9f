//! The EMA workflow: H1 of one input to each output channel, averaged over every segment of
//! every log given (the `frf` workflow's estimator), then the modes identified from them.

use crate::error::Error;
use crate::signal::ema::{EmaModel, EmaOptions, FrfSet, identify};
use crate::signal::{Frf, IngestOptions, WelchOptions, frf_of_files};
use std::path::PathBuf;

pub struct EmaRequest<'a> {
    pub logs: &'a [PathBuf],
    pub input: &'a str,
    pub outputs: &'a [String],
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    pub options: EmaOptions,
}

pub struct EmaRun {
    /// The spectra of each output, in the order of `outputs`.
    pub frfs: Vec<Frf>,
    pub set: FrfSet,
    pub model: EmaModel,
}

pub fn run(req: &EmaRequest) -> Result<EmaRun, Error> {
    if req.outputs.is_empty() {
        return Err(Error::Other(
            "--output: name at least one response channel".into(),
        ));
    }
    let frfs: Vec<Frf> = req
        .outputs
        .iter()
        .map(|o| frf_of_files(req.logs, req.input, o, &req.ingest, &req.welch))
        .collect::<Result<_, _>>()?;
    let set = FrfSet {
        freqs: frfs[0].frequencies(),
        channels: req.outputs.to_vec(),
        h: frfs.iter().map(|f| f.h1()).collect(),
    };
    let model = identify(&set, &req.options)?;
    Ok(EmaRun { frfs, set, model })
}
