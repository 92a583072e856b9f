//! The records of an impact test, one per hit, with the windows of impact testing: a force
//! window (the input is zero outside its pulse, so that the sensor noise of the rest of the
//! record does not enter the cross-spectrum) and, when the response has not died away by the
//! end of its segment, an exponential window on both channels. The exponential window adds a
//! known damping, σ = 1/τ: a mode at f gains ζ = 1/(2π f τ), which [`corrected_q`] removes.

use super::impact::{ImpactPulse, median};
use serde::Serialize;

/// A response whose last [`TAIL_SHARE`] of the segment still exceeds this share of its peak
/// is leaking: it gets the exponential window that brings its end to this share.
pub const DECAY_TARGET: f64 = 0.01;
/// The end of a segment, as a share of it, where the decay is judged.
pub const TAIL_SHARE: f64 = 0.05;
/// The force window keeps one pulse width before each pulse and this many widths after its
/// end: on the pyfrf hammer records the H1 peaks move by less than 0.2% for 0 to 50 widths,
/// and by 2% (with a lower coherence) when the whole record's force noise is kept.
pub const FORCE_TAIL_WIDTHS: usize = 4;
/// Pre-trigger before each hit, as a share of the shortest spacing between hits.
pub const PRE_TRIGGER_SHARE: f64 = 0.1;

/// One force and response record per hit, all of `len` samples.
pub struct HitRecords {
    pub records: Vec<(Vec<f64>, Vec<f64>)>,
    pub windows: ImpactWindows,
}

/// The windows applied, for the JSON and the notes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImpactWindows {
    /// Samples per hit segment.
    pub segment_samples: usize,
    /// The force is kept from one pulse width before each pulse to [`FORCE_TAIL_WIDTHS`]
    /// after it, zero elsewhere.
    pub force_window: bool,
    /// Time constant of the exponential window, s; `None` when every response had decayed
    /// below [`DECAY_TARGET`] of its peak by the end of its segment.
    pub exponential_tau_s: Option<f64>,
}

/// A log's force and response with its hits (in time order).
pub struct HitLog<'a> {
    pub force: &'a [f64],
    pub response: &'a [f64],
    pub hits: &'a [ImpactPulse],
}

/// Cuts every log at its hits, equalises the segment length and applies the windows.
pub fn hit_records(logs: &[HitLog], fs: f64) -> HitRecords {
    let segments: Vec<Vec<(usize, usize)>> = logs.iter().map(|l| segment_starts(l, fs)).collect();
    let len = logs
        .iter()
        .zip(&segments)
        .flat_map(|(l, segs)| segment_lengths(segs, l.force.len()))
        .min()
        .unwrap_or(0);
    let mut records = Vec::new();
    for (l, segs) in logs.iter().zip(&segments) {
        let base = median(l.force);
        for (&(start, hit), pulse) in segs.iter().zip(l.hits) {
            let width = ((pulse.width_s * fs).round() as usize).max(1);
            let keep = hit.saturating_sub(width)..(hit + (1 + FORCE_TAIL_WIDTHS) * width).min(len);
            let force: Vec<f64> = (0..len)
                .map(|i| {
                    if keep.contains(&i) {
                        l.force[start + i] - base
                    } else {
                        0.0
                    }
                })
                .collect();
            records.push((force, l.response[start..start + len].to_vec(), hit));
        }
    }
    let tau = exponential_tau(&records, fs);
    if let Some(tau) = tau {
        for (f, y, hit) in &mut records {
            apply_exponential(f, *hit, tau, fs);
            apply_exponential(y, *hit, tau, fs);
        }
    }
    HitRecords {
        records: records.into_iter().map(|(f, y, _)| (f, y)).collect(),
        windows: ImpactWindows {
            segment_samples: len,
            force_window: true,
            exponential_tau_s: tau,
        },
    }
}

/// (segment start, hit offset within it) per hit: each segment starts a pre-trigger before its
/// hit, the first at the record start when its hit comes earlier than that.
fn segment_starts(l: &HitLog, fs: f64) -> Vec<(usize, usize)> {
    let at = |p: &ImpactPulse| (p.start_s * fs).round() as usize;
    let spacing = l
        .hits
        .windows(2)
        .map(|w| at(&w[1]) - at(&w[0]))
        .min()
        .unwrap_or(usize::MAX);
    let first = l.hits.first().map_or(0, at);
    let pre = first.min((PRE_TRIGGER_SHARE * spacing as f64) as usize);
    l.hits
        .iter()
        .map(|p| {
            let h = at(p);
            (h - pre.min(h), pre.min(h))
        })
        .collect()
}

/// Each segment runs to the next one's start, the last to the record end.
fn segment_lengths(segs: &[(usize, usize)], n: usize) -> Vec<usize> {
    (0..segs.len())
        .map(|k| segs.get(k + 1).map_or(n, |s| s.0) - segs[k].0)
        .collect()
}

/// The exponential window's time constant: the strongest any leaking segment needs to bring
/// its tail to [`DECAY_TARGET`] of its peak, the same for every segment so that all estimate
/// the same (equally damped) FRF.
fn exponential_tau(records: &[(Vec<f64>, Vec<f64>, usize)], fs: f64) -> Option<f64> {
    let mut tau: Option<f64> = None;
    for (_, y, hit) in records {
        let n = y.len();
        let peak = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let tail_from = n - ((TAIL_SHARE * n as f64) as usize).max(1);
        let tail = y[tail_from..].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if peak > 0.0 && tail > DECAY_TARGET * peak {
            let t = (n - hit) as f64 / fs / (tail / (DECAY_TARGET * peak)).ln();
            tau = Some(tau.map_or(t, |m: f64| m.min(t)));
        }
    }
    tau
}

fn apply_exponential(x: &mut [f64], hit: usize, tau: f64, fs: f64) {
    for (i, v) in x.iter_mut().enumerate().skip(hit) {
        *v *= (-((i - hit) as f64) / (fs * tau)).exp();
    }
}

/// A pole identified on exponentially windowed records, (natural frequency, ζ), with the
/// window taken out: e^(−t/τ) moves every pole left by 1/τ, so the decay rate ζ·ωn loses 1/τ
/// and the damped frequency stays (exact, where [`corrected_q`] is its light-damping form for
/// a half-power Q). `None` when the window's decay is all that was measured.
pub fn corrected_pole(f_hz: f64, zeta: f64, tau_s: f64) -> Option<(f64, f64)> {
    let wn = 2.0 * std::f64::consts::PI * f_hz;
    let decay = zeta * wn - 1.0 / tau_s;
    if decay <= 0.0 {
        return None;
    }
    let wd = wn * (1.0 - zeta.powi(2)).max(0.0).sqrt();
    let wn_true = decay.hypot(wd);
    Some((wn_true / (2.0 * std::f64::consts::PI), decay / wn_true))
}

/// The half-power Q of a mode at `f_hz` with the exponential window's damping removed:
/// ζ = 1/(2Q) − 1/(2π f τ). `None` when the window's damping is all that was measured.
pub fn corrected_q(f_hz: f64, q: f64, tau_s: f64) -> Option<f64> {
    let zeta = 1.0 / (2.0 * q) - 1.0 / (2.0 * std::f64::consts::PI * f_hz * tau_s);
    (zeta > 0.0).then(|| 1.0 / (2.0 * zeta))
}
