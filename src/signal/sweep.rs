//! Sine-sweep tracking: response amplitude and phase against the instantaneous drive frequency,
//! by short-time demodulation with the drive's own phase as the reference (a tracking filter
//! that follows the sweep exactly, whatever its law: linear, logarithmic or irregular).
//!
//! Inputs: a control (drive) channel and response channels of one sweep log, uniformly sampled.
//! Method: the analytic signal of the drive (FFT Hilbert transform, rustfft) gives its phase
//! φ(t); in each Hann-weighted block the drive frequency is the least-squares slope of φ, and
//! every channel is demodulated by e^{−iφ}, so that H = Y/X is the complex response per unit
//! drive at that frequency. Hand-written because no maintained crate does sweep tracking.

use super::frf::Resonance;
use super::peaks::half_power_band;
use crate::error::SignalError;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use serde::Serialize;

#[derive(Debug, Clone, PartialEq)]
pub struct SweepOptions {
    /// Block length, s: long enough for many cycles, short next to the time the sweep takes to
    /// cross a half-power band.
    pub block_s: f64,
    /// Step between block centres, s.
    pub hop_s: f64,
    /// Drive amplitude below which a block is dropped (fraction of the largest block's).
    pub min_drive_fraction: f64,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            block_s: 0.25,
            hop_s: 0.02,
            min_drive_fraction: 0.05,
        }
    }
}

/// Tracked response, one entry per block, in increasing drive frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepTrack {
    pub time_s: Vec<f64>,
    pub frequency_hz: Vec<f64>,
    pub drive_amplitude: Vec<f64>,
    /// `h[r][k]`: response `r` per unit drive at block `k`, complex.
    #[serde(skip)]
    pub h: Vec<Vec<Complex64>>,
    /// `sine_fraction[r][k]`: share of the response's block power at the drive frequency
    /// (1 = a clean sine; the sweep's counterpart of coherence).
    pub sine_fraction: Vec<Vec<f64>>,
    /// Share of the drive's own block power at its tracked frequency: near 1 for a swept
    /// sine, low for random, multi-tone or impact drives.
    pub drive_sine_fraction: Vec<f64>,
}

/// A block is a sine when this share of the drive's power is at its tracked frequency.
pub const MIN_DRIVE_SINE_FRACTION: f64 = 0.5;
/// A block must hold this many cycles of the drive for its frequency to be measured.
pub const MIN_CYCLES_PER_BLOCK: f64 = 2.0;
/// Share of the blocks that must be sines for the log to be a sweep.
pub const MIN_SINE_BLOCK_SHARE: f64 = 0.5;
/// Highest over lowest sine frequency of a sweep; below it the drive is a dwell.
pub const MIN_SWEEP_RATIO: f64 = 1.05;
/// Share of the steps between consecutive sine blocks (in time) that must move the frequency
/// the same way: a sweep runs one way, a ringing or noisy drive wanders.
pub const MIN_MONOTONIC_SHARE: f64 = 0.9;

/// Share of the time steps between `(time, frequency)` blocks that go the majority's way.
fn monotonic_share(mut blocks: Vec<(f64, f64)>) -> f64 {
    blocks.sort_by(|a, b| a.0.total_cmp(&b.0));
    let steps = blocks.len().saturating_sub(1);
    let up = blocks.windows(2).filter(|w| w[1].1 > w[0].1).count();
    let down = blocks.windows(2).filter(|w| w[1].1 < w[0].1).count();
    up.max(down) as f64 / steps.max(1) as f64
}

/// Why `track` is not a sine sweep, or `None` when it is one: most blocks must hold a clean
/// sine of at least two cycles, whose frequency moves one way in time and spans a ratio of
/// 1.05 or more.
pub fn not_a_sweep(track: &SweepTrack, block_s: f64) -> Option<String> {
    let sine_blocks: Vec<(f64, f64)> = (0..track.frequency_hz.len())
        .filter(|&k| {
            track.frequency_hz[k] * block_s >= MIN_CYCLES_PER_BLOCK
                && track.drive_sine_fraction[k] >= MIN_DRIVE_SINE_FRACTION
        })
        .map(|k| (track.time_s[k], track.frequency_hz[k]))
        .collect();
    let sines: Vec<f64> = sine_blocks.iter().map(|b| b.1).collect();
    let blocks = track.frequency_hz.len();
    let share = sines.len() as f64 / blocks.max(1) as f64;
    let (lo, hi) = sines
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &f| (l.min(f), h.max(f)));
    if blocks == 0 || share < MIN_SINE_BLOCK_SHARE {
        return Some(format!(
            "the drive is a sine of {MIN_CYCLES_PER_BLOCK}+ cycles in {:.0}% of {blocks} blocks (at least {:.0}% needed): it is not a swept sine",
            100.0 * share,
            100.0 * MIN_SINE_BLOCK_SHARE
        ));
    }
    if hi / lo < MIN_SWEEP_RATIO {
        return Some(format!(
            "the drive's frequency stays within {lo:.3}–{hi:.3} Hz: a dwell, not a sweep (a sweep spans a ratio of {MIN_SWEEP_RATIO} or more)"
        ));
    }
    let one_way = monotonic_share(sine_blocks);
    if one_way < MIN_MONOTONIC_SHARE {
        return Some(format!(
            "the drive's frequency wanders over {lo:.3}–{hi:.3} Hz ({:.0}% of the steps between blocks go one way, a sweep needs {:.0}%): a ringing or noisy drive, not a sweep",
            100.0 * one_way,
            100.0 * MIN_MONOTONIC_SHARE
        ));
    }
    None
}

