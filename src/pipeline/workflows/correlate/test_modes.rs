//! The test side of the correlation: real mode shapes over the test points, read from
//! `[test_modes]` or identified (LSCF + LSFD) from the `[[test_log]]`s `[correlation] logs`
//! names, from each log's control to every test point's channel.

use crate::error::{Error, SignalError};
use crate::pipeline::plan::{TestLogPlan, test_log};
use crate::signal::ema::measured::{Layout, read_measured_frfs};
use crate::signal::ema::{Criteria, EmaOptions, FrfForm, FrfSet, Method, identify};
use crate::signal::{PeakOptions, frf_of_files};
use crate::spec::LogKind;
use crate::spec::Scene;
use crate::spec::correlation::{CorrelationSpec, TestModesSpec};
use serde::Serialize;
use std::path::PathBuf;

/// Highest LSCF order and the stable orders a pole needs: the `satqual ema` defaults.
const ORDER_MAX: usize = 60;
const MIN_STABLE_ORDERS: usize = 5;

#[derive(Debug, Clone, Serialize)]
pub struct TestMode {
    pub frequency_hz: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<f64>,
    /// Real shape, one value per test point in scene order.
    pub shape: Vec<f64>,
    /// Modal phase collinearity of an identified mode: how real its complex shape was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mpc: Option<f64>,
}

/// The test modes and a sentence saying where they come from.
pub fn test_modes(scene: &Scene) -> Result<(Vec<TestMode>, String), Error> {
    let f = &scene.file;
    match (&f.test_modes, &f.correlation) {
        (Some(tm), _) => Ok(from_table(scene, tm)),
        (None, Some(c)) if !c.logs.is_empty() => identified(scene, c),
        _ => Err(scene
            .locator()
            .err(
                "test_point",
                "no test modes: give a [test_modes] table or [correlation] logs to identify them from",
            )
            .into()),
    }
}

fn from_table(scene: &Scene, tm: &TestModesSpec) -> (Vec<TestMode>, String) {
    let points = &scene.file.test_point;
    let modes = tm
        .mode
        .iter()
        .map(|m| {
            let shape = match (&m.shape, &m.shape_by_channel) {
                (Some(s), _) => s.clone(),
                (None, Some(map)) => points.iter().map(|p| map[&p.channel]).collect(),
                // One test point and no shape (validated): the mode is seen there.
                (None, None) => vec![1.0],
            };
            TestMode {
                frequency_hz: m.frequency_hz,
                damping_ratio: m.damping_ratio,
                shape,
                mpc: None,
            }
        })
        .collect();
    let source = tm
        .source
        .clone()
        .unwrap_or_else(|| "[test_modes] of the scene".into());
    (modes, source)
}

/// LSCF + LSFD on the FRFs of the named logs, averaged together.
fn identified(scene: &Scene, c: &CorrelationSpec) -> Result<(Vec<TestMode>, String), Error> {
    let (set, control, form) = measured_frfs(scene, c)?;
    let model = identify(
        &set,
        &EmaOptions {
            form,
            ..ema_options(c)
        },
    )?;
    let modes = model.modes.iter().map(real_mode).collect();
    let source = format!(
        "LSCF + LSFD ({} / {}) of test log(s) {}",
        set.channels.join(","),
        control,
        c.logs.join(", ")
    );
    Ok((modes, source))
}

/// The H1 FRFs of the `[correlation] logs`, averaged together, from their shared control to
/// every test point's channel (in test-point order), that control's name and the FRFs' form;
/// or the FRFs the logs store (`kind = "frf"`).
pub fn measured_frfs(
    scene: &Scene,
    c: &CorrelationSpec,
) -> Result<(FrfSet, String, FrfForm), Error> {
    let loc = scene.locator();
    let mut plans = Vec::new();
    for name in &c.logs {
        let (i, t) = scene
            .file
            .test_log
            .iter()
            .enumerate()
            .find(|(_, t)| &t.name == name)
            .expect("validated: every [correlation] log names a [[test_log]]");
        plans.push(test_log(scene, i, t)?);
    }
    let first = &plans[0];
    if let Some(p) = plans.iter().find(|p| p.control != first.control) {
        let msg = format!(
            "control `{}` differs from `{}` of test log `{}`: the logs identified together share one input",
            p.control, first.control, first.name
        );
        return Err(loc
            .err(&format!("test_log[{}].control", p.index), msg)
            .into());
    }
    let paths: Vec<_> = plans.iter().map(|p| p.path.clone()).collect();
    if first.kind == LogKind::Frf {
        return stored_frfs(scene, &paths, first);
    }
    let mut set = FrfSet {
        freqs: Vec::new(),
        channels: Vec::new(),
        h: Vec::new(),
    };
    for (i, tp) in scene.file.test_point.iter().enumerate() {
        let frf = frf_of_files(
            &paths,
            &first.control,
            &tp.channel,
            &first.ingest,
            &first.welch,
        )
        .map_err(|e| locate_channel(scene, e, i, &tp.channel, first.index, &first.control))?;
        if set.freqs.is_empty() {
            set.freqs = frf.frequencies();
        }
        set.channels.push(tp.channel.clone());
        set.h.push(frf.h1());
    }
    Ok((set, first.control.clone(), FrfForm::Accelerance))
}

