//! Impact (hammer) input detection: a record whose input is one or more short force pulses is
//! analysed one segment per hit, no Hann window and no detrend, because a Hann window centred
//! on the record would weight a pulse at its start by nearly 0, and segments that do not start
//! at a hit would average the pulse with segments of sensor noise.
//!
//! The test: the samples of the input that depart from its median by more than 10% of the
//! largest departure form pulses (runs merged across gaps shorter than [`MERGE_WIDTHS`] times
//! their width, so that a pulse's own ringing stays one pulse); each pulse is at most 1% of the
//! span to the next hit (or to the record end), and the pulses hold at least half of the
//! record's energy (about the median).

use super::welch::{Detrend, WelchOptions, Window};
use serde::Serialize;

/// Departure from the median, as a share of the largest, that counts as part of a pulse.
pub const PULSE_LEVEL: f64 = 0.1;
/// Longest pulse, as a share of the span it starts (to the next hit or the record end).
pub const MAX_PULSE_SHARE: f64 = 0.01;
/// Least share of the record's energy inside the pulses.
pub const MIN_ENERGY_SHARE: f64 = 0.5;
/// Runs of samples above the pulse level closer than this many times the run's width are one
/// pulse (a hammer tip rings, a double hit within a few milliseconds is one blow).
pub const MERGE_WIDTHS: usize = 20;

/// A short pulse found in an input record: one hit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImpactPulse {
    /// The record (log) it was found in, 0-based in the order the logs were given.
    pub record: usize,
    pub start_s: f64,
    pub width_s: f64,
    /// Share of the record's energy (about the median) inside the pulse.
    pub energy_share: f64,
}

pub(super) fn median(x: &[f64]) -> f64 {
    let mut v = x.to_vec();
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, |a, b| a.total_cmp(b)).1
}

/// The hits of an impact record sampled at `fs` (in time order), or `None` when `x` is not a
/// train of short pulses.
pub fn detect_hits(x: &[f64], fs: f64) -> Option<Vec<ImpactPulse>> {
    if x.len() < 2 {
        return None;
    }
    let base = median(x);
    let dev: Vec<f64> = x.iter().map(|v| (v - base).abs()).collect();
    let peak = dev.iter().fold(0.0f64, |m, &d| m.max(d));
    if !(peak > 0.0 && peak.is_finite()) {
        return None;
    }
    let runs = pulse_runs(&dev, PULSE_LEVEL * peak);
    let total: f64 = dev.iter().map(|d| d * d).sum();
    let mut hits = Vec::with_capacity(runs.len());
    let mut inside_all = 0.0;
    for (k, &(first, last)) in runs.iter().enumerate() {
        let span_end = runs.get(k + 1).map_or(x.len(), |r| r.0);
        let width = last - first + 1;
        if width as f64 > MAX_PULSE_SHARE * (span_end - first) as f64 {
            return None;
        }
        let inside: f64 = dev[first..=last].iter().map(|d| d * d).sum();
        inside_all += inside;
        hits.push(ImpactPulse {
            record: 0,
            start_s: first as f64 / fs,
            width_s: width as f64 / fs,
            energy_share: inside / total,
        });
    }
    (inside_all >= MIN_ENERGY_SHARE * total).then_some(hits)
}

/// Runs (first, last sample) where `dev` exceeds `level`, merged across short gaps.
fn pulse_runs(dev: &[f64], level: f64) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (i, _) in dev.iter().enumerate().filter(|(_, d)| **d > level) {
        match runs.last_mut() {
            Some((a, b)) if i - *b <= MERGE_WIDTHS * (*b - *a + 1) => *b = i,
            _ => runs.push((i, i)),
        }
    }
    runs
}

/// The Welch options of an impact test whose shortest hit segment holds `samples`: one
/// segment per hit, rectangular window, no detrend, no overlap.
pub fn impact_welch(samples: usize) -> WelchOptions {
    WelchOptions {
        nperseg: samples,
        overlap: 0.0,
        window: Window::Boxcar,
        detrend: Detrend::None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pulse_train(n: usize, starts: &[usize], width: usize) -> Vec<f64> {
        let mut x = vec![0.0; n];
        for &s in starts {
            for (j, v) in x[s..s + width].iter_mut().enumerate() {
                *v = (std::f64::consts::PI * (j as f64 + 0.5) / width as f64).sin();
            }
        }
        x
    }

    /// Three half-sine pulses of 10 samples, 2000 samples apart: three hits at their starts.
    #[test]
    fn a_pulse_train_is_one_hit_per_pulse() {
        let x = pulse_train(6000, &[100, 2100, 4100], 10);
        let hits = detect_hits(&x, 1000.0).unwrap();
        let starts: Vec<f64> = hits.iter().map(|h| h.start_s).collect();
        assert_eq!(starts.len(), 3);
        for (s, want) in starts.iter().zip([0.1, 2.1, 4.1]) {
            assert!((s - want).abs() < 2e-3, "{s}");
        }
    }

    /// A pulse whose level dips below the threshold mid-way (a ringing tip) stays one hit; a
    /// pulse as wide as 2% of its span is no impact.
    #[test]
    fn ringing_is_one_hit_and_a_wide_pulse_none() {
        let mut x = pulse_train(6000, &[100], 10);
        x[104] = 0.0;
        assert_eq!(detect_hits(&x, 1000.0).unwrap().len(), 1);
        assert!(detect_hits(&pulse_train(6000, &[100], 120), 1000.0).is_none());
    }
}
