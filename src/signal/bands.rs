//! Levels from a PSD: overall and band RMS (Grms for g²/Hz), octave and third-octave band
//! levels, and tolerance bands of a measured control PSD against a reference profile given as
//! `[f_hz, g2_hz]` breakpoints interpolated log-log (the scene format; see `crate::units`).
//!
//! Inputs: PSD lines from [`super::welch`] or a UFF58 PSD record, on increasing frequencies.

use crate::error::SignalError;
use crate::units::{loglog_integral, loglog_interp};
use serde::Serialize;
use std::path::Path;

/// Trapezoidal integral of `values` over `freqs` within `[f_lo, f_hi]`, the spectrum linearly
/// interpolated at edges that fall between lines.
pub fn integrate(freqs: &[f64], values: &[f64], f_lo: f64, f_hi: f64) -> f64 {
    let n = freqs.len().min(values.len());
    if n < 2 || f_hi <= f_lo {
        return 0.0;
    }
    let mut sum = 0.0;
    for k in 0..n - 1 {
        let (fa, fb) = (freqs[k], freqs[k + 1]);
        let (a, b) = (fa.max(f_lo), fb.min(f_hi));
        if b <= a || fb <= fa {
            continue;
        }
        let at = |f: f64| values[k] + (values[k + 1] - values[k]) * (f - fa) / (fb - fa);
        sum += 0.5 * (at(a) + at(b)) * (b - a);
    }
    sum
}

/// RMS over all lines: √∫S df (Grms for a g²/Hz spectrum).
pub fn rms_of(freqs: &[f64], values: &[f64]) -> f64 {
    match (freqs.first(), freqs.last()) {
        (Some(&a), Some(&b)) => integrate(freqs, values, a, b).sqrt(),
        _ => 0.0,
    }
}

/// RMS within `[f_lo, f_hi]`.
pub fn band_rms(freqs: &[f64], values: &[f64], f_lo: f64, f_hi: f64) -> f64 {
    integrate(freqs, values, f_lo, f_hi).sqrt()
}

/// One fractional-octave band.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Band {
    pub center_hz: f64,
    pub lower_hz: f64,
    pub upper_hz: f64,
    pub rms: f64,
}

/// Base-10 fractional-octave bands (IEC 61260-1: centres 1000·10^(3k/(10·b)), edges at
/// centre·10^(±3/(20·b))), `per_octave` = 1 or 3, for every band that lies wholly within the
/// lines above DC.
pub fn octave_bands(freqs: &[f64], values: &[f64], per_octave: u32) -> Vec<Band> {
    let b = f64::from(per_octave.max(1));
    let (Some(&f_first), Some(&f_last)) = (freqs.iter().find(|&&f| f > 0.0), freqs.last()) else {
        return Vec::new();
    };
    let half = 10f64.powf(3.0 / (20.0 * b));
    let mut out = Vec::new();
    for k in -60..=40 {
        let fc = 1000.0 * 10f64.powf(3.0 * f64::from(k) / (10.0 * b));
        let (lo, hi) = (fc / half, fc * half);
        if lo >= f_first && hi <= f_last {
            out.push(Band {
                center_hz: fc,
                lower_hz: lo,
                upper_hz: hi,
                rms: band_rms(freqs, values, lo, hi),
            });
        }
    }
    out
}

/// Tolerance limits around a reference profile.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToleranceSpec {
    pub alarm_db: f64,
    pub abort_db: f64,
    /// Allowed departure of the measured Grms from the profile's, percent.
    pub grms_pct: f64,
}

impl Default for ToleranceSpec {
    fn default() -> Self {
        ToleranceSpec {
            alarm_db: 3.0,
            abort_db: 6.0,
            grms_pct: 10.0,
        }
    }
}

/// Outcome of a tolerance check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ToleranceStatus {
    /// Every line within the alarm band and the Grms within tolerance.
    Ok,
    /// Some line beyond the alarm band, none beyond abort, Grms within tolerance.
    Alarm,
    /// A line beyond the abort band, or the Grms out of tolerance.
    Abort,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToleranceReport {
    pub spec: ToleranceSpec,
    /// Lines inside the profile's frequency range.
    pub lines_checked: usize,
    pub fraction_outside_alarm: f64,
    pub fraction_outside_abort: f64,
    /// Measured/reference in dB at the line of largest |excursion| (signed).
    pub worst_excursion_db: f64,
    pub worst_frequency_hz: f64,
    pub measured_grms: f64,
    pub reference_grms: f64,
    pub grms_error_pct: f64,
    pub status: ToleranceStatus,
    /// No abort (an alarm alone does not stop a test).
    pub pass: bool,
}

