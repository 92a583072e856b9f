//! The EMA workflow: H1 of one input to each output channel, estimated as the `frf` workflow
//! does (averaged over every segment of every log given, or over every hit of an impact test
//! with its windows), then the modes identified from them.

use super::frf::{Estimate, estimate};
use crate::error::Error;
use crate::signal::ema::{EmaModel, EmaOptions, FrfSet, Mode, identify};
use crate::signal::frf::read_frf_logs;
use crate::signal::impact_windows::{ImpactWindows, corrected_pole};
use crate::signal::{Frf, IngestOptions, WelchOptions};
use std::path::PathBuf;

pub struct EmaRequest<'a> {
    pub logs: &'a [PathBuf],
    pub input: &'a str,
    pub outputs: &'a [String],
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    /// `welch` holds the defaults rather than options the user chose: an impact input then
    /// replaces them with the impact options, as in the `frf` workflow.
    pub welch_is_default: bool,
    pub options: EmaOptions,
}

pub struct EmaRun {
    /// The spectra of each output, in the order of `outputs`.
    pub frfs: Vec<Frf>,
    pub set: FrfSet,
    pub model: EmaModel,
    /// The Welch options used (the impact options when an impact was detected).
    pub welch: WelchOptions,
    /// The windows of the impact analysis, when it was one.
    pub impact_windows: Option<ImpactWindows>,
}

pub fn run(req: &EmaRequest) -> Result<EmaRun, Error> {
    if req.outputs.is_empty() {
        return Err(Error::Other(
            "--output: name at least one response channel".into(),
        ));
    }
    let logs: Vec<_> = req
        .outputs
        .iter()
        .map(|o| read_frf_logs(req.logs, req.input, o, &req.ingest))
        .collect::<Result<_, _>>()?;
    let mut notes = Vec::new();
    let Estimate {
        frfs,
        welch,
        windows,
        ..
    } = estimate(
        &logs,
        req.input,
        &req.welch,
        req.welch_is_default,
        &mut notes,
    )?;
    let set = FrfSet {
        freqs: frfs[0].frequencies(),
        channels: req.outputs.to_vec(),
        h: frfs.iter().map(|f| f.h1()).collect(),
    };
    let mut model = identify(&set, &req.options)?;
    if let Some(tau) = windows.as_ref().and_then(|w| w.exponential_tau_s) {
        model.modes = without_window_damping(model.modes, tau, &mut notes);
    }
    notes.append(&mut model.notes);
    model.notes = notes;
    Ok(EmaRun {
        frfs,
        set,
        model,
        welch,
        impact_windows: windows,
    })
}

/// The identified modes with the exponential window's decay taken out of their poles
/// (`impact_windows::corrected_pole`); a mode whose decay the window alone explains has no
/// damping the test can show: it is dropped, with a note.
fn without_window_damping(modes: Vec<Mode>, tau: f64, notes: &mut Vec<String>) -> Vec<Mode> {
    modes
        .into_iter()
        .filter_map(|mut m| {
            let Some((f, zeta)) = corrected_pole(m.frequency_hz, m.damping_ratio, tau) else {
                notes.push(format!(
                    "mode at {:.3} Hz dropped: its damping (ζ {:.5}) is no more than the exponential window's \
                     (τ = {tau:.4} s adds ζ = {:.5}); longer records would show it",
                    m.frequency_hz,
                    m.damping_ratio,
                    1.0 / (2.0 * std::f64::consts::PI * m.frequency_hz * tau)
                ));
                return None;
            };
            (m.frequency_hz, m.damping_ratio) = (f, zeta);
            Some(m)
        })
        .collect()
}
