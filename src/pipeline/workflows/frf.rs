//! The FRF workflow: H1, H2 and coherence between two channels averaged over every segment of
//! every log given, and the resonances of |H1| with their half-power Q. With a screen, the
//! resonances are searched only in the band the input excites and kept only where the
//! coherence is high; an impact input, detected, sets the Welch options of an impact test.

use crate::error::Error;
use crate::signal::frf::frf;
use crate::signal::frf::{frf_of_logs, h_unit, read_frf_logs};
use crate::signal::impact::{ImpactPulse, detect_hits, impact_welch};
use crate::signal::impact_windows::{HitLog, ImpactWindows, corrected_q, hit_records};
use crate::signal::ingest::{IngestRecord, Log};
use crate::signal::screen::{ExcitedBand, excited_band, split_by_coherence};
use crate::signal::welch::{MIN_NPERSEG, resolution_note, short_log_nperseg};
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
    /// Every hit of every record when the input was detected as an impact.
    pub impact: Option<Vec<ImpactPulse>>,
    /// The windows of the impact analysis (force, exponential), when it was one.
    pub impact_windows: Option<ImpactWindows>,
    pub screen: Option<ScreenReport>,
    /// The reader's decisions, per log.
    pub ingest: Vec<(PathBuf, IngestRecord)>,
    /// Decisions and warnings worth a line on stderr.
    pub notes: Vec<String>,
    /// Unit of H (output / input as computed: `g/N`).
    pub h_unit: String,
}

pub fn run(req: &FrfRequest) -> Result<FrfRun, Error> {
    let logs = read_frf_logs(req.logs, req.input, req.output, &req.ingest)?;
    let h_unit = h_unit(&logs[0], req.input, req.output);
    let mut notes = Vec::new();
    let Estimate {
        mut frfs,
        welch,
        hits: impact,
        windows,
    } = estimate(
        std::slice::from_ref(&logs),
        req.input,
        &req.welch,
        req.welch_is_default,
        &mut notes,
    )?;
    let frf = frfs.remove(0);
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
    notes.extend(q_resolution_notes(&frf, &resonances, windows.is_some()));
    let resonances = match windows.as_ref().and_then(|w| w.exponential_tau_s) {
        Some(tau) => without_window_damping(resonances, tau),
        None => resonances,
    };
    Ok(FrfRun {
        frf,
        resonances,
        welch,
        impact: impact.map(|h| h.concat()),
        impact_windows: windows,
        screen,
        ingest: logs
            .iter()
            .map(|l| (l.info.file.clone(), l.info.ingest.clone()))
            .collect(),
        notes,
        h_unit,
    })
}

/// H1 of one input to each output, and how it was estimated.
pub struct Estimate {
    /// One per output, in order.
    pub frfs: Vec<Frf>,
    /// The Welch options used (the impact options when an impact was detected).
    pub welch: WelchOptions,
    /// Every hit of every record when the input was detected as an impact.
    pub hits: Option<Vec<Vec<ImpactPulse>>>,
    /// The windows of the impact analysis (force, exponential), when it was one.
    pub windows: Option<ImpactWindows>,
}

/// H1 of the input to each output (`outputs[k]`: every log read with the input and output
/// k), Welch-averaged, or, when the input is a train of short pulses and `welch` holds the
/// defaults, with the impact options (one force-windowed segment per hit, and one exponential
/// window shared by every output so that all of them see the same added damping).
pub fn estimate(
    outputs: &[Vec<Log>],
    input: &str,
    welch: &WelchOptions,
    welch_is_default: bool,
    notes: &mut Vec<String>,
) -> Result<Estimate, Error> {
    let impact = outputs.first().and_then(|logs| impact_of(logs));
    if impact.is_some() && !welch_is_default {
        notes.push(format!(
            "`{input}` looks like an impact (one short pulse per record), but Welch options were given: they are used as given; \
             a window or segments shorter than the record weigh the pulse down (leave the Welch flags out for the impact options)"
        ));
    }
    match impact.filter(|_| welch_is_default) {
        Some(hits) => {
            let (frfs, windows) = impact_frfs(outputs, &hits)?;
            notes.push(impact_note(&hits, input, &windows));
            Ok(Estimate {
                frfs,
                welch: impact_welch(windows.segment_samples),
                hits: Some(hits),
                windows: Some(windows),
            })
        }
        None => {
            let welch = short_log_welch(outputs, welch, welch_is_default, notes);
            Ok(Estimate {
                frfs: outputs
                    .iter()
                    .map(|logs| frf_of_logs(logs, input, &welch))
                    .collect::<Result<_, _>>()?,
                welch,
                hits: None,
                windows: None,
            })
        }
    }
}