fn analytic(x: &[f64]) -> Vec<Complex64> {
    let n = x.len();
    let mut planner = FftPlanner::<f64>::new();
    let mut buf: Vec<Complex64> = x.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    planner.plan_fft_forward(n).process(&mut buf);
    for (k, z) in buf.iter_mut().enumerate() {
        let g = if k == 0 || (n.is_multiple_of(2) && k == n / 2) {
            1.0
        } else if k < n.div_ceil(2) {
            2.0
        } else {
            0.0
        };
        *z *= g / n as f64;
    }
    planner.plan_fft_inverse(n).process(&mut buf);
    buf
}

/// Share of a block's weighted power held by its demodulated sine `z`: the sine's weighted
/// mean square is 2|z|²/Σw, compared with the block's Σw·x².
fn sine_share(z: Complex64, pow: f64, wsum: f64) -> f64 {
    if pow > 0.0 {
        (2.0 * z.norm_sqr() / wsum / pow).min(1.0)
    } else {
        0.0
    }
}

/// Tracks `responses` against the sweep in `drive`, sampled at `fs`.
pub fn track_sweep(
    drive: &[f64],
    responses: &[&[f64]],
    fs: f64,
    opts: &SweepOptions,
) -> Result<SweepTrack, SignalError> {
    let block = (opts.block_s * fs).round() as usize;
    let hop = ((opts.hop_s * fs).round() as usize).max(1);
    if !(fs > 0.0 && fs.is_finite()) || block < 8 {
        return Err(SignalError::BadParameter {
            name: "block_s",
            value: opts.block_s.to_string(),
            reason: format!("a block must hold at least 8 samples at fs = {fs} Hz"),
        });
    }
    for (i, r) in responses.iter().enumerate() {
        if r.len() != drive.len() {
            return Err(SignalError::Channel {
                channel: format!("response {}", i + 1),
                message: format!("{} samples, the drive has {}", r.len(), drive.len()),
            });
        }
    }
    // The Hilbert transform rings at the ends of the record: keep one block clear of each.
    if drive.len() / 4 < block {
        return Err(SignalError::SegmentTooLong {
            nperseg: block.saturating_mul(4),
            len: drive.len(),
            channel: "drive".into(),
            file: None,
        });
    }
    let z = analytic(drive);
    let mut phase = Vec::with_capacity(z.len());
    let mut prev = 0.0;
    let mut offset = 0.0;
    for (i, c) in z.iter().enumerate() {
        let a = c.arg();
        if i > 0 {
            let d = a - prev;
            if d > std::f64::consts::PI {
                offset -= 2.0 * std::f64::consts::PI;
            } else if d < -std::f64::consts::PI {
                offset += 2.0 * std::f64::consts::PI;
            }
        }
        prev = a;
        phase.push(a + offset);
    }
    let w: Vec<f64> = (0..block)
        .map(|j| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * (j as f64 + 0.5) / block as f64).cos())
        .collect();
    let wsum: f64 = w.iter().sum();
    // (time, frequency, drive amplitude, H per response, sine fraction per response, drive's)
    type Row = (f64, f64, f64, Vec<Complex64>, Vec<f64>, f64);
    let mut rows: Vec<Row> = Vec::new();
    let mut start = block;
    while start + 2 * block <= drive.len() {
        let seg = start..start + block;
        // Least-squares slope of the phase: the block's mean drive frequency.
        let tm = (block as f64 - 1.0) / 2.0;
        let pm = phase[seg.clone()].iter().sum::<f64>() / block as f64;
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for (j, p) in phase[seg.clone()].iter().enumerate() {
            let dt = j as f64 - tm;
            sxy += dt * (p - pm);
            sxx += dt * dt;
        }
        let freq = sxy / sxx * fs / (2.0 * std::f64::consts::PI);
        let demod = |x: &[f64]| -> (Complex64, f64) {
            let mut acc = Complex64::new(0.0, 0.0);
            let mut pow = 0.0;
            for (j, i) in seg.clone().enumerate() {
                acc += Complex64::from_polar(w[j] * x[i], -phase[i]);
                pow += w[j] * x[i] * x[i];
            }
            (acc, pow)
        };
        let (xd, drive_pow) = demod(drive);
        let amp = 2.0 * xd.norm() / wsum;
        let drive_sine = sine_share(xd, drive_pow, wsum);
        let mut hs = Vec::with_capacity(responses.len());
        let mut fr = Vec::with_capacity(responses.len());
        for r in responses {
            let (yd, pow) = demod(r);
            hs.push(yd / xd);
            fr.push(sine_share(yd, pow, wsum));
        }
        rows.push(((start as f64 + tm) / fs, freq, amp, hs, fr, drive_sine));
        start = start.saturating_add(hop);
    }
    let max_amp = rows.iter().fold(0.0f64, |m, r| m.max(r.2));
    rows.retain(|r| r.2 >= opts.min_drive_fraction * max_amp && r.1 > 0.0);
    rows.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.total_cmp(&b.0)));
    let nr = responses.len();
    let mut t = SweepTrack {
        time_s: Vec::new(),
        frequency_hz: Vec::new(),
        drive_amplitude: Vec::new(),
        h: vec![Vec::new(); nr],
        sine_fraction: vec![Vec::new(); nr],
        drive_sine_fraction: Vec::new(),
    };
    for (time, f, a, hs, fr, ds) in rows {
        t.drive_sine_fraction.push(ds);
        t.time_s.push(time);
        t.frequency_hz.push(f);
        t.drive_amplitude.push(a);
        for r in 0..nr {
            t.h[r].push(hs[r]);
            t.sine_fraction[r].push(fr[r]);
        }
    }
    Ok(t)
}

