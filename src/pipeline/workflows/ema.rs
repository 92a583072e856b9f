//! The EMA workflow: H1 of one input to each output channel, estimated as the `frf` workflow
//! does (averaged over every segment of every log given, or over every hit of an impact test
//! with its windows), then the modes identified from them.

use super::frf::{Estimate, estimate};
use crate::error::Error;
use crate::signal::ema::{EmaModel, EmaOptions, FrfSet, Mode, identify};
use crate::signal::frf::read_frf_logs;
use crate::signal::impact_windows::ImpactWindows;
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

/// The exponential window e^(−t/τ) moves every pole left by 1/τ: each mode's decay rate
/// ζ·ωn loses 1/τ, its damped frequency stays. A mode whose decay the window alone explains
/// has no damping the test can show: it is dropped, with a note.
fn without_window_damping(modes: Vec<Mode>, tau: f64, notes: &mut Vec<String>) -> Vec<Mode> {
    modes
        .into_iter()
        .filter_map(|mut m| {
            let wn = 2.0 * std::f64::consts::PI * m.frequency_hz;
            let decay = m.damping_ratio * wn - 1.0 / tau;
            let wd = wn * (1.0 - m.damping_ratio.powi(2)).max(0.0).sqrt();
            if decay <= 0.0 {
                notes.push(format!(
                    "mode at {:.3} Hz dropped: its damping (ζ {:.5}) is no more than the exponential window's \
                     (τ = {tau:.4} s adds ζ = {:.5}); longer records would show it",
                    m.frequency_hz,
                    m.damping_ratio,
                    1.0 / (wn * tau)
                ));
                return None;
            }
            let wn_true = decay.hypot(wd);
            m.frequency_hz = wn_true / (2.0 * std::f64::consts::PI);
            m.damping_ratio = decay / wn_true;
            Some(m)
        })
        .collect()
}
