//! Per-mode damping identified from the measured sine peaks of the test modes (`peak` in
//! `[[test_modes.mode]]`): on the updated model, the damping ratio of each paired FE mode is
//! scaled by (predicted peak / measured peak) until the scene's sine input reproduces every
//! measured peak. Near a lightly damped resonance the peak goes as 1/ζ, so the fixed point
//! converges in a few steps; the measured peaks are reproduced by construction, so the
//! identified ratios, not the peaks, are the result.

use super::TargetResult;
use crate::error::Error;
use crate::pipeline::plan::{ModalOverrides, modal_options};
use crate::response::{Prepared, SineOptions, sine};
use crate::spec::Scene;
use crate::spec::analysis::ModeDamping;
use serde::Serialize;

/// Relative peak mismatch at which the identification stops.
const PEAK_TOL: f64 = 1e-6;
/// Fixed-point steps before giving up.
const MAX_STEPS: usize = 50;

#[derive(Debug, Clone, Serialize)]
pub struct IdentifiedDamping {
    pub test_mode: usize,
    pub fe_mode: usize,
    pub channel: String,
    pub measured_g: f64,
    /// The model's peak with the identified ratio.
    pub predicted_g: f64,
    /// The mode's ratio before (the scene's damping) and identified.
    pub zeta_start: f64,
    pub zeta: f64,
    /// The family the entry names (`[damping] modes` `direction`): the scene's own entry's,
    /// else the updated model's mode's largest effective-mass direction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<String>,
}

/// One measured peak: the test mode, its paired FE mode, where and how much.
struct Peak {
    test_mode: usize,
    fe_mode: usize,
    channel: String,
    axis: usize,
    point: usize,
    measured_g: f64,
}

/// The identified ratios of the modes whose test mode gives a peak, on `updated` (the scene
/// at the updated values) with the pairing of `targets`; empty when no test mode has a peak.
pub fn identify(
    updated: &Scene,
    targets: &[TargetResult],
) -> Result<Vec<IdentifiedDamping>, Error> {
    let Some(sine_spec) = updated.file.sine.clone() else {
        return Ok(Vec::new());
    };
    let opts = modal_options(updated, &ModalOverrides::default());
    let (model, sys) = super::super::modal::run(updated, &opts)?;
    let mut prep = Prepared::new(updated, &model, &sys)?;
    let peaks = peaks(updated, targets, &prep)?;
    if peaks.is_empty() {
        return Ok(Vec::new());
    }
    let frequency = |mode: usize| sys.result.modes[mode - 1].frequency_hz;
    let start: Vec<f64> = (peaks.iter())
        .map(|p| prep.damping.zeta_of_mode(p.fe_mode, frequency(p.fe_mode)))
        .collect();
    let mut zeta = start.clone();
    let base_modes = prep.damping.modes.clone().unwrap_or_default();
    let directions: Vec<Option<String>> = (peaks.iter())
        .map(|p| {
            let own = base_modes.iter().find(|m| m.mode == p.fe_mode);
            own.and_then(|m| m.direction.clone()).or_else(|| {
                let mode = &sys.result.modes[p.fe_mode - 1];
                mode.dominant_direction().map(str::to_string)
            })
        })
        .collect();
    for _ in 0..MAX_STEPS {
        prep.damping.modes = Some(with_modes(&base_modes, &peaks, &zeta, &directions));
        let predicted = predicted_peaks(&prep, &sine_spec, &peaks)?;
        let ratio: Vec<f64> = (predicted.iter().zip(&peaks))
            .map(|(g, p)| g / p.measured_g)
            .collect();
        if ratio.iter().all(|r| (r - 1.0).abs() < PEAK_TOL) {
            return Ok(results(&peaks, &predicted, &start, &zeta, &directions));
        }
        for (z, r) in zeta.iter_mut().zip(&ratio) {
            *z = (*z * r).clamp(5e-5, 0.999);
        }
    }
    Err(updated
        .locator()
        .err(
            "test_modes",
            format!("the damping identified from the measured sine peaks did not settle in {MAX_STEPS} steps: a peak is not governed by its paired mode"),
        )
        .into())
}

/// The scene's per-mode entries with the identified ones in place of theirs.
fn with_modes(
    base: &[ModeDamping],
    peaks: &[Peak],
    zeta: &[f64],
    directions: &[Option<String>],
) -> Vec<ModeDamping> {
    let mut modes: Vec<ModeDamping> = (base.iter())
        .filter(|m| !peaks.iter().any(|p| p.fe_mode == m.mode))
        .cloned()
        .collect();
    modes.extend(
        (peaks.iter().zip(zeta).zip(directions)).map(|((p, &zeta), direction)| ModeDamping {
            mode: p.fe_mode,
            zeta,
            direction: direction.clone(),
        }),
    );
    modes.sort_by_key(|m| m.mode);
    modes
}

/// Each peak's point on its sweep axis, the sweeps run once per axis.
fn predicted_peaks(
    prep: &Prepared,
    spec: &crate::spec::analysis::SineSpec,
    peaks: &[Peak],
) -> Result<Vec<f64>, Error> {
    let mut by_axis: Vec<(usize, sine::SineAxis)> = Vec::new();
    for p in peaks {
        if !by_axis.iter().any(|(a, _)| *a == p.axis) {
            by_axis.push((
                p.axis,
                sine::run(prep, spec, p.axis, &SineOptions::default())?,
            ));
        }
    }
    Ok(peaks
        .iter()
        .map(|p| {
            let run = &by_axis
                .iter()
                .find(|(a, _)| *a == p.axis)
                .expect("run above")
                .1;
            run.peaks[p.point].acceleration_g
        })
        .collect())
}

/// The measured peaks of the test modes, each with its paired FE mode and response point.
fn peaks(scene: &Scene, targets: &[TargetResult], prep: &Prepared) -> Result<Vec<Peak>, Error> {
    let loc = scene.locator();
    let Some(tm) = &scene.file.test_modes else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (i, m) in tm.mode.iter().enumerate() {
        let Some(peak) = &m.peak else { continue };
        let key = format!("test_modes.mode[{i}].peak");
        let Some(t) = targets.iter().find(|t| t.test_mode == i + 1) else {
            let msg = "the mode is not an update target, so no FE mode is paired with it";
            return Err(loc.err(&key, msg).into());
        };
        let tp = (scene.file.test_point.iter())
            .find(|t| t.channel == peak.channel)
            .expect("validated: the channel is a test point's");
        let axis = tp.axis().expect("validated direction").0;
        let Some(point) = prep.outputs.points.iter().position(|p| p.node == tp.node) else {
            let msg = format!(
                "node {} of channel `{}` is not a response point: add a [[response]] at it",
                tp.node, peak.channel
            );
            return Err(loc.err(&key, msg).into());
        };
        out.push(Peak {
            test_mode: i + 1,
            fe_mode: t.fe_mode,
            channel: peak.channel.clone(),
            axis,
            point,
            measured_g: peak.g,
        });
    }
    Ok(out)
}

fn results(
    peaks: &[Peak],
    predicted: &[f64],
    start: &[f64],
    zeta: &[f64],
    directions: &[Option<String>],
) -> Vec<IdentifiedDamping> {
    (0..peaks.len())
        .map(|i| IdentifiedDamping {
            test_mode: peaks[i].test_mode,
            fe_mode: peaks[i].fe_mode,
            channel: peaks[i].channel.clone(),
            measured_g: peaks[i].measured_g,
            predicted_g: predicted[i],
            zeta_start: start[i],
            zeta: zeta[i],
            direction: directions[i].clone(),
        })
        .collect()
}
