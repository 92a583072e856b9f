//! The FRF workflow: H1, H2 and coherence between two channels averaged over every segment of
//! every log given, and the resonances of |H1| with their half-power Q. With a screen, the
//! resonances are searched only in the band the input excites and kept only where the
//! coherence is high; an impact input, detected, sets the Welch options of an impact test.

use crate::error::Error;
use crate::signal::frf::{frf_of_logs, read_frf_logs};
use crate::signal::impact::{ImpactPulse, detect_impact, impact_welch};
use crate::signal::ingest::{IngestRecord, Log};
use crate::signal::screen::{ExcitedBand, excited_band, split_by_coherence};
use crate::signal::welch::resolution_note;
use crate::signal::{Frf, IngestOptions, PeakOptions, Resonance, WelchOptions};
use std::path::PathBuf;

pub struct FrfRequest<'a> {
    pub logs: &'a [PathBuf],
    pub input: &'a str,
    pub output: &'a str,
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    /// `welch` holds the defaults rather than options the user chose: an impact input then
    /// replaces them with the impact options (one segment per hit, no window).
    pub welch_is_default: bool,
    pub peaks: PeakOptions,
    /// Search resonances from the first line above 0 Hz, whatever `peaks.f_min_hz` says: the
    /// DC line of an FRF carries no resonance.
    pub from_first_line: bool,
    /// Band and coherence screen; `None`: every peak of `peaks`' band is a resonance.
    pub screen: Option<Screen>,
}

/// Where resonances are searched: the band the input excites (or the edges given) and peaks
/// of coherence at least `min_coherence`.
#[derive(Debug, Clone, PartialEq)]
pub struct Screen {
    pub excitation_db: f64,
    pub min_coherence: f64,
    /// Edges given by the user; each replaces the excited band's edge.
    pub fmin: Option<f64>,
    pub fmax: Option<f64>,
}

/// What the screen decided.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ScreenReport {
    /// The band the input excites; `None` when its autospectrum is zero above DC.
    pub excited: Option<ExcitedBand>,
    /// The band searched, Hz; `None` when nothing was searched (a tonal input).
    pub searched_hz: Option<(f64, f64)>,
    pub min_coherence: f64,
    /// Peaks that would have been reported but have a coherence below `min_coherence`.
    pub screened_out: Vec<Resonance>,
}

pub struct FrfRun {
    pub frf: Frf,
    pub resonances: Vec<Resonance>,
    /// The Welch options used (the impact options when an impact was detected).
    pub welch: WelchOptions,
    /// The pulse of each record when the input was detected as an impact.
    pub impact: Option<Vec<ImpactPulse>>,
    pub screen: Option<ScreenReport>,
    /// The reader's decisions, per log.
    pub ingest: Vec<(PathBuf, IngestRecord)>,
    /// Decisions and warnings worth a line on stderr.
    pub notes: Vec<String>,
}

pub fn run(req: &FrfRequest) -> Result<FrfRun, Error> {
    let logs = read_frf_logs(req.logs, req.input, req.output, &req.ingest)?;
    let mut notes = Vec::new();
    let impact = impact_of(&logs);
    match &impact {
        Some(p) if req.welch_is_default => notes.push(impact_note(p, req.input, shortest(&logs))),
        Some(_) => notes.push(format!(
            "`{}` looks like an impact (one short pulse per record), but Welch options were given: they are used as given; \
             a window or segments shorter than the record weigh the pulse down (leave the Welch flags out for the impact options)",
            req.input
        )),
        None => {}
    }
    let impact = impact.filter(|_| req.welch_is_default);
    let welch = match &impact {
        Some(_) => impact_welch(shortest(&logs)),
        None => req.welch.clone(),
    };
    let frf = frf_of_logs(&logs, req.input, &welch)?;
    let f = frf.frequencies();
    let mut peaks = req.peaks.clone();
    if req.from_first_line || req.screen.is_some() {
        peaks.f_min_hz = peaks.f_min_hz.max(f.get(1).copied().unwrap_or(0.0));
    }
    let (resonances, screen) = match &req.screen {
        Some(s) => {
            let (kept, report) = screened(&frf, &peaks, s, &mut notes);
            (kept, Some(report))
        }
        None => (
            crate::signal::resonances(&f, &frf.h1(), &frf.coherence(), &peaks),
            None,
        ),
    };
    Ok(FrfRun {
        frf,
        resonances,
        welch,
        impact,
        screen,
        ingest: logs
            .iter()
            .map(|l| (l.info.file.clone(), l.info.ingest.clone()))
            .collect(),
        notes,
    })
}

