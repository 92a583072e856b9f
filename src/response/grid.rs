//! Frequency grids: log-spaced points over the band plus a cluster of points across every
//! mode's half-power band (fn·(1 + x·ζ) for x evenly spaced in ±`halfwidth`), plus the
//! profile's breakpoints. Near a resonance the magnitude varies on the scale ζ·fn, which no
//! affordable log grid resolves; the cluster does, at a fixed cost per mode.
//!
//! Sine peaks: with a spacing h·ζ·fn the worst grid miss of an SDOF peak is
//! 1 − 1/√(1 + (h/2)²) ≈ h²/8; the default 81 points over ±4ζ (h = 0.1) bound it by 0.13 %.
//! Random: the integrand is near-Lorentzian across the band; with the fourth-order rule of
//! [`integrate`], 41 points over ±5ζ keep the Grms error far below 0.5 % (see the bench).

use crate::error::ResponseError;

/// How dense a grid is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSpec {
    /// Log-spaced points per decade over the whole band.
    pub per_decade: usize,
    /// Points across each mode's band.
    pub per_mode: usize,
    /// Half-width of each mode's band, in units of ζ·fn.
    pub halfwidth: f64,
    /// Beyond the band, tail points at x = halfwidth·ratioᵏ (x in units of ζ·fn) out to 30 %
    /// of fn; 0 = none. The Lorentzian tail beyond ±5ζ still holds ~13 % of a mode's mean
    /// square, and it is a power law in (f − fn), not in f, so a log grid resolves it poorly.
    pub tail_ratio: f64,
    /// Most points the grid may have (`[limits] grid_points`), checked on the estimate before
    /// any point is made.
    pub max_points: usize,
}

impl GridSpec {
    /// The sine default: peak error below 0.13 % by construction (see the module doc).
    pub const SINE: GridSpec = GridSpec {
        per_decade: 60,
        per_mode: 81,
        halfwidth: 4.0,
        tail_ratio: 0.0,
        max_points: MAX_GRID_POINTS,
    };
    /// The random default: Grms error 4e-4 % at Q = 15 and 7e-3 % at Q = 100 on the paper
    /// stack (reports/bench/response.md); without the tails, 0.6 % at Q = 100.
    pub const RANDOM: GridSpec = GridSpec {
        per_decade: 60,
        per_mode: 41,
        halfwidth: 5.0,
        tail_ratio: 1.25,
        max_points: MAX_GRID_POINTS,
    };
}

/// The default most frequency points of a response grid; a larger estimate comes from a
/// mutated band or damping, and is refused before anything is allocated.
pub const MAX_GRID_POINTS: usize = crate::spec::limits::GRID_POINTS;

/// Clustered grid over [lo, hi] for modes `(fn_hz, zeta)`; `extra` points (profile
/// breakpoints) are added when inside the band. The band and the damping are checked and the
/// grid's size estimated before any point is made.
pub fn clustered(
    lo: f64,
    hi: f64,
    modes: &[(f64, f64)],
    spec: GridSpec,
    extra: &[f64],
) -> Result<Vec<f64>, ResponseError> {
    check_band(lo, hi)?;
    let estimate = estimate_points(lo, hi, modes, spec).saturating_add(extra.len());
    if estimate > spec.max_points {
        return Err(ResponseError::Invalid(format!(
            "the frequency grid over {lo}..{hi} Hz would have about {estimate} points, above the limit of {}; narrow the band or check the damping (Q, zeta) of the modes; {}",
            spec.max_points,
            crate::spec::limits::raise_hint("grid_points")
        )));
    }
    Ok(build(lo, hi, modes, spec, extra))
}

/// A band the grid can be built on: finite, positive, increasing, not subnormal, and with a
/// finite ratio (the log grid is lo·(hi/lo)^t).
fn check_band(lo: f64, hi: f64) -> Result<(), ResponseError> {
    if !(lo.is_normal() && hi.is_normal() && lo > 0.0 && hi > lo && (hi / lo).is_finite()) {
        return Err(ResponseError::Invalid(format!(
            "the frequency band {lo}..{hi} Hz is not a finite, positive, increasing range"
        )));
    }
    Ok(())
}

/// Upper bound of the grid's size, computed in floating point so that no estimate overflows.
fn estimate_points(lo: f64, hi: f64, modes: &[(f64, f64)], spec: GridSpec) -> usize {
    let mut n = (hi / lo).log10() * spec.per_decade as f64 + 2.0;
    for &(fnat, z) in modes {
        if !(fnat.is_finite() && z.is_finite()) {
            return usize::MAX;
        }
        n += spec.per_mode as f64;
        if spec.tail_ratio > 1.0 && z > 0.0 {
            let steps = (0.3 / (spec.halfwidth * spec.tail_ratio * z)).ln() / spec.tail_ratio.ln();
            n += 2.0 * steps.max(0.0) + 2.0;
        } else if spec.tail_ratio > 1.0 {
            return usize::MAX;
        }
    }
    if n.is_finite() && n < usize::MAX as f64 {
        n as usize
    } else {
        usize::MAX
    }
}

