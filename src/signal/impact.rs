//! Impact (hammer) input detection: a record whose input is one short force pulse is averaged
//! with one segment per hit, no window and no detrend, because a Hann window centred on the
//! record would weight the pulse at its start by nearly 0, and segments shorter than the
//! record would average the pulse with segments of sensor noise.
//!
//! The test: the samples of the input that depart from its median by more than 10% of the
//! largest departure all lie within 1% of the record, and that span holds at least half of the
//! record's energy (about the median).

use super::welch::{Detrend, WelchOptions, Window};
use serde::Serialize;

/// Departure from the median, as a share of the largest, that counts as part of the pulse.
pub const PULSE_LEVEL: f64 = 0.1;
/// Longest pulse, as a share of the record.
pub const MAX_PULSE_SHARE: f64 = 0.01;
/// Least share of the record's energy inside the pulse.
pub const MIN_ENERGY_SHARE: f64 = 0.5;

/// A single short pulse found in an input record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImpactPulse {
    pub start_s: f64,
    pub width_s: f64,
    /// Share of the record's energy (about the median) inside the pulse.
    pub energy_share: f64,
}

fn median(x: &[f64]) -> f64 {
    let mut v = x.to_vec();
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, |a, b| a.total_cmp(b)).1
}

/// The pulse of an impact record sampled at `fs`, or `None` when `x` is not one short pulse.
pub fn detect_impact(x: &[f64], fs: f64) -> Option<ImpactPulse> {
    if x.len() < 2 {
        return None;
    }
    let base = median(x);
    let dev: Vec<f64> = x.iter().map(|v| (v - base).abs()).collect();
    let peak = dev.iter().fold(0.0f64, |m, &d| m.max(d));
    if !(peak > 0.0 && peak.is_finite()) {
        return None;
    }
    let above = |d: &&f64| **d > PULSE_LEVEL * peak;
    let first = dev.iter().position(|d| above(&d))?;
    let last = dev.iter().rposition(|d| above(&d))?;
    let span = last - first + 1;
    if span as f64 > MAX_PULSE_SHARE * x.len() as f64 {
        return None;
    }
    let total: f64 = dev.iter().map(|d| d * d).sum();
    let inside: f64 = dev[first..=last].iter().map(|d| d * d).sum();
    let energy_share = inside / total;
    (energy_share >= MIN_ENERGY_SHARE).then(|| ImpactPulse {
        start_s: first as f64 / fs,
        width_s: span as f64 / fs,
        energy_share,
    })
}

/// The Welch options of an impact test whose shortest record holds `samples`: one segment per
/// hit, rectangular window, no detrend, no overlap.
pub fn impact_welch(samples: usize) -> WelchOptions {
    WelchOptions {
        nperseg: samples,
        overlap: 0.0,
        window: Window::Boxcar,
        detrend: Detrend::None,
    }
}