fn shortest(logs: &[Log]) -> usize {
    logs.iter().map(|l| l.data[0].len()).min().unwrap_or(0)
}

/// The pulses when every record's input is one short pulse.
fn impact_of(logs: &[Log]) -> Option<Vec<ImpactPulse>> {
    logs.iter()
        .map(|l| detect_impact(&l.data[0], l.info.fs_hz))
        .collect()
}

fn impact_note(pulses: &[ImpactPulse], input: &str, nperseg: usize) -> String {
    let widest = pulses.iter().fold(0.0f64, |m, p| m.max(p.width_s));
    format!(
        "impact input detected: `{input}` is one pulse of at most {:.3} ms in each of {} record(s); \
         impact options used: one segment per hit (nperseg {nperseg}), boxcar window, no detrend, no overlap \
         (pass --nperseg, --window, --overlap or --detrend to choose otherwise)",
        widest * 1e3,
        pulses.len(),
    )
}

/// Resonances searched in the excited band (or the edges given) and kept where coherent.
fn screened(
    frf: &Frf,
    peaks: &PeakOptions,
    s: &Screen,
    notes: &mut Vec<String>,
) -> (Vec<Resonance>, ScreenReport) {
    let f = frf.frequencies();
    let excited = excited_band(&f, &frf.gxx, s.excitation_db);
    let mut report = ScreenReport {
        excited: excited.clone(),
        searched_hz: None,
        min_coherence: s.min_coherence,
        screened_out: Vec::new(),
    };
    let given = s.fmin.is_some() && s.fmax.is_some();
    let band = match &excited {
        Some(b) if b.is_continuous() || given => b,
        Some(b) => {
            notes.push(tonal_note(b));
            return (Vec::new(), report);
        }
        None if given => &ExcitedBand {
            lo_hz: 0.0,
            hi_hz: f64::INFINITY,
            coverage: 0.0,
            excitation_db: s.excitation_db,
        },
        None => {
            notes.push("the input has no power above DC: no resonance is searched".into());
            return (Vec::new(), report);
        }
    };
    let lo = s.fmin.unwrap_or(band.lo_hz).max(peaks.f_min_hz);
    let hi = s.fmax.unwrap_or(band.hi_hz).min(peaks.f_max_hz);
    report.searched_hz = Some((lo, hi));
    let all = crate::signal::resonances(
        &f,
        &frf.h1(),
        &frf.coherence(),
        &PeakOptions {
            f_min_hz: lo,
            f_max_hz: hi,
            max_peaks: usize::MAX,
            ..peaks.clone()
        },
    );
    let (kept, out) = split_by_coherence(all, s.min_coherence, peaks.max_peaks);
    report.screened_out = out;
    notes.extend(screen_notes(frf, &report, lo, hi));
    (kept, report)
}

fn tonal_note(b: &ExcitedBand) -> String {
    format!(
        "the input excites discrete lines, not a band: within {} dB of its peak it holds only {:.1}% of the lines from {:.3} to {:.3} Hz; \
         |H1| between them is the ratio of two noises, so no resonance is searched (a sweep, random or impact input is needed, or pass --fmin and --fmax)",
        b.excitation_db,
        100.0 * b.coverage,
        b.lo_hz,
        b.hi_hz
    )
}

/// The band searched, the peaks screened out and the warnings about resolution and coherence.
fn screen_notes(frf: &Frf, r: &ScreenReport, lo: f64, hi: f64) -> Vec<String> {
    let mut notes = vec![format!(
        "resonances searched over {lo:.3}–{hi:.3} Hz{} at coherence ≥ {}",
        r.excited.as_ref().map_or(String::new(), |b| format!(
            " (input autospectrum within {} dB of its peak over {:.3}–{:.3} Hz)",
            b.excitation_db, b.lo_hz, b.hi_hz
        )),
        r.min_coherence
    )];
    if !r.screened_out.is_empty() {
        let list: Vec<String> = r
            .screened_out
            .iter()
            .map(|p| format!("{:.2} Hz (coherence {:.3})", p.frequency_hz, p.coherence))
            .collect();
        notes.push(format!(
            "{} peak(s) left out for coherence below {}: {}",
            list.len(),
            r.min_coherence,
            list.join(", ")
        ));
    }
    if frf.segments == 1 {
        notes.push(
            "one segment averaged: the coherence is 1 on every line by construction and screens nothing".into(),
        );
    }
    notes.extend(resolution_note(frf.fs, frf.nperseg, lo, hi));
    notes
}
