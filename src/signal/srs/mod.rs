//! Shock response spectrum (SRS) of an acceleration record: for each natural frequency of a
//! fractional-octave grid, the extreme absolute acceleration of a single-degree-of-freedom
//! oscillator (quality factor Q) driven at its base by the record.
//!
//! Per frequency the record is run through Smallwood's ramp-invariant filter ([`filter`]), then
//! through a zero tail of one damped period of the lowest natural frequency (the residual). The
//! response after the input ends is a decaying sinusoid, so its largest positive and negative
//! values both fall within its first damped period: one period of the lowest frequency is
//! enough for every frequency of the grid (and it is what `endaq.calc.shock.shock_spectrum`
//! appends for a two-sided spectrum, which keeps the two comparable).
//!
//! Reported per frequency: maximax (largest |response|), positive and negative (largest value of
//! each sign over input and tail, the negative as a magnitude), primary and residual maximax,
//! and the pseudo-velocity maximax (ω·|z|max, z the relative displacement).
//!
//! Files: [`filter`] the coefficients and the filter pass, [`file`] a log file to spectra,
//! [`spec`] the tolerance check against a shock specification.

pub mod file;
pub mod filter;
pub mod spec;

pub use file::{ChannelSrs, LogSrs, srs_of_file};
pub use spec::{SpecCheck, SpecPoint, SpecTolerance, check_against_spec};

use crate::error::SignalError;
use rayon::prelude::*;
use serde::Serialize;

/// How the static offset of a record is removed before the spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Offset {
    /// Keep the record as it is.
    None,
    /// Subtract the mean of the whole record.
    Mean,
    /// Subtract the mean of the samples before the shock (see [`pre_shock_mean`]).
    PreShock,
}

impl Offset {
    pub fn parse(s: &str) -> Result<Offset, SignalError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "none" => Ok(Offset::None),
            "mean" => Ok(Offset::Mean),
            "pre-shock" | "preshock" => Ok(Offset::PreShock),
            _ => Err(SignalError::BadParameter {
                name: "offset",
                value: s.to_string(),
                reason: "expected none, mean or pre-shock".into(),
            }),
        }
    }
}

/// What to compute.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SrsOptions {
    pub q: f64,
    pub fmin_hz: f64,
    pub fmax_hz: f64,
    /// Natural frequencies per octave (6 or 12 in the test standards).
    pub per_octave: u32,
    pub offset: Offset,
}

impl Default for SrsOptions {
    fn default() -> Self {
        SrsOptions {
            q: 10.0,
            fmin_hz: 10.0,
            fmax_hz: 10_000.0,
            per_octave: 12,
            offset: Offset::Mean,
        }
    }
}

/// The default highest natural frequency: ten samples per period of the highest oscillator
/// (the sampling rule of NASA-HDBK-7005 §3.4 for shock data), and at most the 10 kHz that
/// pyroshock specifications stop at.
pub fn default_fmax_hz(fs_hz: f64) -> f64 {
    (fs_hz / 10.0).min(10_000.0)
}

impl SrsOptions {
    /// `fmax_hz = ∞` asks for [`default_fmax_hz`] of the record's rate; any other value stays.
    pub fn resolved_for(&self, fs_hz: f64) -> SrsOptions {
        let mut o = *self;
        if o.fmax_hz == f64::INFINITY {
            o.fmax_hz = default_fmax_hz(fs_hz);
        }
        o
    }

    pub fn validate(&self) -> Result<(), SignalError> {
        let bad = |name, value: f64, reason: &str| {
            Err(SignalError::BadParameter {
                name,
                value: value.to_string(),
                reason: reason.into(),
            })
        };
        // Q <= 1/2 is critically or over-damped: the damped frequency of the filter is not real.
        if !(self.q.is_finite() && self.q > 0.5) {
            return bad(
                "q",
                self.q,
                "the quality factor must be finite and above 0.5",
            );
        }
        if !(self.fmin_hz.is_finite() && self.fmin_hz > 0.0) {
            return bad("fmin", self.fmin_hz, "must be a positive frequency");
        }
        if !(self.fmax_hz.is_finite() && self.fmax_hz >= self.fmin_hz) {
            return bad("fmax", self.fmax_hz, "must be finite and not below fmin");
        }
        if !(1..=96).contains(&self.per_octave) {
            return bad("per-octave", f64::from(self.per_octave), "must be 1 to 96");
        }
        Ok(())
    }
}

/// The natural frequencies fmin·2^(k/n), k = 0, 1, ... up to fmax (inclusive to 1e-9 relative,
/// so that fmax = fmin·2^m lands on the grid).
pub fn natural_frequencies(fmin_hz: f64, fmax_hz: f64, per_octave: u32) -> Vec<f64> {
    let n = f64::from(per_octave.max(1));
    (0..)
        .map(|k| fmin_hz * 2f64.powf(f64::from(k) / n))
        .take_while(|&f| f <= fmax_hz * (1.0 + 1e-9))
        .collect()
}