/// The default segment is for long random tests: logs shorter than it get a shorter one, as
/// `psd` gives them, said in a note. Options the user chose are kept (and a segment longer
/// than the log is then an error).
fn short_log_welch(
    outputs: &[Vec<Log>],
    welch: &WelchOptions,
    welch_is_default: bool,
    notes: &mut Vec<String>,
) -> WelchOptions {
    let shortest = outputs
        .iter()
        .flatten()
        .map(|l| l.info.samples as usize)
        .min()
        .unwrap_or(0);
    let mut w = welch.clone();
    if welch_is_default && shortest < w.nperseg && shortest >= MIN_NPERSEG {
        w.nperseg = short_log_nperseg(shortest);
        notes.push(format!(
            "the shortest log has {shortest} samples, fewer than the default segment: nperseg {} (--nperseg to choose)",
            w.nperseg
        ));
    }
    w
}

/// A note for every resonance whose half-power band (as measured, before any correction for
/// an exponential window) is under-resolved (`signal::peaks::under_resolved_band`).
fn q_resolution_notes(frf: &Frf, resonances: &[Resonance], impact: bool) -> Vec<String> {
    use crate::signal::peaks::{MIN_HALF_POWER_LINES, under_resolved_band};
    let df = frf.fs / frf.nperseg as f64;
    resonances
        .iter()
        .filter_map(|r| {
            let band = r.frequency_hz / r.q?;
            let lines = under_resolved_band(band, df)?;
            let needed = (MIN_HALF_POWER_LINES * frf.fs / band).ceil();
            let remedy = if impact {
                format!("records of {:.2} s or longer resolve it", needed / frf.fs)
            } else {
                format!("--nperseg {needed:.0} or more resolves it")
            };
            Some(format!(
                "resonance at {:.3} Hz: its half-power band ({band:.4} Hz) spans {lines:.1} line(s) of {df:.4} Hz, \
                 so its Q is set by the resolution as much as by the damping (the window widens the band: \
                 the Q reads low); {remedy}",
                r.frequency_hz
            ))
        })
        .collect()
}

/// The hits of every record when every record's input is a train of short pulses.
fn impact_of(logs: &[Log]) -> Option<Vec<Vec<ImpactPulse>>> {
    logs.iter()
        .enumerate()
        .map(|(k, l)| {
            let mut hits = detect_hits(&l.data[0], l.info.fs_hz)?;
            hits.iter_mut().for_each(|h| h.record = k);
            Some(hits)
        })
        .collect()
}

/// H1 of each output averaged over every hit of every record, each hit its own force- and
/// (if needed) exponentially windowed segment; the segment length and the exponential window
/// are chosen over every output's records together.
fn impact_frfs(
    outputs: &[Vec<Log>],
    hits: &[Vec<ImpactPulse>],
) -> Result<(Vec<Frf>, ImpactWindows), Error> {
    let fs = outputs
        .first()
        .and_then(|logs| logs.first())
        .map_or(0.0, |l| l.info.fs_hz);
    let hit_logs: Vec<HitLog> = outputs
        .iter()
        .flat_map(|logs| logs.iter().zip(hits))
        .map(|(l, h)| HitLog {
            force: &l.data[0],
            response: &l.data[1],
            hits: h,
        })
        .collect();
    let cut = hit_records(&hit_logs, fs);
    let per_output = cut.records.len() / outputs.len().max(1);
    let options = impact_welch(cut.windows.segment_samples);
    let frfs = cut
        .records
        .chunks(per_output.max(1))
        .map(|chunk| {
            let records: Vec<(&[f64], &[f64])> = chunk
                .iter()
                .map(|(f, y)| (f.as_slice(), y.as_slice()))
                .collect();
            frf(&records, fs, &options)
        })
        .collect::<Result<_, _>>()?;
    Ok((frfs, cut.windows))
}

/// The resonances' Q with the exponential window's damping taken out; a Q the window alone
/// explains is dropped (`None`, said in the JSON as no Q).
fn without_window_damping(resonances: Vec<Resonance>, tau: f64) -> Vec<Resonance> {
    resonances
        .into_iter()
        .map(|mut r| {
            r.q = r.q.and_then(|q| corrected_q(r.frequency_hz, q, tau));
            r
        })
        .collect()
}

fn impact_note(hits: &[Vec<ImpactPulse>], input: &str, w: &ImpactWindows) -> String {
    let all: Vec<&ImpactPulse> = hits.iter().flatten().collect();
    let widest = all.iter().fold(0.0f64, |m, p| m.max(p.width_s));
    let exp = match w.exponential_tau_s {
        Some(tau) => format!(
            "; the response had not died away by the end of a segment: exponential window τ = {:.4} s on both channels \
             (it adds ζ = 1/(2π f τ), taken out of the reported Q)",
            tau
        ),
        None => String::new(),
    };
    format!(
        "impact input detected: `{input}` holds {} hit(s) of at most {:.3} ms in {} record(s); \
         impact options used: one segment per hit (nperseg {}), force window, boxcar, no detrend, no overlap{exp} \
         (pass --nperseg, --window, --overlap or --detrend to choose otherwise)",
        all.len(),
        widest * 1e3,
        hits.len(),
        w.segment_samples,
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
