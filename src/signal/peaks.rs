//! Peak picking on spectra and resonance picking on |H|: local maxima kept by prominence (in
//! dB, as scipy.signal.find_peaks defines it), located between bins by a parabola through the
//! three bins around the maximum, and, for resonances, the half-power bandwidth interpolated
//! linearly between bins to give Q = f / Δf.
//!
//! Inputs are the lines of a [`super::Psd`] or of an FRF magnitude, on increasing frequencies.

use serde::Serialize;

/// A spectral peak.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Peak {
    pub frequency_hz: f64,
    pub value: f64,
    /// Prominence in dB.
    pub prominence_db: f64,
    /// Line of the maximum.
    pub line: usize,
}

/// Which peaks to keep.
#[derive(Debug, Clone, PartialEq)]
pub struct PeakOptions {
    /// Smallest prominence kept, dB.
    pub min_prominence_db: f64,
    /// Most peaks returned (the highest ones), reported in frequency order.
    pub max_peaks: usize,
    pub f_min_hz: f64,
    pub f_max_hz: f64,
    /// 10 for power quantities (PSD), 20 for amplitudes (|H|).
    pub db_per_decade: f64,
    /// Peaks further below the highest line of the band than this are dropped, dB.
    pub dynamic_range_db: f64,
}

/// Beyond the 96 dB a 16-bit acquisition spans, a peak is the arithmetic's (round-off of
/// float32 samples sits near −150 dB), not a feature of the structure or the test.
pub const DYNAMIC_RANGE_DB: f64 = 100.0;

impl Default for PeakOptions {
    fn default() -> Self {
        PeakOptions {
            min_prominence_db: 6.0,
            max_peaks: 5,
            f_min_hz: 0.0,
            f_max_hz: f64::INFINITY,
            db_per_decade: 10.0,
            dynamic_range_db: DYNAMIC_RANGE_DB,
        }
    }
}

fn db(v: f64, k: f64) -> f64 {
    k * v.max(1e-300).log10()
}

/// Parabolic interpolation through lines i-1, i, i+1: (fractional offset, value at the vertex).
pub fn parabolic(values: &[f64], i: usize) -> (f64, f64) {
    if i == 0 || i + 1 >= values.len() {
        return (0.0, values.get(i).copied().unwrap_or(0.0));
    }
    let (a, b, c) = (values[i - 1], values[i], values[i + 1]);
    let den = a - 2.0 * b + c;
    if den >= 0.0 || !den.is_finite() {
        return (0.0, b);
    }
    let p = (0.5 * (a - c) / den).clamp(-0.5, 0.5);
    (p, b - 0.25 * (a - c) * p)
}

fn freq_at(freqs: &[f64], i: usize, p: f64) -> f64 {
    if p >= 0.0 {
        freqs[i] + p * (freqs.get(i + 1).copied().unwrap_or(freqs[i]) - freqs[i])
    } else {
        freqs[i] + p * (freqs[i] - freqs[i.saturating_sub(1)])
    }
}

