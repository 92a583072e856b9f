//! The EMA workflow: H1 of one input to each output channel, estimated as the `frf` workflow
//! does (averaged over every segment of every log given, or over every hit of an impact test
//! with its windows), then the modes identified from them.

use super::frf::{Estimate, estimate};
use crate::error::Error;
use crate::signal::ema::measured::{MeasuredFrfs, read_measured_frfs};
use crate::signal::ema::{EmaModel, EmaOptions, FrfForm, FrfSet, Mode, identify};
use crate::signal::frf::read_frf_logs;
use crate::signal::impact_windows::{ImpactWindows, corrected_pole};
use crate::signal::{Frf, IngestOptions, WelchOptions};
use std::path::PathBuf;

pub struct EmaRequest<'a> {
    pub logs: &'a [PathBuf],
    /// The force or drive channel of time logs; the reference point of measured FRFs (needed
    /// only when the files hold several).
    pub input: Option<&'a str>,
    /// Response channels of time logs; the FRFs to fit of measured ones (all when empty).
    pub outputs: &'a [String],
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    /// `welch` holds the defaults rather than options the user chose: an impact input then
    /// replaces them with the impact options, as in the `frf` workflow.
    pub welch_is_default: bool,
    pub options: EmaOptions,
    /// `options.form` was given by the user rather than defaulted: measured FRFs that state
    /// another form are then refused.
    pub form_is_given: bool,
}

/// Where the FRFs came from.
pub enum FrfSource {
    /// H1 estimated from time logs.
    Estimated {
        /// The spectra of each output, in the order of `outputs`.
        frfs: Vec<Frf>,
        /// The Welch options used (the impact options when an impact was detected).
        welch: WelchOptions,
        /// The windows of the impact analysis, when it was one.
        impact_windows: Option<ImpactWindows>,
    },
    /// FRFs read from UFF files as the acquisition system stored them.
    Measured(Box<MeasuredFrfs>),
}

pub struct EmaRun {
    pub source: FrfSource,
    pub set: FrfSet,
    pub model: EmaModel,
    /// The form fitted (the measured FRFs' own when they state it).
    pub form: FrfForm,
    /// The input named in reports: the force channel, or the measured FRFs' common point.
    pub input: String,
}

pub fn run(req: &EmaRequest) -> Result<EmaRun, Error> {
    if let Some(measured) = read_measured_frfs(req.logs, req.input, req.outputs)? {
        return run_measured(req, measured);
    }
    let input = req.input.ok_or_else(|| {
        Error::Other("--input: name the force (or drive) channel of the logs".into())
    })?;
    if req.outputs.is_empty() {
        return Err(Error::Other(
            "--output: name at least one response channel".into(),
        ));
    }
    let logs: Vec<_> = req
        .outputs
        .iter()
        .map(|o| read_frf_logs(req.logs, input, o, &req.ingest))
        .collect::<Result<_, _>>()?;
    let mut notes = Vec::new();
    let Estimate {
        frfs,
        welch,
        windows,
        ..
    } = estimate(&logs, input, &req.welch, req.welch_is_default, &mut notes)?;
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
        source: FrfSource::Estimated {
            frfs,
            welch,
            impact_windows: windows,
        },
        set,
        model,
        form: req.options.form,
        input: input.to_string(),
    })
}

/// Fits FRFs read from files, in the form they state (a given `--frf-form` must agree).
fn run_measured(req: &EmaRequest, mut measured: MeasuredFrfs) -> Result<EmaRun, Error> {
    let mut options = req.options.clone();
    match measured.form {
        Some(form) if req.form_is_given && form != options.form => {
            return Err(Error::Other(format!(
                "--frf-form {}: the file's FRFs are {} (record 9's data type); leave                  --frf-form out or give that form",
                options.form.name(),
                form.name()
            )));
        }
        Some(form) => options.form = form,
        None => measured.notes.push(format!(
            "{}: fitted as {} (--frf-form)",
            measured.form_basis,
            options.form.name()
        )),
    }
    let set = std::mem::replace(
        &mut measured.set,
        FrfSet {
            freqs: Vec::new(),
            channels: Vec::new(),
            h: Vec::new(),
        },
    );
    let mut model = identify(&set, &options)?;
    let mut notes = std::mem::take(&mut measured.notes);
    notes.append(&mut model.notes);
    model.notes = notes;
    Ok(EmaRun {
        input: measured.common_point.clone(),
        source: FrfSource::Measured(Box::new(measured)),
        set,
        model,
        form: options.form,
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