/// Checks the measured lines against the profile over the profile's frequency range. The
/// measured Grms integrates the measured lines over that range; the reference Grms is the exact
/// log-log integral of the profile.
pub fn tolerance_bands(
    freqs: &[f64],
    values: &[f64],
    profile: &[(f64, f64)],
    spec: &ToleranceSpec,
) -> Result<ToleranceReport, SignalError> {
    validate_profile(profile)?;
    let (f1, f2) = (profile[0].0, profile[profile.len() - 1].0);
    let mut checked = 0usize;
    let (mut alarm, mut abort) = (0usize, 0usize);
    let (mut worst, mut worst_f) = (0.0f64, f1);
    for (&f, &v) in freqs.iter().zip(values) {
        if f < f1 || f > f2 {
            continue;
        }
        let r = loglog_interp(profile, f);
        if r <= 0.0 {
            continue;
        }
        checked += 1;
        // A zero measured line is as far below as a float allows; −300 dB stands for it.
        let d = if v > 0.0 {
            10.0 * (v / r).log10()
        } else {
            -300.0
        };
        if d.abs() > spec.alarm_db {
            alarm += 1;
        }
        if d.abs() > spec.abort_db {
            abort += 1;
        }
        if d.abs() > worst.abs() {
            worst = d;
            worst_f = f;
        }
    }
    if checked == 0 {
        return Err(SignalError::Invalid(format!(
            "no measured line falls inside the profile range {f1}–{f2} Hz"
        )));
    }
    let measured = integrate(freqs, values, f1, f2).sqrt();
    let reference = loglog_integral(profile).sqrt();
    let grms_error_pct = 100.0 * (measured - reference) / reference;
    let status = if abort > 0 || grms_error_pct.abs() > spec.grms_pct {
        ToleranceStatus::Abort
    } else if alarm > 0 {
        ToleranceStatus::Alarm
    } else {
        ToleranceStatus::Ok
    };
    Ok(ToleranceReport {
        spec: spec.clone(),
        lines_checked: checked,
        fraction_outside_alarm: alarm as f64 / checked as f64,
        fraction_outside_abort: abort as f64 / checked as f64,
        worst_excursion_db: worst,
        worst_frequency_hz: worst_f,
        measured_grms: measured,
        reference_grms: reference,
        grms_error_pct,
        status,
        pass: status != ToleranceStatus::Abort,
    })
}

fn validate_profile(profile: &[(f64, f64)]) -> Result<(), SignalError> {
    if profile.len() < 2 {
        return Err(SignalError::Invalid(
            "a profile needs at least two [f_hz, g2_hz] points".into(),
        ));
    }
    for (i, w) in profile.windows(2).enumerate() {
        if w[1].0.partial_cmp(&w[0].0) != Some(std::cmp::Ordering::Greater) {
            return Err(SignalError::Invalid(format!(
                "profile point {}: frequencies must increase",
                i + 2
            )));
        }
    }
    for (i, p) in profile.iter().enumerate() {
        if !(p.0 > 0.0 && p.0.is_finite() && p.1 > 0.0 && p.1.is_finite()) {
            return Err(SignalError::Invalid(format!(
                "profile point {}: [{}, {}] must be positive and finite",
                i + 1,
                p.0,
                p.1
            )));
        }
    }
    Ok(())
}

/// Reads a profile: a TOML file with `profile_g2_hz = [[f_hz, g2_hz], ...]` (or `points`), or a
/// two-column CSV with a header.
pub fn read_profile(path: &Path) -> Result<Vec<(f64, f64)>, SignalError> {
    let bytes =
        crate::signal::ingest::text::read_all(path).map_err(|e| SignalError::Unsupported {
            file: path.to_path_buf(),
            message: format!("cannot read: {e}"),
        })?;
    let text = String::from_utf8_lossy(&bytes);
    let bad = |line: usize, m: String| SignalError::BadCell {
        file: path.to_path_buf(),
        line: line as u64,
        column: "profile".into(),
        text: m,
        what: "bad profile point",
    };
    let pts: Vec<(f64, f64)> = if path.extension().is_some_and(|e| e == "toml") {
        let v: toml::Table = toml::from_str(&text).map_err(|e| SignalError::Unsupported {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        let arr = v
            .iter()
            .find(|(k, _)| k.ends_with("g2_hz") || k.as_str() == "points")
            .and_then(|(_, a)| a.as_array())
            .ok_or_else(|| SignalError::Unsupported {
                file: path.to_path_buf(),
                message: "no `profile_g2_hz = [[f_hz, g2_hz], ...]` array".into(),
            })?;
        arr.iter()
            .enumerate()
            .map(|(i, p)| {
                let a = p.as_array().filter(|a| a.len() == 2);
                let num =
                    |x: &toml::Value| x.as_float().or_else(|| x.as_integer().map(|i| i as f64));
                match a.and_then(|a| Some((num(&a[0])?, num(&a[1])?))) {
                    Some(pt) => Ok(pt),
                    None => Err(bad(i + 1, format!("point {} is not [f_hz, g2_hz]", i + 1))),
                }
            })
            .collect::<Result<_, _>>()?
    } else {
        let mut v = Vec::new();
        for (i, l) in text.lines().enumerate().skip(1) {
            if l.trim().is_empty() {
                continue;
            }
            let mut it = l.split(',').map(|s| s.trim().parse::<f64>());
            match (it.next(), it.next()) {
                (Some(Ok(f)), Some(Ok(g))) => v.push((f, g)),
                _ => return Err(bad(i + 1, l.to_string())),
            }
        }
        v
    };
    validate_profile(&pts).map_err(|e| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(pts)
}
