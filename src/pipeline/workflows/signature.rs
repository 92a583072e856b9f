//! The signature workflow: the resonances of a signature taken before a test and of one taken
//! after, matched mode by mode.

use super::frf::{self, FrfRequest, FrfRun, Screen};
use crate::error::Error;
use crate::signal::{
    IngestOptions, PeakOptions, Resonance, SignatureCriteria, SignatureReport, WelchOptions,
    compare_signatures,
};
use std::path::PathBuf;

/// The before-signature names the modes to watch (its most prominent resonances); the
/// after-signature is searched this many times as wide, so that a mode whose prominence
/// merely changed rank (a weakened mode) is still matched rather than reported as lost.
pub const AFTER_SEARCH_FACTOR: usize = 2;

/// Resonances searched in the after-signature when `modes` are watched.
pub fn after_peaks(modes: usize) -> usize {
    modes * AFTER_SEARCH_FACTOR
}

pub struct SignatureRequest<'a> {
    pub before: &'a PathBuf,
    pub after: &'a PathBuf,
    pub input: &'a str,
    pub output: &'a str,
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    /// `welch` holds the defaults: an impact input replaces them (see [`FrfRequest`]).
    pub welch_is_default: bool,
    /// Band and coherence screen of the before-signature; the after-signature is searched
    /// over the band searched before.
    pub screen: Option<Screen>,
    /// Peak search of the before-signature; `max_peaks` is the number of modes watched.
    pub peaks: PeakOptions,
    pub criteria: SignatureCriteria,
}

pub struct SignatureRun {
    pub before: FrfRun,
    pub after: FrfRun,
    pub report: SignatureReport,
}

pub fn run(req: &SignatureRequest) -> Result<SignatureRun, Error> {
    let frf_of = |log: &PathBuf, peaks: PeakOptions, screen: Option<Screen>| {
        frf::run(&FrfRequest {
            logs: std::slice::from_ref(log),
            input: req.input,
            output: req.output,
            ingest: req.ingest.clone(),
            welch: req.welch.clone(),
            welch_is_default: req.welch_is_default,
            peaks,
            from_first_line: false,
            screen,
        })
    };
    let before = frf_of(req.before, req.peaks.clone(), req.screen.clone())?;
    let after_screen = match (&req.screen, &before.screen) {
        (Some(s), Some(r)) => match r.searched_hz {
            Some((lo, hi)) => Some(Screen {
                fmin: Some(lo),
                fmax: Some(hi),
                ..s.clone()
            }),
            None => return Err(nothing_searched(req.before, &before)),
        },
        (s, _) => s.clone(),
    };
    let after_opts = PeakOptions {
        max_peaks: after_peaks(req.peaks.max_peaks),
        ..req.peaks.clone()
    };
    let after = frf_of(req.after, after_opts, after_screen)?;
    let report = compare(&before.resonances, &after.resonances, &req.criteria);
    Ok(SignatureRun {
        before,
        after,
        report,
    })
}

/// The before-signature's input excites no band (tones, or nothing): neither a pass nor a
/// fail can be said, so the comparison is refused with the reason.
fn nothing_searched(before: &std::path::Path, run: &FrfRun) -> Error {
    Error::Other(format!(
        "{}: no signature can be compared: {}",
        before.display(),
        run.notes.last().map_or("no band searched", String::as_str)
    ))
}

/// Matches the modes of `before` in `after` and judges each against the criteria.
pub fn compare(
    before: &[Resonance],
    after: &[Resonance],
    criteria: &SignatureCriteria,
) -> SignatureReport {
    compare_signatures(before, after, criteria)
}