/// The stored FRFs of the reference a log's control names, or, from a roving hammer, of the
/// response it names: one per test point's channel, in the form the file states.
fn stored_frfs(
    scene: &Scene,
    paths: &[PathBuf],
    log: &TestLogPlan,
) -> Result<(FrfSet, String, FrfForm), Error> {
    let loc = scene.locator();
    let key = |k: &str| format!("test_log[{}].{k}", log.index);
    let channels: Vec<String> = scene
        .file
        .test_point
        .iter()
        .map(|tp| tp.channel.clone())
        .collect();
    let measured = match read_measured_frfs(paths, Some(&log.control), &channels) {
        Ok(Some(m)) => m,
        Ok(None) => {
            let msg = "kind = \"frf\", but the file holds no FRF (UFF58 function type 4)";
            return Err(loc.err(&key("kind"), msg).into());
        }
        Err(by_reference) => match read_measured_frfs(paths, None, &channels) {
            Ok(Some(m))
                if m.layout == Layout::CommonResponse
                    && same_point(&m.common_point, &log.control) =>
            {
                m
            }
            _ => return Err(loc.err(&key("control"), by_reference.to_string()).into()),
        },
    };
    let form = measured.form.unwrap_or(FrfForm::Accelerance);
    Ok((measured.set, measured.common_point, form))
}

/// Whether a point as the reader names it (`TestCase:1:+X`) is the one a scene names, with or
/// without its entity.
fn same_point(full: &str, named: &str) -> bool {
    let (full, named) = (full.to_lowercase(), named.to_lowercase());
    full == named || full.ends_with(&format!(":{named}"))
}

/// A channel missing from the log, located at the test point or the log's control naming it.
fn locate_channel(
    scene: &Scene,
    e: SignalError,
    point: usize,
    channel: &str,
    log: usize,
    control: &str,
) -> Error {
    let loc = scene.locator();
    match &e {
        SignalError::NoSuchChannel { name, .. } if name == channel => loc
            .err(&format!("test_point[{point}].channel"), e.to_string())
            .into(),
        SignalError::NoSuchChannel { name, .. } if name == control => loc
            .err(&format!("test_log[{log}].control"), e.to_string())
            .into(),
        SignalError::Channel { .. } => loc
            .err(&format!("test_point[{point}].channel"), e.to_string())
            .into(),
        _ => e.into(),
    }
}

fn ema_options(c: &CorrelationSpec) -> EmaOptions {
    EmaOptions {
        f_lo: c.fmin_hz.unwrap_or(0.0),
        f_hi: c.fmax_hz.unwrap_or(f64::MAX),
        method: Method::Lscf,
        order_max: ORDER_MAX,
        order_max_is_default: false,
        form: FrfForm::Accelerance,
        criteria: Criteria {
            min_orders: MIN_STABLE_ORDERS,
            ..Criteria::default()
        },
        peaks: PeakOptions::default(),
    }
}

/// The real shape of an identified mode: every component turned by the phase of the largest
/// one, then its real part (a normal mode's components are in or out of phase; the MPC says
/// how far the measured shape is from that).
fn real_mode(m: &crate::signal::ema::Mode) -> TestMode {
    let largest = m
        .shape
        .iter()
        .max_by(|a, b| a.re.hypot(a.im).total_cmp(&b.re.hypot(b.im)));
    let phase = largest.map_or(0.0, |s| s.im.atan2(s.re));
    let (c, s) = (phase.cos(), phase.sin());
    TestMode {
        frequency_hz: m.frequency_hz,
        damping_ratio: Some(m.damping_ratio),
        shape: m.shape.iter().map(|e| e.re * c + e.im * s).collect(),
        mpc: Some(m.mpc),
    }
}
