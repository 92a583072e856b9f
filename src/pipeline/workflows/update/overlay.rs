//! Measured FRFs against the model's before and after an update: for scenes whose test modes
//! come from logs (`[correlation] logs`), |H| of each test point's channel over the logs'
//! control, beside the base-driven transmissibility of the model at the same point and
//! direction, on the identification band.

use crate::error::Error;
use crate::pipeline::plan::{ModalOverrides, modal_options};
use crate::pipeline::workflows::correlate::test_modes::measured_frfs;
use crate::response::{OutputSet, Prepared};
use crate::spec::analysis::ResponsePoint;
use crate::spec::{LogKind, Scene};
use serde::Serialize;

#[derive(Debug, Clone, Serialize)]
pub struct Overlay {
    pub channel: String,
    pub frequency_hz: Vec<f64>,
    pub measured: Vec<f64>,
    pub before: Vec<f64>,
    pub after: Vec<f64>,
}

/// The overlays, or why there are none (no logs; stored FRFs per force; test points along
/// several axes, so the logs' drive axis is not known).
pub fn overlays(before: &Scene, after: &Scene) -> Result<Result<Vec<Overlay>, String>, Error> {
    let Some(c) = before
        .file
        .correlation
        .as_ref()
        .filter(|c| !c.logs.is_empty())
    else {
        return Ok(Err(
            "no FRF overlay: the test modes do not come from logs".into()
        ));
    };
    let stored =
        |n: &String| (before.file.test_log.iter()).any(|l| &l.name == n && l.kind == LogKind::Frf);
    if c.logs.iter().any(stored) {
        let msg = "no FRF overlay: the stored FRFs are per unit force, and the model's overlay is a base-drive transmissibility";
        return Ok(Err(msg.into()));
    }
    let axes: Vec<(usize, f64)> = (before.file.test_point.iter())
        .map(|t| t.axis().expect("validated direction"))
        .collect();
    let drive = axes[0].0;
    if axes.iter().any(|a| a.0 != drive) {
        let msg = "no FRF overlay: the test points lie along several axes, and the logs do not say which one the shaker drove";
        return Ok(Err(msg.into()));
    }
    let (set, _, _) = measured_frfs(before, c)?;
    let (lo, hi) = (c.fmin_hz.unwrap_or(0.0), c.fmax_hz.unwrap_or(f64::INFINITY));
    let lines: Vec<usize> = (0..set.freqs.len())
        .filter(|&k| set.freqs[k] > 0.0 && set.freqs[k] >= lo && set.freqs[k] <= hi)
        .collect();
    let freqs: Vec<f64> = lines.iter().map(|&k| set.freqs[k]).collect();
    let predicted_before = transmissibility(before, drive, &freqs)?;
    let predicted_after = transmissibility(after, drive, &freqs)?;
    Ok(Ok((0..set.channels.len())
        .map(|o| Overlay {
            channel: set.channels[o].clone(),
            frequency_hz: freqs.clone(),
            measured: lines.iter().map(|&k| set.h[o][k].norm()).collect(),
            before: predicted_before[o].clone(),
            after: predicted_after[o].clone(),
        })
        .collect()))
}

/// |absolute acceleration / base acceleration| of every test point along its direction, for
/// a base drive along `drive`, at `freqs`.
fn transmissibility(scene: &Scene, drive: usize, freqs: &[f64]) -> Result<Vec<Vec<f64>>, Error> {
    let opts = modal_options(scene, &ModalOverrides::default());
    let (model, sys) = super::super::modal::run(scene, &opts)?;
    let points: Vec<ResponsePoint> = (scene.file.test_point.iter())
        .map(|t| ResponsePoint {
            name: t.channel.clone(),
            node: t.node,
        })
        .collect();
    let mut prep = Prepared::new(scene, &model, &sys)?;
    prep.outputs = OutputSet::build(scene, &model, &sys, &points)?;
    let basis = prep.basis(drive, None, true)?;
    let frf = prep.modal_frf(&basis);
    Ok((scene.file.test_point.iter().enumerate())
        .map(|(i, t)| {
            let row = prep.outputs.points[i].rows[t.axis().expect("validated").0];
            freqs.iter().map(|&f| frf.eval_row(f, row).norm()).collect()
        })
        .collect())
}
