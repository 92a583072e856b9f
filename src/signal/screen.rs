//! Where an FRF's resonances may be searched: only in the band the input excites (read from
//! its autospectrum) and only at peaks whose coherence shows that the output answers the
//! input there. Outside that band, or at a low coherence, |H1| is the ratio of two noises and
//! its peaks are not modes.

use super::frf::Resonance;
use serde::Serialize;

/// Default level below the input autospectrum's peak that still counts as excited, dB.
pub const EXCITATION_DB: f64 = 20.0;
/// Default least coherence at a resonance.
pub const MIN_COHERENCE: f64 = 0.8;
/// Least share of the lines between the band's edges that must be excited: below it the
/// input is a set of tones, and |H1| between them is not measured.
pub const MIN_COVERAGE: f64 = 0.5;

/// The band the input excites.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExcitedBand {
    pub lo_hz: f64,
    pub hi_hz: f64,
    /// Share of the lines from `lo_hz` to `hi_hz` within `excitation_db` of the peak.
    pub coverage: f64,
    pub excitation_db: f64,
}

impl ExcitedBand {
    /// A continuous band, rather than a few tones.
    pub fn is_continuous(&self) -> bool {
        self.coverage >= MIN_COVERAGE
    }
}

/// The lowest and highest line above DC whose input autospectrum `gxx` lies within
/// `excitation_db` of its peak; `None` when the input is zero above DC.
pub fn excited_band(freqs: &[f64], gxx: &[f64], excitation_db: f64) -> Option<ExcitedBand> {
    let peak = gxx.iter().skip(1).fold(0.0f64, |m, &v| m.max(v));
    if peak <= 0.0 {
        return None;
    }
    let level = peak * 10f64.powf(-excitation_db / 10.0);
    let excited: Vec<usize> = (1..gxx.len()).filter(|&k| gxx[k] >= level).collect();
    let (first, last) = (*excited.first()?, *excited.last()?);
    Some(ExcitedBand {
        lo_hz: freqs[first],
        hi_hz: freqs[last],
        coverage: excited.len() as f64 / (last - first + 1) as f64,
        excitation_db,
    })
}

/// Splits resonances (all those found, strongest first or in any order) into the strongest
/// `max_peaks` with coherence ≥ `min_coherence`, in frequency order, and those of the
/// strongest `max_peaks` overall that the coherence screen left out.
pub fn split_by_coherence(
    mut all: Vec<Resonance>,
    min_coherence: f64,
    max_peaks: usize,
) -> (Vec<Resonance>, Vec<Resonance>) {
    all.sort_by(|a, b| {
        b.magnitude
            .total_cmp(&a.magnitude)
            .then(a.frequency_hz.total_cmp(&b.frequency_hz))
    });
    let mut screened: Vec<Resonance> = all
        .iter()
        .take(max_peaks)
        .filter(|r| r.coherence < min_coherence)
        .cloned()
        .collect();
    let mut kept: Vec<Resonance> = all
        .into_iter()
        .filter(|r| r.coherence >= min_coherence)
        .take(max_peaks)
        .collect();
    kept.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    screened.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    (kept, screened)
}