/// Prominent peaks of `values` (non-negative) on increasing `freqs`.
pub fn find_peaks(freqs: &[f64], values: &[f64], opts: &PeakOptions) -> Vec<Peak> {
    let n = values.len().min(freqs.len());
    if n < 3 {
        return Vec::new();
    }
    let k = opts.db_per_decade;
    let lv: Vec<f64> = values[..n].iter().map(|&v| db(v, k)).collect();
    let in_band = |i: usize| freqs[i] >= opts.f_min_hz && freqs[i] <= opts.f_max_hz;
    let top = (0..n)
        .filter(|&i| in_band(i))
        .map(|i| lv[i])
        .fold(f64::NEG_INFINITY, f64::max);
    let mut found = Vec::new();
    for i in 1..n - 1 {
        let local_max = lv[i] > lv[i - 1] && lv[i] >= lv[i + 1];
        if !(local_max && in_band(i)) || lv[i] < top - opts.dynamic_range_db {
            continue;
        }
        // Bases: the lowest point on each side before a higher one (or the end).
        let mut left_min = lv[i];
        let mut j = i;
        while j > 0 {
            j -= 1;
            if lv[j] > lv[i] {
                break;
            }
            left_min = left_min.min(lv[j]);
        }
        let mut right_min = lv[i];
        let mut j = i;
        while j + 1 < n {
            j += 1;
            if lv[j] > lv[i] {
                break;
            }
            right_min = right_min.min(lv[j]);
        }
        let prominence = lv[i] - left_min.max(right_min);
        if prominence >= opts.min_prominence_db {
            let (p, v) = parabolic(&values[..n], i);
            found.push(Peak {
                frequency_hz: freq_at(freqs, i, p),
                value: v,
                prominence_db: prominence,
                line: i,
            });
        }
    }
    found.sort_by(|a, b| b.value.total_cmp(&a.value).then(a.line.cmp(&b.line)));
    found.truncate(opts.max_peaks);
    found.sort_by_key(|p| p.line);
    found
}

/// A half-power band narrower than this many lines gives a Q (or ζ) that the line spacing and
/// the window set as much as the damping does (Hann's main lobe alone is 1.44 lines wide at
/// −3 dB, and the crossings are interpolated between lines): such a value is flagged.
pub const MIN_HALF_POWER_LINES: f64 = 3.0;

/// How many lines of spacing `df` a half-power band of `band_hz` spans, when fewer than
/// [`MIN_HALF_POWER_LINES`] (the band is under-resolved); `None` otherwise.
pub fn under_resolved_band(band_hz: f64, df: f64) -> Option<f64> {
    let lines = band_hz / df;
    (lines < MIN_HALF_POWER_LINES).then_some(lines)
}

/// Half-power (−3 dB) bandwidth around line `i` of the amplitude `mag`, for a peak of height
/// `peak`: the two crossings of peak/√2, interpolated linearly. `None` when a side reaches a
/// higher peak or the end of the data before crossing (Q is then not measurable).
pub fn half_power_band(freqs: &[f64], mag: &[f64], i: usize, peak: f64) -> Option<(f64, f64)> {
    let level = peak / std::f64::consts::SQRT_2;
    let mut j = i;
    let lo = loop {
        if j == 0 {
            return None;
        }
        j -= 1;
        if mag[j] > peak {
            return None;
        }
        if mag[j] < level {
            let t = (level - mag[j]) / (mag[j + 1] - mag[j]);
            break freqs[j] + t * (freqs[j + 1] - freqs[j]);
        }
    };
    let mut j = i;
    let hi = loop {
        if j + 1 >= mag.len() {
            return None;
        }
        j += 1;
        if mag[j] > peak {
            return None;
        }
        if mag[j] < level {
            let t = (mag[j - 1] - level) / (mag[j - 1] - mag[j]);
            break freqs[j - 1] + t * (freqs[j] - freqs[j - 1]);
        }
    };
    Some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three isolated one-line peaks on a flat floor of 1e-20 (PSD, 10 dB per decade): at
    /// 10 Hz (level 1), 20 Hz (1e-9: 90 dB down, kept) and 30 Hz (1e-15: 150 dB down, the
    /// round-off of float32 samples, dropped by [`DYNAMIC_RANGE_DB`]).
    #[test]
    fn peaks_below_the_dynamic_range_are_dropped() {
        let freqs: Vec<f64> = (0..40).map(f64::from).collect();
        let mut values = vec![1e-20; 40];
        (values[10], values[20], values[30]) = (1.0, 1e-9, 1e-15);
        let found = find_peaks(&freqs, &values, &PeakOptions::default());
        let at: Vec<usize> = found.iter().map(|p| p.line).collect();
        assert_eq!(at, [10, 20]);
        let all = PeakOptions {
            dynamic_range_db: f64::INFINITY,
            ..PeakOptions::default()
        };
        assert_eq!(find_peaks(&freqs, &values, &all).len(), 3);
    }
}