fn build(lo: f64, hi: f64, modes: &[(f64, f64)], spec: GridSpec, extra: &[f64]) -> Vec<f64> {
    let mut f = log_spaced(lo, hi, spec.per_decade);
    for &(fnat, z) in modes {
        if spec.per_mode < 2 {
            break;
        }
        let a = fnat * (1.0 - spec.halfwidth * z);
        let b = fnat * (1.0 + spec.halfwidth * z);
        if b < lo || a > hi {
            continue;
        }
        for k in 0..spec.per_mode {
            let x = -spec.halfwidth + 2.0 * spec.halfwidth * k as f64 / (spec.per_mode - 1) as f64;
            let v = fnat * (1.0 + x * z);
            if v >= lo && v <= hi {
                f.push(v);
            }
        }
        if spec.tail_ratio > 1.0 {
            let mut x = spec.halfwidth * spec.tail_ratio;
            while x * z < 0.3 {
                for v in [fnat * (1.0 - x * z), fnat * (1.0 + x * z)] {
                    if v >= lo && v <= hi {
                        f.push(v);
                    }
                }
                x *= spec.tail_ratio;
            }
        }
    }
    f.extend(extra.iter().copied().filter(|&v| v >= lo && v <= hi));
    finish(f)
}

/// `per_decade` log-spaced points from lo to hi (both included).
pub fn log_spaced(lo: f64, hi: f64, per_decade: usize) -> Vec<f64> {
    let decades = (hi / lo).log10();
    let n = ((decades * per_decade as f64).ceil() as usize).max(1);
    let mut f: Vec<f64> = (0..=n)
        .map(|k| lo * (hi / lo).powf(k as f64 / n as f64))
        .collect();
    f[0] = lo;
    f[n] = hi;
    f
}

/// `n` (≥ 2) log-spaced points over [lo, hi]: the uniform grid of the benchmarks.
pub fn log_n(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64))
        .collect()
}

fn finish(mut f: Vec<f64>) -> Vec<f64> {
    f.sort_by(f64::total_cmp);
    f.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs());
    f
}

/// ∫y dx over the grid by piecewise cubics: on each interval, the cubic through the
/// interval's two points and their outer neighbours (the four nearest points at the ends),
/// integrated
/// exactly by 2-point Gauss–Legendre. Fourth order on a non-uniform grid: the trapezoid and
/// power-law rules are second order, and on a clustered grid (where spacings change, so the
/// errors at a peak's top and flanks no longer cancel) they left 0.04 % in the bench where
/// this rule leaves 1e-3 % (reports/bench/response.md).
pub fn integrate(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    if n < 2 {
        return 0.0;
    }
    if n == 2 {
        return 0.5 * (y[0] + y[1]) * (x[1] - x[0]);
    }
    let g = 0.5 / 3f64.sqrt();
    let mut sum = 0.0;
    for i in 0..n - 1 {
        // Four nodes lo..=lo+3 around the interval, shifted inwards at the ends.
        let lo = i.saturating_sub(1).min(n.saturating_sub(4));
        let hi = (lo + 3).min(n - 1);
        // Up to four nodes: lo..=hi.
        let nodes = &x[lo..=hi];
        let vals = &y[lo..=hi];
        let (a, b) = (x[i], x[i + 1]);
        let h = b - a;
        let mut s = 0.0;
        for t in [0.5 - g, 0.5 + g] {
            let xq = a + t * h;
            let mut p = 0.0;
            for (k, (&xk, &yk)) in nodes.iter().zip(vals).enumerate() {
                let mut l = 1.0;
                for (m, &xm) in nodes.iter().enumerate() {
                    if m != k {
                        l *= (xq - xm) / (xk - xm);
                    }
                }
                p += l * yk;
            }
            s += p;
        }
        sum += 0.5 * h * s;
    }
    sum
}

/// Golden-section search for the maximum of `g` on [a, b] (unimodal near a grid peak).
pub fn refine_max(mut a: f64, mut b: f64, g: &dyn Fn(f64) -> f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut gc, mut gd) = (g(c), g(d));
    for _ in 0..40 {
        if gc > gd {
            b = d;
            d = c;
            gd = gc;
            c = b - r * (b - a);
            gc = g(c);
        } else {
            a = c;
            c = d;
            gc = gd;
            d = a + r * (b - a);
            gd = g(d);
        }
        if (b - a) < 1e-10 * b {
            break;
        }
    }
    if gc > gd { (c, gc) } else { (d, gd) }
}
