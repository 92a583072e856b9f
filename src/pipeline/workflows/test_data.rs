//! The test-data workflow of `qualify`: every planned `[[test_log]]` through the PSD, FRF or
//! SRS workflow, the random control against its profile, a shock record against the shock
//! specification, the pre/post signatures compared, and the curves the report plots.

use super::frf::{self, FrfRequest};
use super::psd::{self, PsdRequest};
use crate::error::Error;
use crate::gates::{self, Verdict};
use crate::pipeline::plan::TestLogPlan;
use crate::results::{ShockChannel, TestDataSummary, TestLogResult};
use crate::signal::srs::{SpecTolerance, check_against_spec};
use crate::signal::{
    self as sg, Offset, PeakOptions, Resonance, SignatureCriteria, SrsOptions, ToleranceSpec,
};
use crate::spec::ShockSpec;
use crate::spec::{GatesSpec, Locator, LogKind};

/// Curve points of the tolerance bands drawn around a profile.
const BAND_POINTS: usize = 200;

/// Runs every log, in scene order, then compares the signatures; returns the gates with it.
pub fn run(
    logs: &[TestLogPlan],
    limits: &GatesSpec,
    loc: &Locator,
) -> Result<(TestDataSummary, Vec<Verdict>), Error> {
    let mut results = Vec::new();
    let mut verdicts = Vec::new();
    let (mut before, mut after) = (None, None);
    for log in logs.iter().filter(|l| l.kind != LogKind::Frf) {
        let res = match log.kind {
            LogKind::Random => random_log(log, limits, loc, &mut verdicts),
            LogKind::Shock => shock_log(log, loc, &mut verdicts),
            _ => frf_log(log),
        }
        .map_err(|e| locate_rate_error(e, log, loc))?;
        match log.kind {
            LogKind::SignatureBefore => before = Some(res.resonances.clone()),
            LogKind::SignatureAfter => after = Some(res.resonances.clone()),
            _ => {}
        }
        results.push(res);
    }
    let signature = before
        .zip(after)
        .map(|(b, a)| compare_signatures(&b, &a, limits));
    if let Some(rep) = &signature {
        verdicts.extend(gates::test_data::signature(rep, limits));
    }
    let summary = TestDataSummary {
        logs: results,
        signature,
    };
    Ok((summary, verdicts))
}

fn empty_result(log: &TestLogPlan) -> TestLogResult {
    TestLogResult {
        name: log.name.clone(),
        file: log.file.clone(),
        kind: log.kind,
        tolerance: None,
        channels: Vec::new(),
        resonances: Vec::new(),
        shock: Vec::new(),
        curves: Vec::new(),
        log_scale_y: true,
    }
}

/// A random log: Grms and PSD of every channel, the control against the profile when given.
fn random_log(
    log: &TestLogPlan,
    limits: &GatesSpec,
    loc: &Locator,
    verdicts: &mut Vec<Verdict>,
) -> Result<TestLogResult, Error> {
    // A UFF PSD record has no channel names to select by: take every channel then.
    let uff = sg::uff::looks_like_uff(&log.path);
    let mut ingest = log.ingest.clone();
    if !uff {
        let mut channels = vec![log.control.clone()];
        channels.extend(log.responses.iter().cloned());
        ingest.channels = Some(channels);
    }
    let run = psd::run(&PsdRequest {
        log: &log.path,
        ingest,
        welch: log.welch.clone(),
        peaks: None,
        tolerance: None,
    })?;
    let mut res = empty_result(log);
    res.channels = run
        .psd
        .channels
        .iter()
        .map(|c| (c.name.clone(), c.grms))
        .collect();
    // A UFF file's channels are named by their records (`Channel 1`, or the record's name).
    let control = run.psd.channels.iter().find(|c| c.name == log.control);
    let control = control.ok_or_else(|| {
        let names: Vec<&str> = run.psd.channels.iter().map(|c| c.name.as_str()).collect();
        let msg = format!(
            "channel `{}` is not in {} (its channels: {})",
            log.control,
            log.file,
            names.join(", ")
        );
        loc.err(&format!("test_log[{}].control", log.index), msg)
    })?;
    for c in &run.psd.channels {
        let pts = c
            .psd
            .frequencies()
            .into_iter()
            .zip(c.psd.values.iter().copied());
        let pts = pts.filter(|p| p.0 > 0.0).collect();
        res.curves
            .push((format!("{} (Grms {:.3})", c.name, c.grms), pts));
    }
    if let Some(profile) = &log.profile {
        let spec = ToleranceSpec {
            alarm_db: limits.alarm_db,
            abort_db: limits.abort_db,
            grms_pct: limits.grms_tolerance_pct,
        };
        let rep = psd::tolerance(control, profile, &spec)?;
        verdicts.extend(gates::test_data::random_control(&log.name, &rep, limits));
        res.curves.extend(tolerance_curves(profile, limits));
        res.tolerance = Some(rep);
    }
    Ok(res)
}

/// The profile and its ± alarm and abort bands, on a log grid over the profile's band.
fn tolerance_curves(profile: &[(f64, f64)], limits: &GatesSpec) -> Vec<(String, Vec<(f64, f64)>)> {
    let (lo, hi) = (profile[0].0, profile[profile.len() - 1].0);
    let band = |db: f64| -> Vec<(f64, f64)> {
        crate::response::grid::log_n(lo, hi, BAND_POINTS)
            .into_iter()
            .map(|x| {
                (
                    x,
                    crate::units::loglog_interp(profile, x) * 10f64.powf(db / 10.0),
                )
            })
            .collect()
    };
    let (alarm, abort) = (limits.alarm_db, limits.abort_db);
    vec![
        ("profile".into(), band(0.0)),
        (format!("+{alarm} dB alarm"), band(alarm)),
        (format!("−{alarm} dB alarm"), band(-alarm)),
        (format!("+{abort} dB abort"), band(abort)),
        (format!("−{abort} dB abort"), band(-abort)),
    ]
}

