//! Scene keys of the qualification itself: `[gates]` (every pass/fail threshold, with the
//! documented defaults and their sources) and `[[test_log]]` (measured logs the pipeline sends
//! through the signal module). Paths in `[[test_log]]` are relative to the scene file.

use super::Locator;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

/// Thresholds of the qualification gates. Every field has a default; the scene overrides any.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct GatesSpec {
    /// First lateral frequency (x and y), Hz. Default 10 Hz: the typical launcher lateral
    /// minimum for a primary payload (e.g. Falcon 9 User's Guide: lateral > 10 Hz).
    pub min_lateral_frequency_hz: f64,
    /// First axial frequency, Hz. Default 25 Hz: the typical launcher axial minimum (Falcon 9
    /// User's Guide: axial > 25 Hz).
    pub min_axial_frequency_hz: f64,
    /// Linear buckling factor of the preloaded stack. Default 1.0 (the preload must not buckle
    /// the columns); raise it to demand a knock-down margin.
    pub min_buckling_factor: f64,
    /// Pre/post signature: frequency shift, %. Default 5% (GSFC-STD-7000 practice for an intact
    /// structure after a test level).
    pub max_frequency_shift_pct: f64,
    /// Pre/post signature: amplitude change, %. Default 20% (same source).
    pub max_amplitude_change_pct: f64,
    /// Random control: alarm band, ±dB. Default 3 dB (GSFC-STD-7000 test tolerance).
    pub alarm_db: f64,
    /// Random control: abort band, ±dB. Default 6 dB.
    pub abort_db: f64,
    /// Random control: Grms tolerance, ±%. Default 10%.
    pub grms_tolerance_pct: f64,
    /// Separation: minimum exit speed, m/s. Default 0.2 m/s, an ASSUMPTION: it keeps the
    /// satellites apart before their first orbit manoeuvre; the paper reaches 0.25-0.35 m/s.
    pub min_separation_speed_m_s: f64,
    /// Separation: maximum tip-off rate at bar exit, deg/s. Default 2.5 deg/s, an ASSUMPTION:
    /// the paper (§4) reports 2.47 deg/s for its first satellite and calls it acceptable.
    pub max_tipoff_rate_deg_s: f64,
}

impl Default for GatesSpec {
    fn default() -> Self {
        GatesSpec {
            min_lateral_frequency_hz: 10.0,
            min_axial_frequency_hz: 25.0,
            min_buckling_factor: 1.0,
            max_frequency_shift_pct: 5.0,
            max_amplitude_change_pct: 20.0,
            alarm_db: 3.0,
            abort_db: 6.0,
            grms_tolerance_pct: 10.0,
            min_separation_speed_m_s: 0.2,
            max_tipoff_rate_deg_s: 2.5,
        }
    }
}

/// What kind of measurement a log holds.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum LogKind {
    Random,
    SineSweep,
    SignatureBefore,
    SignatureAfter,
    /// A shock record: its SRS against the scene's `[shock]` specification.
    Shock,
    /// FRFs measured and stored by the acquisition (UFF58 function type 4): the test modes of
    /// `[correlation]` and `update` are identified from them; no test-data gate reads them.
    Frf,
}

/// One measured log handed over by the shaker lab.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestLogSpec {
    pub name: String,
    /// CSV or UFF58 file, relative to the scene file.
    pub file: String,
    pub kind: LogKind,
    /// The control (input) channel; for a shock log, the channel checked against `[shock]`.
    pub control: String,
    #[serde(default)]
    pub responses: Vec<String>,
    /// For `random`: the reference profile to check the control against; "random" names the
    /// scene's `[random]` profile, otherwise a `[[f_hz, g2_hz]]` table is expected in
    /// `profile_table`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile_table: Option<Vec<[f64; 2]>>,
    /// Sampling rate, when the log has no time column.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fs_hz: Option<f64>,
    /// Welch segment length (default 8192; an impact test uses one segment per record).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nperseg: Option<usize>,
    /// Welch overlap fraction (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overlap: Option<f64>,
    /// hann (default), hamming, flattop, boxcar.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<String>,
    /// none, constant (default), linear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub detrend: Option<String>,
}

pub fn validate(gates: &GatesSpec, logs: &[TestLogSpec], loc: &Locator) -> Result<(), SpecError> {
    for (key, v) in [
        ("min_lateral_frequency_hz", gates.min_lateral_frequency_hz),
        ("min_axial_frequency_hz", gates.min_axial_frequency_hz),
        ("min_buckling_factor", gates.min_buckling_factor),
        ("max_frequency_shift_pct", gates.max_frequency_shift_pct),
        ("max_amplitude_change_pct", gates.max_amplitude_change_pct),
        ("alarm_db", gates.alarm_db),
        ("abort_db", gates.abort_db),
        ("grms_tolerance_pct", gates.grms_tolerance_pct),
        ("min_separation_speed_m_s", gates.min_separation_speed_m_s),
        ("max_tipoff_rate_deg_s", gates.max_tipoff_rate_deg_s),
    ] {
        if v < 0.0 {
            return Err(loc.err(
                &format!("gates.{key}"),
                format!("must not be negative, got {v}"),
            ));
        }
    }
    let mut names = std::collections::HashSet::new();
    for (i, l) in logs.iter().enumerate() {
        if !names.insert(l.name.as_str()) {
            return Err(loc.err(
                &format!("test_log[{i}].name"),
                format!("duplicate test log name `{}`", l.name),
            ));
        }
        if l.file.trim().is_empty() {
            return Err(loc.err(&format!("test_log[{i}].file"), "empty file name"));
        }
        if let Some(tab) = &l.profile_table {
            let key = format!("test_log[{i}].profile_table");
            if tab.len() < 2 {
                return Err(loc.err(&key, "the profile needs at least two points"));
            }
            super::analysis::validate_psd_points(tab, &key, loc)?;
        }
        if let Some(fs) = l.fs_hz {
            let key = format!("test_log[{i}].fs_hz");
            if fs <= 0.0 {
                return Err(loc.err(&key, format!("must be positive, got {fs}")));
            }
            super::plausible::check(loc, &key, fs, super::plausible::SAMPLING_RATE_HZ)?;
        }
    }
    Ok(())
}
