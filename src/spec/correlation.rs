//! Scene keys of test-analysis correlation: `[[test_point]]` (which model DOF each measured
//! channel sees, with the sensor's mass), `[test_modes]` (modes identified elsewhere) and
//! `[correlation]` (the frequency standard and, without `[test_modes]`, the logs to identify
//! the modes from).

use super::{Locator, SceneFile};
use crate::error::SpecError;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashSet};

/// One measured channel and the model DOF it sees.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestPointSpec {
    /// The channel's name in the logs, or in `[test_modes]` shapes.
    pub channel: String,
    /// Scene node id.
    pub node: i64,
    /// `+x`, `-x`, `+y`, `-y`, `+z` or `-z` (global axes).
    pub direction: String,
    /// The sensor's mass, added to the model as a lumped mass at the node.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor_mass_kg: Option<f64>,
}

impl TestPointSpec {
    /// (axis 0..3, sign) of the direction, `None` when it is not one of the six.
    pub fn axis(&self) -> Option<(usize, f64)> {
        parse_direction(&self.direction)
    }
}

pub fn parse_direction(d: &str) -> Option<(usize, f64)> {
    let sign = match d.as_bytes().first()? {
        b'+' => 1.0,
        b'-' => -1.0,
        _ => return None,
    };
    let axis = match &d[1..] {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        _ => return None,
    };
    Some((axis, sign))
}

/// Modes identified outside satqual.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestModesSpec {
    /// Where the modes come from (report text).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    pub mode: Vec<TestModeSpec>,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestModeSpec {
    pub frequency_hz: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<f64>,
    /// Real shape, one value per `[[test_point]]` in scene order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<Vec<f64>>,
    /// Real shape by channel name; every test point's channel must appear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape_by_channel: Option<BTreeMap<String, f64>>,
    /// The mode's measured peak response in the scene's sine test: `satqual update` identifies
    /// the mode's damping from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak: Option<TestPeakSpec>,
}

/// `peak = { channel, g }`: the largest absolute acceleration the channel measured, along its
/// direction, in the sine sweep along that direction (the scene's `[sine]` input).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestPeakSpec {
    pub channel: String,
    pub g: f64,
}

/// The frequency-error limit of the paired modes, by the standard that states it.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum FrequencyStandard {
    /// ECSS-E-ST-32-11C: ±3% for the primary modes.
    #[default]
    #[serde(rename = "ecss-e-st-32-11c")]
    EcssEst3211c,
    /// NASA-STD-5002: ±5%.
    #[serde(rename = "nasa-std-5002")]
    NasaStd5002,
}

impl FrequencyStandard {
    pub fn tolerance_pct(self) -> f64 {
        match self {
            FrequencyStandard::EcssEst3211c => 3.0,
            FrequencyStandard::NasaStd5002 => 5.0,
        }
    }

    pub fn source(self) -> &'static str {
        match self {
            FrequencyStandard::EcssEst3211c => {
                "ECSS-E-ST-32-11C (±3% for primary modes), [correlation] frequency_standard"
            }
            FrequencyStandard::NasaStd5002 => {
                "NASA-STD-5002 (±5%), [correlation] frequency_standard"
            }
        }
    }
}

/// How `satqual correlate` gets its test modes and judges them.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct CorrelationSpec {
    /// `ecss-e-st-32-11c` (±3%, default) or `nasa-std-5002` (±5%).
    pub frequency_standard: FrequencyStandard,
    /// Without `[test_modes]`: the `[[test_log]]` names whose FRFs (their `control` to every
    /// test point's channel) are averaged and identified by LSCF + LSFD.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub logs: Vec<String>,
    /// The band identified from the logs, Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fmin_hz: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fmax_hz: Option<f64>,
}

/// Checks the test points against the model and the test modes against the test points.
pub fn validate(file: &SceneFile, model: &SceneFile, loc: &Locator) -> Result<(), SpecError> {
    let nodes: HashSet<i64> = model.node.iter().map(|n| n.id).collect();
    let mut channels = HashSet::new();
    for (i, tp) in file.test_point.iter().enumerate() {
        let key = |k: &str| format!("test_point[{i}].{k}");
        if !nodes.contains(&tp.node) {
            let msg = format!("node {} is not in the model", tp.node);
            return Err(loc.err(&key("node"), msg));
        }
        if tp.axis().is_none() {
            let msg = format!("`{}`: expected +x, -x, +y, -y, +z or -z", tp.direction);
            return Err(loc.err(&key("direction"), msg));
        }
        if let Some(m) = tp.sensor_mass_kg
            && m < 0.0
        {
            return Err(loc.err(
                &key("sensor_mass_kg"),
                format!("must not be negative, got {m}"),
            ));
        }
        if !channels.insert(tp.channel.as_str()) {
            let msg = format!("channel `{}` is on two test points", tp.channel);
            return Err(loc.err(&key("channel"), msg));
        }
    }
    if let Some(tm) = &file.test_modes {
        validate_test_modes(tm, &file.test_point, loc)?;
        validate_peaks(tm, file, loc)?;
    }
    if let Some(c) = &file.correlation {
        validate_correlation(c, file, loc)?;
    }
    validate_frf_logs(file, loc)
}

