//! Tolerance check of a measured SRS against a shock specification given as breakpoints
//! `[f_hz, level]` (interpolated log-log, as in NASA-STD-7003A and MIL-STD-810H Method 516):
//! per natural frequency within the specification's range, the excursion
//! 20·log10(measured/specified) in dB (an SRS is an amplitude), and the fractions of points above
//! the upper and below the lower limit. Both standards allow a tolerance band around the
//! specification and, in some cases, a share of points outside it: both are parameters here.

use super::SrsPoint;
use crate::units::loglog_interp;
use serde::Serialize;

/// Limits around the specification, dB, and the share of points allowed outside each.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpecTolerance {
    pub upper_db: f64,
    pub lower_db: f64,
    pub allowed_fraction: f64,
}

impl Default for SpecTolerance {
    fn default() -> Self {
        SpecTolerance {
            upper_db: 6.0,
            lower_db: 6.0,
            allowed_fraction: 0.0,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpecPoint {
    pub frequency_hz: f64,
    pub measured: f64,
    pub specified: f64,
    pub excursion_db: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpecCheck {
    pub tolerance: SpecTolerance,
    pub points: Vec<SpecPoint>,
    pub fraction_above_upper: f64,
    pub fraction_below_lower: f64,
    /// The excursion of largest magnitude and where it is.
    pub worst_db: f64,
    pub worst_hz: f64,
    pub pass: bool,
}

/// Checks the maximax spectrum `srs` against `spec` (validated breakpoints, e.g. from
/// [`crate::signal::read_profile`]). Points outside the specification's frequency range are
/// not checked; with none inside, the check fails (nothing was shown to meet it).
pub fn check_against_spec(srs: &[SrsPoint], spec: &[(f64, f64)], tol: SpecTolerance) -> SpecCheck {
    let (lo, hi) = match (spec.first(), spec.last()) {
        (Some(a), Some(b)) => (a.0, b.0),
        _ => (f64::INFINITY, f64::NEG_INFINITY),
    };
    let points: Vec<SpecPoint> = srs
        .iter()
        .filter(|p| p.frequency_hz >= lo && p.frequency_hz <= hi)
        .map(|p| spec_point(p, spec))
        .collect();
    let n = points.len().max(1) as f64;
    let above = points
        .iter()
        .filter(|p| p.excursion_db > tol.upper_db)
        .count() as f64
        / n;
    let below = points
        .iter()
        .filter(|p| p.excursion_db < -tol.lower_db)
        .count() as f64
        / n;
    let worst = points
        .iter()
        .fold(None::<&SpecPoint>, |w, p| match w {
            Some(w) if w.excursion_db.abs() >= p.excursion_db.abs() => Some(w),
            _ => Some(p),
        })
        .copied();
    SpecCheck {
        tolerance: tol,
        fraction_above_upper: above,
        fraction_below_lower: below,
        worst_db: worst.map_or(0.0, |w| w.excursion_db),
        worst_hz: worst.map_or(0.0, |w| w.frequency_hz),
        pass: !points.is_empty() && above <= tol.allowed_fraction && below <= tol.allowed_fraction,
        points,
    }
}

fn spec_point(p: &SrsPoint, spec: &[(f64, f64)]) -> SpecPoint {
    let specified = loglog_interp(spec, p.frequency_hz);
    // A zero response against a positive level is -inf dB: report a finite floor instead
    // (JSON has no infinity), far below any tolerance.
    let excursion_db = if p.maximax > 0.0 && specified > 0.0 {
        20.0 * (p.maximax / specified).log10()
    } else {
        -400.0
    };
    SpecPoint {
        frequency_hz: p.frequency_hz,
        measured: p.maximax,
        specified,
        excursion_db,
    }
}