/// Samples of the residual tail: one damped period of `fmin_hz`, floor(T/dt) + 1.
pub fn residual_samples(fmin_hz: f64, q: f64, dt: f64) -> usize {
    let zeta = 1.0 / (2.0 * q);
    let period = 1.0 / (fmin_hz * (1.0 - zeta * zeta).sqrt());
    (period / dt).floor() as usize + 1
}

/// One natural frequency of the spectrum, in the channel's unit (g for accelerations);
/// `pseudo_velocity` in that unit times seconds (see [`ChannelSrs::pv_unit`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SrsPoint {
    pub frequency_hz: f64,
    pub maximax: f64,
    pub positive: f64,
    /// Magnitude of the most negative response.
    pub negative: f64,
    pub primary: f64,
    pub residual: f64,
    pub pseudo_velocity: f64,
}

/// The spectrum of `x` (sampled at `fs_hz`, offset already removed) at `freqs`. Frequencies
/// are independent, so the parallel map gives the same bytes whatever the thread count.
pub fn srs(x: &[f64], fs_hz: f64, freqs: &[f64], q: f64) -> Result<Vec<SrsPoint>, SignalError> {
    check_signal(x, fs_hz, freqs)?;
    let dt = 1.0 / fs_hz;
    let fmin = freqs.iter().copied().fold(f64::INFINITY, f64::min);
    let tail = residual_samples(fmin, q, dt);
    Ok(freqs
        .par_iter()
        .map(|&f| point(x, f, q, dt, tail))
        .collect())
}

fn point(x: &[f64], f: f64, q: f64, dt: f64, tail: usize) -> SrsPoint {
    let (p, r) = filter::primary_residual(&filter::absolute_acceleration(f, q, dt), x, tail);
    let (pv_p, pv_r) = filter::primary_residual(&filter::pseudo_velocity(f, q, dt), x, tail);
    let positive = p.max.max(r.max);
    let negative = -p.min.min(r.min);
    SrsPoint {
        frequency_hz: f,
        maximax: positive.abs().max(negative.abs()),
        positive,
        negative,
        primary: p.abs_max(),
        residual: r.abs_max(),
        pseudo_velocity: pv_p.abs_max().max(pv_r.abs_max()),
    }
}

fn check_signal(x: &[f64], fs_hz: f64, freqs: &[f64]) -> Result<(), SignalError> {
    if x.is_empty() {
        return Err(SignalError::Invalid("the record has no samples".into()));
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(SignalError::Invalid(format!(
            "sample {i} is not finite ({})",
            x[i]
        )));
    }
    if !(fs_hz.is_finite() && fs_hz > 0.0) {
        return Err(SignalError::BadParameter {
            name: "fs",
            value: fs_hz.to_string(),
            reason: "the sampling rate must be positive".into(),
        });
    }
    if freqs.is_empty() {
        return Err(SignalError::Invalid(
            "no natural frequency to compute".into(),
        ));
    }
    // At or above Nyquist the filter aliases: the spectrum there means nothing.
    if let Some(&f) = freqs.iter().find(|&&f| !(f > 0.0 && f < 0.5 * fs_hz)) {
        return Err(SignalError::BadParameter {
            name: "fmax",
            value: f.to_string(),
            reason: format!(
                "natural frequencies must lie in (0, fs/2 = {} Hz)",
                0.5 * fs_hz
            ),
        });
    }
    Ok(())
}

/// Largest |x| and its sample index (the first one on a tie).
pub fn peak(x: &[f64]) -> (f64, usize) {
    x.iter().enumerate().fold(
        (0.0, 0),
        |(m, i), (j, &v)| if v.abs() > m { (v.abs(), j) } else { (m, i) },
    )
}

/// Fraction of the peak deviation from the first sample that marks the onset of the shock.
pub const ONSET_FRACTION: f64 = 0.1;
/// Fewest samples before the onset from which a pre-shock offset is estimated.
pub const MIN_PRE_SHOCK_SAMPLES: usize = 64;

/// Mean of the samples before the shock onset: the first sample whose deviation from the first
/// sample reaches [`ONSET_FRACTION`] of the largest deviation. Fails (naming the onset) when
/// fewer than [`MIN_PRE_SHOCK_SAMPLES`] precede it: a record that starts in the shock has no
/// pre-shock level to measure.
pub fn pre_shock_mean(x: &[f64], fs_hz: f64) -> Result<f64, String> {
    let x0 = x.first().copied().unwrap_or(0.0);
    let dev_max = x.iter().fold(0.0f64, |m, v| m.max((v - x0).abs()));
    let onset = x
        .iter()
        .position(|v| (v - x0).abs() >= ONSET_FRACTION * dev_max)
        .unwrap_or(x.len());
    if onset < MIN_PRE_SHOCK_SAMPLES {
        return Err(format!(
            "only {onset} sample(s) before the shock onset at t = {:.6e} s (first deviation of {}% of the peak); {} needed to estimate a pre-shock offset: use --offset mean or none",
            onset as f64 / fs_hz,
            100.0 * ONSET_FRACTION,
            MIN_PRE_SHOCK_SAMPLES
        ));
    }
    Ok(x[..onset].iter().sum::<f64>() / onset as f64)
}