/// A shock log: the SRS of the control and of each response over the specification's band
/// (mean removed), each checked against the scene's `[shock]`.
fn shock_log(
    log: &TestLogPlan,
    loc: &Locator,
    verdicts: &mut Vec<Verdict>,
) -> Result<TestLogResult, Error> {
    let spec = log.shock.as_ref().ok_or_else(|| {
        let key = format!("test_log[{}].kind", log.index);
        loc.err(&key, "a shock log needs the scene's [shock] specification")
    })?;
    let points = spec.breakpoints();
    let mut ingest = log.ingest.clone();
    let mut channels = vec![log.control.clone()];
    channels.extend(log.responses.iter().cloned());
    ingest.channels = Some(channels);
    let opts = SrsOptions {
        q: spec.q,
        fmin_hz: points[0].0,
        fmax_hz: points[points.len() - 1].0,
        per_octave: spec.per_octave,
        offset: Offset::Mean,
    };
    let srs = sg::srs_of_file(&log.path, &ingest, &opts)?;
    let tol = shock_tolerance(spec);
    let mut res = empty_result(log);
    for c in srs.channels {
        let check = check_against_spec(&c.srs, &points, tol);
        verdicts.extend(gates::test_data::shock_spec(&log.name, &c.name, &check));
        let maximax = c.srs.iter().map(|p| (p.frequency_hz, p.maximax)).collect();
        res.curves
            .push((format!("{} SRS maximax, Q = {}", c.name, spec.q), maximax));
        res.shock.push(ShockChannel {
            name: c.name,
            unit: c.unit,
            peak: c.peak,
            peak_time_s: c.peak_time_s,
            check,
        });
    }
    res.curves.extend(shock_spec_curves(&points, tol));
    Ok(res)
}

fn shock_tolerance(spec: &ShockSpec) -> SpecTolerance {
    SpecTolerance {
        upper_db: spec.upper_db,
        lower_db: spec.lower_db,
        allowed_fraction: spec.allowed_fraction,
    }
}

/// The shock specification and its upper and lower limits (an SRS is an amplitude: 20 dB per
/// decade), on a log grid over its band.
fn shock_spec_curves(points: &[(f64, f64)], tol: SpecTolerance) -> Vec<(String, Vec<(f64, f64)>)> {
    let (lo, hi) = (points[0].0, points[points.len() - 1].0);
    let band = |db: f64| -> Vec<(f64, f64)> {
        crate::response::grid::log_n(lo, hi, BAND_POINTS)
            .into_iter()
            .map(|x| {
                (
                    x,
                    crate::units::loglog_interp(points, x) * 10f64.powf(db / 20.0),
                )
            })
            .collect()
    };
    vec![
        ("shock spec".into(), band(0.0)),
        (format!("+{} dB", tol.upper_db), band(tol.upper_db)),
        (format!("−{} dB", tol.lower_db), band(-tol.lower_db)),
    ]
}

/// A rate the scene gave (`fs_hz`) that the file's own rate contradicts (or that is not
/// positive) is the scene's error: located at that key.
fn locate_rate_error(e: Error, log: &TestLogPlan, loc: &Locator) -> Error {
    match e {
        Error::Signal(crate::error::SignalError::BadParameter {
            name: "fs", reason, ..
        }) if log.ingest.fs.is_some() => loc
            .err(&format!("test_log[{}].fs_hz", log.index), reason)
            .into(),
        other => other,
    }
}

/// A sweep or signature log: the FRF control → first response, its resonances and curves.
fn frf_log(log: &TestLogPlan) -> Result<TestLogResult, Error> {
    let output = &log.responses[0];
    let run = frf::run(&FrfRequest {
        logs: std::slice::from_ref(&log.path),
        input: &log.control,
        output,
        ingest: log.ingest.clone(),
        welch: log.welch.clone(),
        welch_is_default: false,
        peaks: PeakOptions {
            max_peaks: log.max_peaks,
            db_per_decade: 20.0,
            ..Default::default()
        },
        from_first_line: true,
        screen: None,
    })?;
    let f = run.frf.frequencies();
    let h1 = run.frf.h1();
    let coh = run.frf.coherence();
    let mut res = empty_result(log);
    res.resonances = run.resonances;
    let mag = f
        .iter()
        .zip(&h1)
        .skip(1)
        .map(|(x, v)| (*x, v.norm()))
        .collect();
    res.curves
        .push((format!("|H1| {output}/{}", log.control), mag));
    let c = f.iter().zip(&coh).skip(1).map(|(x, v)| (*x, *v)).collect();
    res.curves.push(("coherence".into(), c));
    Ok(res)
}

fn compare_signatures(
    before: &[Resonance],
    after: &[Resonance],
    limits: &GatesSpec,
) -> sg::SignatureReport {
    let criteria = SignatureCriteria {
        max_shift_pct: limits.max_frequency_shift_pct,
        max_amp_change_pct: limits.max_amplitude_change_pct,
        ..Default::default()
    };
    super::signature::compare(before, after, &criteria)
}
