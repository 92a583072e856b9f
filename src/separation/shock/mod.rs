//! The release shock: the acceleration history of every moving body (satellites, and the
//! carrier when it is free) from the forces that act on it (springs, bore contacts, friction)
//! divided by its mass, its peak in g, its shock response spectrum per axis, and the check of
//! that spectrum against a component shock specification.
//!
//! The run records the acceleration at every accepted step (`sim::records`); [`resample`]
//! puts it on a uniform grid of `sample_rate_hz` over the window the body moves under forces
//! (a satellite from its release to its exit from the bars, the free carrier from the first
//! release to the end of the run). The peak comes from the recorded step ends (the forces at
//! the states the integrator accepted); the spectrum from the grid, through the SRS of
//! `signal::srs` (Smallwood filter) and its specification check, unchanged. No offset is
//! removed: the history starts at rest, so its level is the shock's own.
//!
//! Axes are those of the carrier frame (x, y lateral, z along the bars); a satellite tilts by
//! at most clearance/pitch ≈ 2 mrad on the bars, so they are its own axes to 2e-6 in the
//! cosine.

mod resample;

pub use resample::resample;

use super::{Model, SeparationResult};
use crate::error::SignalError;
use crate::signal::srs::natural_frequencies;
use crate::signal::srs::{SpecCheck, SpecTolerance, SrsPoint, check_against_spec, srs};
use crate::spec::separation::ShockSpec;
use crate::units::G;
use serde::Serialize;

const AXES: [&str; 3] = ["x", "y", "z"];

/// The release shock of one run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ReleaseShock {
    pub sample_rate_hz: f64,
    pub q: f64,
    pub fmin_hz: f64,
    pub fmax_hz: f64,
    pub per_octave: u32,
    /// Specification breakpoints [f_hz, g]; empty: no gate.
    pub spec_g: Vec<[f64; 2]>,
    pub tolerance: SpecTolerance,
    pub bodies: Vec<BodyShock>,
}

/// One body's shock: the largest over its three axes, and each axis.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BodyShock {
    /// `satellite K` or `carrier`.
    pub body: String,
    /// From the unlock command, s: the span of the uniform history.
    pub window_s: [f64; 2],
    pub peak_g: f64,
    pub peak_time_s: f64,
    pub peak_axis: &'static str,
    pub srs_max_g: f64,
    pub srs_max_hz: f64,
    pub srs_max_axis: &'static str,
    pub axes: Vec<AxisShock>,
    /// Against `spec_g`, when the scene gives one.
    pub spec: Option<BodySpecCheck>,
    /// The uniform history, g per axis (for the CSV).
    #[serde(skip)]
    pub samples: Vec<[f64; 3]>,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct AxisShock {
    pub axis: &'static str,
    pub peak_g: f64,
    pub peak_time_s: f64,
    pub srs_max_g: f64,
    pub srs_max_hz: f64,
    #[serde(skip)]
    pub srs: Vec<SrsPoint>,
}

/// The specification check of one body: per axis `signal::srs::check_against_spec`; the
/// body passes when no axis has more than `allowed_fraction` of its points above
/// spec + `upper_db`. Below the lower limit is reported, not failed: a release gentler
/// than the component was qualified for is the aim. `governing` is the point that decides
/// the pass: on the worst axis, the highest excursion once the allowed share of points is
/// set aside.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BodySpecCheck {
    pub pass: bool,
    pub fraction_above_upper: f64,
    pub fraction_below_lower: f64,
    /// `None` when no natural frequency of the spectrum lies within the specification's
    /// range (then nothing was shown to meet it, and the check fails).
    pub governing: Option<GoverningPoint>,
}

#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct GoverningPoint {
    pub axis: &'static str,
    pub frequency_hz: f64,
    pub measured_g: f64,
    /// spec × 10^(upper_db/20), g.
    pub limit_g: f64,
    pub excursion_db: f64,
}

/// The release shock of `result` (run with `record_acceleration`) under `spec`'s options.
pub fn release_shock(
    model: &Model,
    result: &SeparationResult,
    spec: &ShockSpec,
) -> Result<ReleaseShock, SignalError> {
    let acc = result
        .acceleration
        .as_ref()
        .ok_or_else(|| SignalError::Invalid("the run did not record its accelerations".into()))?;
    let fs = spec.sample_rate_hz();
    let freqs = natural_frequencies(spec.fmin_hz, spec.fmax_hz, spec.per_octave);
    let tol = SpecTolerance {
        upper_db: spec.upper_db,
        lower_db: spec.lower_db,
        allowed_fraction: spec.allowed_fraction,
    };
    let points: Vec<(f64, f64)> = spec.spec_g.iter().map(|p| (p[0], p[1])).collect();
    let mut bodies = Vec::new();
    for (b, window) in windows(model, result) {
        let Some(window) = window else { continue };
        let name = if b == 0 {
            "carrier".to_string()
        } else {
            format!("satellite {b}")
        };
        let body = body_shock(
            name,
            &acc.times_s,
            &acc.bodies[b],
            window,
            fs,
            &freqs,
            spec.q,
        )?;
        bodies.push(with_spec_check(body, &points, tol));
    }
    Ok(ReleaseShock {
        sample_rate_hz: fs,
        q: spec.q,
        fmin_hz: spec.fmin_hz,
        fmax_hz: spec.fmax_hz,
        per_octave: spec.per_octave,
        spec_g: spec.spec_g.clone(),
        tolerance: tol,
        bodies,
    })
}