/// The dominant resonance of tracked response `r`: the largest |H|, refined by a parabola
/// through its neighbours in frequency, with half-power Q. `None` if the track is too short.
pub fn sweep_resonance(track: &SweepTrack, r: usize) -> Option<Resonance> {
    let h = track.h.get(r)?;
    let f = &track.frequency_hz;
    let mag: Vec<f64> = h.iter().map(|z| z.norm()).collect();
    let (i, _) = mag.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    if i == 0 || i + 1 >= mag.len() {
        return None;
    }
    // Parabola through three (f, |H|) points on a non-uniform frequency grid.
    let (x0, x1, x2) = (f[i - 1], f[i], f[i + 1]);
    let (y0, y1, y2) = (mag[i - 1], mag[i], mag[i + 1]);
    let d = (x0 - x1) * (x0 - x2) * (x1 - x2);
    let (fp, vp) = if d != 0.0 {
        let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
        let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
        let c = y1 - a * x1 * x1 - b * x1;
        if a < 0.0 {
            let xv = (-b / (2.0 * a)).clamp(x0, x2);
            (xv, a * xv * xv + b * xv + c)
        } else {
            (x1, y1)
        }
    } else {
        (x1, y1)
    };
    let q = half_power_band(f, &mag, i, vp).map(|(lo, hi)| fp / (hi - lo));
    Some(Resonance {
        frequency_hz: fp,
        magnitude: vp,
        q,
        coherence: track.sine_fraction[r][i],
        phase_deg: h[i].arg().to_degrees(),
        prominence_db: None,
    })
}

/// Why the half-power Q of a tracked resonance is set by the tracking rather than by the
/// damping, if it is: its half-power band spans fewer than
/// [`super::peaks::MIN_HALF_POWER_LINES`] track points, or one block sweeps over more than
/// that share of the band (the block averages the response across the peak: |H| and Q read
/// low). Both are measured at the resonance from the track itself; `None` when resolved.
pub fn q_resolution_note(
    track: &SweepTrack,
    res: &Resonance,
    opts: &SweepOptions,
) -> Option<String> {
    use super::peaks::{MIN_HALF_POWER_LINES, under_resolved_band};
    let band = res.frequency_hz / res.q?;
    let (f, t) = (&track.frequency_hz, &track.time_s);
    let i = f
        .partition_point(|&x| x < res.frequency_hz)
        .clamp(1, f.len().checked_sub(2)?);
    let spacing = (f[i + 1] - f[i - 1]).abs() / 2.0;
    let rate = (f[i + 1] - f[i - 1]).abs() / (t[i + 1] - t[i - 1]);
    let span = rate * opts.block_s;
    let at = format!(
        "resonance at {:.3} Hz: its half-power band ({band:.4} Hz)",
        res.frequency_hz
    );
    // From the band as measured, which the averaging widens: a necessary bound, not a
    // sufficient one.
    let remedy = |what: &str, limit: f64| {
        format!(
            "it needs {what} {limit:.4} s or less (less still if the true band is narrower), or a slower sweep"
        )
    };
    if let Some(per_block) = under_resolved_band(band, span) {
        return Some(format!(
            "{at} is only {per_block:.1} times the {span:.4} Hz one {:.3} s block sweeps there ({rate:.3} Hz/s), \
             so each block averages the response across the peak: |H| and Q read low and the peak shifts the sweep's way; {}",
            opts.block_s,
            remedy("--block-s", band / (MIN_HALF_POWER_LINES * rate))
        ));
    }
    under_resolved_band(band, spacing).map(|points| {
        format!(
            "{at} spans {points:.1} track point(s) {spacing:.4} Hz apart, so its Q is set by the tracking grid as much as by the damping; {}",
            remedy("--hop-s", band / (MIN_HALF_POWER_LINES * rate))
        )
    })
}