/// Stored FRFs feed the correlation only: one named by no `[correlation] logs` would be read
/// by nothing, and mixing them with time logs there would average FRFs with spectra.
fn validate_frf_logs(file: &SceneFile, loc: &Locator) -> Result<(), SpecError> {
    let named = |n: &String| {
        file.correlation
            .as_ref()
            .is_some_and(|c| c.logs.contains(n))
    };
    let is_frf = |n: &String| {
        file.test_log
            .iter()
            .any(|l| &l.name == n && l.kind == super::LogKind::Frf)
    };
    for (i, l) in file.test_log.iter().enumerate() {
        if l.kind == super::LogKind::Frf && !named(&l.name) {
            let msg =
                "a log of stored FRFs is read by [correlation] only: name it in [correlation] logs";
            return Err(loc.err(&format!("test_log[{i}].kind"), msg));
        }
    }
    if let Some(c) = &file.correlation
        && c.logs.iter().any(is_frf)
        && !c.logs.iter().all(is_frf)
    {
        let msg = "stored FRFs (kind = \"frf\") cannot be averaged with the spectra of time logs: name one kind";
        return Err(loc.err("correlation.logs", msg));
    }
    Ok(())
}

fn validate_test_modes(
    tm: &TestModesSpec,
    points: &[TestPointSpec],
    loc: &Locator,
) -> Result<(), SpecError> {
    if points.is_empty() {
        return Err(loc.err("test_modes", "test modes need [[test_point]] entries"));
    }
    if tm.mode.is_empty() {
        return Err(loc.err("test_modes", "no [[test_modes.mode]] given"));
    }
    for (i, m) in tm.mode.iter().enumerate() {
        let key = |k: &str| format!("test_modes.mode[{i}].{k}");
        if m.frequency_hz <= 0.0 {
            let msg = format!("must be positive, got {}", m.frequency_hz);
            return Err(loc.err(&key("frequency_hz"), msg));
        }
        let (k, f) = (key("frequency_hz"), m.frequency_hz);
        super::plausible::check(loc, &k, f, super::plausible::FREQUENCY_HZ)?;
        if let Some(z) = m.damping_ratio
            && !(0.0..1.0).contains(&z)
        {
            return Err(loc.err(&key("damping_ratio"), format!("must be in [0, 1), got {z}")));
        }
        match (&m.shape, &m.shape_by_channel) {
            (Some(_), Some(_)) => {
                return Err(loc.err(&key("shape"), "give shape or shape_by_channel, not both"));
            }
            (Some(s), None) if s.len() != points.len() => {
                let msg = format!(
                    "{} values for {} test points (one per [[test_point]], in scene order)",
                    s.len(),
                    points.len()
                );
                return Err(loc.err(&key("shape"), msg));
            }
            (None, Some(map)) => check_shape_channels(map, points, &key("shape_by_channel"), loc)?,
            (None, None) if points.len() > 1 => {
                let msg = "a shape is needed with more than one test point";
                return Err(loc.err(&key("frequency_hz"), msg));
            }
            _ => {}
        }
    }
    Ok(())
}

/// Every peak names a test point's channel and a positive level, and the scene has the sine
/// input it was measured under.
fn validate_peaks(tm: &TestModesSpec, file: &SceneFile, loc: &Locator) -> Result<(), SpecError> {
    for (i, m) in tm.mode.iter().enumerate() {
        let Some(p) = &m.peak else { continue };
        let key = |k: &str| format!("test_modes.mode[{i}].peak.{k}");
        if !file.test_point.iter().any(|t| t.channel == p.channel) {
            let msg = format!("`{}` is not the channel of a [[test_point]]", p.channel);
            return Err(loc.err(&key("channel"), msg));
        }
        if !(p.g > 0.0 && p.g.is_finite()) {
            return Err(loc.err(&key("g"), format!("must be positive, got {}", p.g)));
        }
        if file.sine.is_none() {
            let msg = "a measured sine peak needs the scene's [sine] input it was measured under";
            return Err(loc.err(&key("g"), msg));
        }
    }
    Ok(())
}

fn check_shape_channels(
    map: &BTreeMap<String, f64>,
    points: &[TestPointSpec],
    key: &str,
    loc: &Locator,
) -> Result<(), SpecError> {
    if let Some(c) = map
        .keys()
        .find(|c| !points.iter().any(|p| &p.channel == *c))
    {
        return Err(loc.err(
            key,
            format!("channel `{c}` is not a [[test_point]] channel"),
        ));
    }
    if let Some(p) = points.iter().find(|p| !map.contains_key(&p.channel)) {
        let msg = format!("channel `{}` of a [[test_point]] is missing", p.channel);
        return Err(loc.err(key, msg));
    }
    Ok(())
}

fn validate_correlation(
    c: &CorrelationSpec,
    file: &SceneFile,
    loc: &Locator,
) -> Result<(), SpecError> {
    for (i, name) in c.logs.iter().enumerate() {
        if !file.test_log.iter().any(|l| &l.name == name) {
            let msg = format!("no [[test_log]] is named `{name}`");
            return Err(loc.err(&format!("correlation.logs[{i}]"), msg));
        }
    }
    for (key, v) in [("fmin_hz", c.fmin_hz), ("fmax_hz", c.fmax_hz)] {
        if let Some(f) = v
            && f < 0.0
        {
            return Err(loc.err(
                &format!("correlation.{key}"),
                format!("must not be negative, got {f}"),
            ));
        }
    }
    Ok(())
}

/// The sensors' masses as lumped masses of the model.
pub fn add_sensor_masses(file: &SceneFile, model: &mut SceneFile) {
    for tp in &file.test_point {
        if let Some(m) = tp.sensor_mass_kg.filter(|m| *m > 0.0) {
            model.mass.push(super::Mass {
                node: tp.node,
                mass_kg: m,
                inertia_kg_m2: [0.0; 3],
                offset_m: [0.0; 3],
            });
        }
    }
}