/// The span each body moves under forces, by body (0 = carrier): a released satellite from
/// its release to its exit (or the end of the run); the carrier, when free, from the first
/// release to the end. `None`: the body never moves.
fn windows(model: &Model, result: &SeparationResult) -> Vec<(usize, Option<[f64; 2]>)> {
    let end = result.end_time_s;
    let first = result
        .satellites
        .iter()
        .filter_map(|s| s.release_time_s)
        .filter(|&t| t <= end)
        .reduce(f64::min);
    let carrier = model.carrier.as_ref().and(first).map(|t| [t, end]);
    let mut out = vec![(0, carrier)];
    for s in &result.satellites {
        let w = s
            .release_time_s
            .filter(|&t| t <= end)
            .map(|t| [t, s.exit_time_s.map_or(end, |e| t + e)]);
        out.push((s.index, w));
    }
    out
}

fn body_shock(
    body: String,
    times: &[f64],
    values: &[[f64; 3]],
    window: [f64; 2],
    fs: f64,
    freqs: &[f64],
    q: f64,
) -> Result<BodyShock, SignalError> {
    let count = ((window[1] - window[0]) * fs).floor() as usize + 1;
    let samples: Vec<[f64; 3]> = resample(times, values, window[0], fs, count)
        .into_iter()
        .map(|a| a.map(|v| v / G))
        .collect();
    let mut axes = Vec::with_capacity(3);
    for (i, axis) in AXES.into_iter().enumerate() {
        let x: Vec<f64> = samples.iter().map(|s| s[i]).collect();
        let spectrum = srs(&x, fs, freqs, q)?;
        let (peak_g, peak_time_s) = recorded_peak(times, values, window, i);
        let top = spectrum.iter().fold(
            &spectrum[0],
            |m, p| if p.maximax > m.maximax { p } else { m },
        );
        axes.push(AxisShock {
            axis,
            peak_g,
            peak_time_s,
            srs_max_g: top.maximax,
            srs_max_hz: top.frequency_hz,
            srs: spectrum,
        });
    }
    let peak = largest(&axes, |a| a.peak_g);
    let top = largest(&axes, |a| a.srs_max_g);
    Ok(BodyShock {
        body,
        window_s: window,
        peak_g: peak.peak_g,
        peak_time_s: peak.peak_time_s,
        peak_axis: peak.axis,
        srs_max_g: top.srs_max_g,
        srs_max_hz: top.srs_max_hz,
        srs_max_axis: top.axis,
        axes,
        spec: None,
        samples,
    })
}

/// The axis with the largest `key` (the first on a tie).
fn largest(axes: &[AxisShock], key: impl Fn(&AxisShock) -> f64) -> &AxisShock {
    axes.iter()
        .fold(&axes[0], |m, a| if key(a) > key(m) { a } else { m })
}

/// Largest |a| on axis `i` over the recorded step ends within `window`, g, and its time.
fn recorded_peak(times: &[f64], values: &[[f64; 3]], window: [f64; 2], i: usize) -> (f64, f64) {
    times
        .iter()
        .zip(values)
        .filter(|(t, _)| **t >= window[0] && **t <= window[1])
        .fold((0.0, window[0]), |(m, tm), (t, v)| {
            let a = v[i].abs() / G;
            if a > m { (a, *t) } else { (m, tm) }
        })
}

fn with_spec_check(mut body: BodyShock, spec: &[(f64, f64)], tol: SpecTolerance) -> BodyShock {
    if spec.is_empty() {
        return body;
    }
    let checks: Vec<(&'static str, SpecCheck)> = body
        .axes
        .iter()
        .map(|a| (a.axis, check_against_spec(&a.srs, spec, tol)))
        .collect();
    let governing = checks
        .iter()
        .filter_map(|(axis, c)| governing_point(axis, c, tol))
        .fold(None::<GoverningPoint>, |m, g| match m {
            Some(m) if m.excursion_db >= g.excursion_db => Some(m),
            _ => Some(g),
        });
    body.spec = Some(BodySpecCheck {
        pass: governing.is_some()
            && checks
                .iter()
                .all(|(_, c)| c.fraction_above_upper <= tol.allowed_fraction),
        fraction_above_upper: checks
            .iter()
            .map(|(_, c)| c.fraction_above_upper)
            .fold(0.0, f64::max),
        fraction_below_lower: checks
            .iter()
            .map(|(_, c)| c.fraction_below_lower)
            .fold(0.0, f64::max),
        governing,
    });
    body
}

/// The point that decides an axis: with k = ⌊allowed_fraction · n⌋ points allowed above the
/// limit, the (k+1)-th highest excursion (it lies above the limit exactly when more than k
/// points do). `None` when the spectrum and the specification share no frequency.
fn governing_point(
    axis: &'static str,
    c: &SpecCheck,
    tol: SpecTolerance,
) -> Option<GoverningPoint> {
    let mut pts: Vec<_> = c.points.iter().collect();
    pts.sort_by(|a, b| b.excursion_db.total_cmp(&a.excursion_db));
    let k =
        ((tol.allowed_fraction * pts.len() as f64).floor() as usize).min(pts.len().checked_sub(1)?);
    let p = pts[k];
    Some(GoverningPoint {
        axis,
        frequency_hz: p.frequency_hz,
        measured_g: p.measured,
        limit_g: p.specified * 10f64.powf(tol.upper_db / 20.0),
        excursion_db: p.excursion_db,
    })
}
