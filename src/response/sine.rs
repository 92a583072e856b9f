//! Sine-sweep response: amplitude against frequency of every output under the scene's sine
//! level (displacement segments a = (2πf)²·d, acceleration segments), their peaks, and the
//! lock-integrity margins from the peak loads. The grid is clustered around every mode in the
//! band ([`super::grid`]); response-point peaks are then refined by a golden-section search on
//! the modal transfer function itself.
//!
//! Combined amplitudes (the harmonic components of one sweep frequency have phases; the
//! resultants below ignore them, which bounds the true resultant from above):
//! shear = √(|Fx|² + |Fy|²), face moment = √(|Mx|² + |My|²), bar bending = √(|My|² + |Mz|²).

use super::grid::{self, GridSpec};
use super::margins;
use super::{Curves, Frf, Prepared, axis_name};
use crate::error::Error;
use crate::gates::Verdict;
use crate::spec::analysis::SineSpec;
use faer::c64;
use serde::Serialize;

#[derive(Debug, Clone)]
pub struct SineOptions {
    pub grid: GridSpec,
    /// Modes kept (all computed ones when `None`).
    pub modes: Option<usize>,
    pub residual: bool,
    /// Refine response-point and joint-load peaks between grid points.
    pub refine: bool,
}

impl Default for SineOptions {
    fn default() -> Self {
        SineOptions {
            grid: GridSpec::SINE,
            modes: None,
            residual: true,
            refine: true,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct PointPeak {
    pub name: String,
    pub node: i64,
    pub frequency_hz: f64,
    /// Absolute acceleration amplitude, g.
    pub acceleration_g: f64,
    /// Response over input at the peak.
    pub transmissibility: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct InterfaceSine {
    pub name: String,
    /// Peak amplitude of the axial (z) joint force, N: the load that unloads the preload.
    pub max_tension_n: f64,
    pub tension_frequency_hz: f64,
    /// Peak shear resultant, N.
    pub max_shear_n: f64,
    pub shear_frequency_hz: f64,
    /// Peak bending moment across the joint face, N·m.
    pub max_moment_n_m: f64,
    /// Nominal preload of the joint, N (stack joints).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preload_n: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct BarStationSine {
    pub name: String,
    pub bar: String,
    pub z_m: f64,
    pub max_axial_n: f64,
    pub max_bending_n_m: f64,
    /// Peak dynamic normal stress |N|/A + M_b/Z, Pa.
    pub max_stress_pa: f64,
    pub frequency_hz: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct SineAxis {
    pub axis: String,
    pub modes_used: usize,
    pub residual_vector: bool,
    pub frequency_points: usize,
    pub peaks: Vec<PointPeak>,
    pub interfaces: Vec<InterfaceSine>,
    pub bar_stations: Vec<BarStationSine>,
    pub margins: Vec<Verdict>,
    #[serde(skip)]
    pub curves: Curves,
}

/// Runs the sine analysis along `axis` (0, 1, 2).
pub fn run(
    prep: &Prepared,
    spec: &SineSpec,
    axis: usize,
    opts: &SineOptions,
) -> Result<SineAxis, Error> {
    let basis = prep.basis(axis, opts.modes, opts.residual)?;
    let frf = prep.modal_frf(&basis);
    let (lo, hi) = spec.band();
    let modes = basis.excited_modes();
    let breaks: Vec<f64> = spec
        .segment
        .iter()
        .flat_map(|s| [s.from_hz, s.to_hz])
        .collect();
    let f = grid::clustered(lo, hi, &modes, opts.grid, &breaks)?;
    let mut out = evaluate(prep, spec, axis, (&frf, opts.refine), &f)?;
    out.modes_used = basis.n_modes;
    out.residual_vector = basis.len() > basis.n_modes;
    if opts.refine {
        // Refine each point's peak on the transfer function itself.
        for (pi, p) in prep.outputs.points.iter().enumerate() {
            let row = p.rows[axis];
            let k = out.curves.series[pi]
                .1
                .iter()
                .enumerate()
                .fold(0, |b, (i, v)| {
                    if *v > out.curves.series[pi].1[b] {
                        i
                    } else {
                        b
                    }
                });
            let g = |x: f64| frf.eval_row(x, row).norm() * spec.level_g(x);
            let (fx, gx) = refined_peak(&f, k, out.peaks[pi].acceleration_g, &g);
            if gx > out.peaks[pi].acceleration_g {
                out.peaks[pi].frequency_hz = fx;
                out.peaks[pi].acceleration_g = gx;
                out.peaks[pi].transmissibility = gx / spec.level_g(fx);
            }
        }
    }
    Ok(out)
}

/// The peak of `g` at grid point k: the golden-section maximum between its grid neighbours
/// when that is higher than the grid value, else the grid point itself.
fn refined_peak(f: &[f64], k: usize, grid_max: f64, g: &dyn Fn(f64) -> f64) -> (f64, f64) {
    let a = f[k.saturating_sub(1)];
    let b = f[(k + 1).min(f.len() - 1)];
    let (fx, gx) = grid::refine_max(a, b, g);
    if gx > grid_max {
        (fx, gx)
    } else {
        (f[k], grid_max)
    }
}

/// Evaluates any FRF (modal or direct) on a given grid and reduces it to peaks and margins.
/// With `refine`, every joint-load peak (tension, shear, moment and the gapping load that
/// the margins read) is refined between its grid neighbours on the FRF itself, as the
/// response points' accelerations are: on the grid alone a peak between two points reads low
/// (unconservative) by up to the grid's miss.
pub fn evaluate(
    prep: &Prepared,
    spec: &SineSpec,
    axis: usize,
    (frf, refine): (&dyn Frf, bool),
    f: &[f64],
) -> Result<SineAxis, Error> {
    let h = super::frf::on_grid(frf, f);
    let input: Vec<f64> = f.iter().map(|&x| spec.level_g(x)).collect();
    let o = &prep.outputs;
    let case = format!("sine {}", axis_name(axis));
    let amp = |k: usize, row: usize| h[k][row].norm() * input[k];
    let argmax = |v: &[f64]| {
        v.iter()
            .enumerate()
            .fold((0, f64::MIN), |b, (i, &x)| if x > b.1 { (i, x) } else { b })
    };

    let mut curves = Curves {
        frequency_hz: f.to_vec(),
        input: input.clone(),
        ..Default::default()
    };
    let mut peaks = Vec::new();
    for p in &o.points {
        let v: Vec<f64> = (0..f.len()).map(|k| amp(k, p.rows[axis])).collect();
        let (k, a) = argmax(&v);
        peaks.push(PointPeak {
            name: p.name.clone(),
            node: p.node,
            frequency_hz: f[k],
            acceleration_g: a,
            transmissibility: if input[k] > 0.0 { a / input[k] } else { 0.0 },
        });
        curves.series.push((format!("{} [g]", p.name), v));
    }
    let mut ms = Vec::new();
    let mut interfaces = Vec::new();
    for i in &o.interfaces {
        let r = i.rows;
        let t: Vec<f64> = (0..f.len()).map(|k| amp(k, r[2])).collect();
        let s: Vec<f64> = (0..f.len())
            .map(|k| amp(k, r[0]).hypot(amp(k, r[1])))
            .collect();
        let m: Vec<f64> = (0..f.len())
            .map(|k| amp(k, r[3]).hypot(amp(k, r[4])))
            .collect();
        let factor = prep.face_moment_factor(i);
        let p: Vec<f64> = (0..f.len()).map(|k| t[k] + m[k] * factor).collect();
        let peak = |v: &[f64], load: &dyn Fn(&[c64]) -> f64| {
            let (k, grid_max) = argmax(v);
            if !refine {
                return (f[k], grid_max);
            }
            let at = |x: f64| {
                let mut h = Vec::new();
                frf.eval(x, &mut h);
                load(&h) * spec.level_g(x)
            };
            refined_peak(f, k, grid_max, &at)
        };
        let norm = |h: &[c64], row: usize| h[row].norm();
        let (ft, tmax) = peak(&t, &|h| norm(h, r[2]));
        let (fs, smax) = peak(&s, &|h| norm(h, r[0]).hypot(norm(h, r[1])));
        let (_, mmax) = peak(&m, &|h| norm(h, r[3]).hypot(norm(h, r[4])));
        let (_, pext) = peak(&p, &|h| {
            norm(h, r[2]) + norm(h, r[3]).hypot(norm(h, r[4])) * factor
        });
        ms.extend(margins::interface(i, pext, smax, &prep.margins, &case));
        interfaces.push(InterfaceSine {
            name: i.name.clone(),
            max_tension_n: tmax,
            tension_frequency_hz: ft,
            max_shear_n: smax,
            shear_frequency_hz: fs,
            max_moment_n_m: mmax,
            preload_n: i.preload_n,
        });
        let c = &mut curves.interfaces;
        c.push((format!("{} tension [N]", i.name), t));
        c.push((format!("{} shear [N]", i.name), s));
        c.push((format!("{} moment [N m]", i.name), m));
    }
    let mut stations = Vec::new();
    let mut bar_ms = Vec::new();
    for st in &o.stations {
        let r = st.rows;
        let mut best = (0usize, 0.0f64, 0.0f64, 0.0f64);
        let (mut vy, mut vu) = (0.0f64, 0.0f64);
        let mut bend_curve = Vec::with_capacity(f.len());
        let mut stress_curve = Vec::with_capacity(f.len());
        for k in 0..f.len() {
            let n = amp(k, r[0]);
            let t = amp(k, r[1]);
            let mb = amp(k, r[2]).hypot(amp(k, r[3]));
            let sigma = n / st.area_m2 + mb / st.section_modulus_m3;
            bend_curve.push(mb);
            stress_curve.push(sigma);
            if sigma > best.3 {
                best = (k, n, mb, sigma);
            }
            vy = vy.max(margins::bar_von_mises(
                st,
                &prep.margins,
                prep.margins.yield_factor,
                n,
                mb,
                t,
            ));
            vu = vu.max(margins::bar_von_mises(
                st,
                &prep.margins,
                prep.margins.ultimate_factor,
                n,
                mb,
                t,
            ));
        }
        let max_axial = (0..f.len()).map(|k| amp(k, r[0])).fold(0.0, f64::max);
        let max_bend = (0..f.len())
            .map(|k| amp(k, r[2]).hypot(amp(k, r[3])))
            .fold(0.0, f64::max);
        stations.push(BarStationSine {
            name: st.name.clone(),
            bar: st.bar.clone(),
            z_m: st.position_m[2],
            max_axial_n: max_axial,
            max_bending_n_m: max_bend,
            max_stress_pa: best.3,
            frequency_hz: f[best.0],
        });
        bar_ms.extend(margins::bar(st, &prep.margins, vy, vu, &case));
        curves
            .bars
            .push((format!("{} bending [N m]", st.name), bend_curve));
        curves
            .bars
            .push((format!("{} stress [Pa]", st.name), stress_curve));
    }
    ms.extend(margins::worst_per_item(bar_ms));
    Ok(SineAxis {
        axis: axis_name(axis).into(),
        modes_used: 0,
        residual_vector: false,
        frequency_points: f.len(),
        peaks,
        interfaces,
        bar_stations: stations,
        margins: ms,
        curves,
    })
}
