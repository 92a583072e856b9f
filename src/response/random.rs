//! Random-vibration response: response PSD |H(f)|²·S_in(f) of every output (input
//! interpolated log-log between the profile points), its mean square by the piecewise
//! power-law rule on a grid clustered across every mode's half-power band, Grms and 3σ, and
//! Miles' equation per significant mode as a cross-check column.
//!
//! Resultants are exact in mean square: E[Fx² + Fy²] = σx² + σy², so the shear (and bending)
//! resultant rms is √(σx² + σy²). The axial-plus-bending combinations of the margins add the
//! rms values (an upper bound: it assumes the two are fully correlated).

use super::grid::{self, GridSpec};
use super::margins;
use super::{Curves, Frf, Prepared, axis_name};
use crate::error::Error;
use crate::gates::Verdict;
use crate::spec::analysis::RandomSpec;
use serde::Serialize;

#[derive(Debug, Clone)]
pub struct RandomOptions {
    pub grid: GridSpec,
    pub modes: Option<usize>,
    pub residual: bool,
}

impl Default for RandomOptions {
    fn default() -> Self {
        RandomOptions {
            grid: GridSpec::RANDOM,
            modes: None,
            residual: true,
        }
    }
}

/// Miles' equation for one mode at one point: |φΓ|·√(π/2·fn·Q·S(fn)).
#[derive(Debug, Clone, Serialize)]
pub struct MilesMode {
    pub mode: usize,
    pub frequency_hz: f64,
    pub grms: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct RandomPoint {
    pub name: String,
    pub node: i64,
    pub grms: f64,
    pub three_sigma_g: f64,
    pub peak_psd_hz: f64,
    pub peak_psd_g2_hz: f64,
    /// Root-sum-square of the Miles values of the significant modes.
    pub miles_grms: f64,
    pub miles: Vec<MilesMode>,
}

#[derive(Debug, Clone, Serialize)]
pub struct InterfaceRandom {
    pub name: String,
    pub tension_rms_n: f64,
    pub tension_3sigma_n: f64,
    pub shear_rms_n: f64,
    pub shear_3sigma_n: f64,
    pub moment_rms_n_m: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct BarStationRandom {
    pub name: String,
    pub bar: String,
    pub z_m: f64,
    pub axial_rms_n: f64,
    pub bending_rms_n_m: f64,
    /// 3·(σ_N + σ_M) rms normal stress, Pa.
    pub stress_3sigma_pa: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct RandomAxis {
    pub axis: String,
    pub input_grms: f64,
    pub modes_used: usize,
    pub residual_vector: bool,
    pub frequency_points: usize,
    pub responses: Vec<RandomPoint>,
    pub interfaces: Vec<InterfaceRandom>,
    pub bar_stations: Vec<BarStationRandom>,
    pub margins: Vec<Verdict>,
    #[serde(skip)]
    pub curves: Curves,
}

/// The frequency grid of a random analysis for a basis.
pub fn grid_for(
    spec: &RandomSpec,
    basis: &super::Basis,
    g: GridSpec,
) -> Result<Vec<f64>, crate::error::ResponseError> {
    let t = spec.table();
    let (lo, hi) = (t[0].0, t[t.len() - 1].0);
    let modes = basis.excited_modes();
    let breaks: Vec<f64> = t.iter().map(|p| p.0).collect();
    grid::clustered(lo, hi, &modes, g, &breaks)
}

/// Runs the random analysis along `axis`.
pub fn run(
    prep: &Prepared,
    spec: &RandomSpec,
    axis: usize,
    opts: &RandomOptions,
) -> Result<RandomAxis, Error> {
    let basis = prep.basis(axis, opts.modes, opts.residual)?;
    let frf = prep.modal_frf(&basis);
    let f = grid_for(spec, &basis, opts.grid)?;
    let mut out = evaluate(prep, spec, axis, &frf, &f)?;
    out.modes_used = basis.n_modes;
    out.residual_vector = basis.len() > basis.n_modes;
    // Miles per significant mode for each point.
    let t = spec.table();
    let nb = basis.len();
    for (pi, p) in prep.outputs.points.iter().enumerate() {
        let row = p.rows[axis];
        let mut c: Vec<MilesMode> = (0..basis.n_modes)
            .filter_map(|j| {
                let fnat = basis.frequency_hz(j);
                let s = crate::units::loglog_interp(&t, fnat);
                if s <= 0.0 {
                    return None;
                }
                let q = 0.5 / basis.zeta[j];
                let a = frf.coeffs[row * nb + j] * basis.gamma[j];
                Some(MilesMode {
                    mode: j + 1,
                    frequency_hz: fnat,
                    grms: a.abs() * (std::f64::consts::FRAC_PI_2 * fnat * q * s).sqrt(),
                })
            })
            .collect();
        let max = c.iter().map(|m| m.grms).fold(0.0, f64::max);
        // Significant: at least 10 % of the largest modal Miles value; the five largest.
        c.retain(|m| m.grms >= 0.1 * max && m.grms > 0.0);
        c.sort_by(|a, b| b.grms.total_cmp(&a.grms));
        c.truncate(5);
        c.sort_by_key(|m| m.mode);
        // Folded from +0.0: an empty f64 sum is -0.0, which would print as a negative RMS.
        out.responses[pi].miles_grms = c.iter().fold(0.0, |s, m| s + m.grms * m.grms).sqrt();
        out.responses[pi].miles = c;
    }
    Ok(out)
}

/// Evaluates any FRF on a given grid and reduces it to rms values and margins.
pub fn evaluate(
    prep: &Prepared,
    spec: &RandomSpec,
    axis: usize,
    frf: &dyn Frf,
    f: &[f64],
) -> Result<RandomAxis, Error> {
    let t = spec.table();
    let h = super::frf::on_grid(frf, f);
    let input: Vec<f64> = f
        .iter()
        .map(|&x| crate::units::loglog_interp(&t, x))
        .collect();
    let psd = |row: usize| -> Vec<f64> {
        (0..f.len())
            .map(|k| h[k][row].norm_sqr() * input[k])
            .collect()
    };
    let ms = |row: usize| grid::integrate(f, &psd(row));
    let o = &prep.outputs;
    let case = format!("random {}", axis_name(axis));
    let mut curves = Curves {
        frequency_hz: f.to_vec(),
        input: input.clone(),
        ..Default::default()
    };
    let mut responses = Vec::new();
    for p in &o.points {
        let v = psd(p.rows[axis]);
        let g = grid::integrate(f, &v).sqrt();
        let (k, pk) = v
            .iter()
            .enumerate()
            .fold((0, 0.0), |b, (i, &x)| if x > b.1 { (i, x) } else { b });
        responses.push(RandomPoint {
            name: p.name.clone(),
            node: p.node,
            grms: g,
            three_sigma_g: 3.0 * g,
            peak_psd_hz: f[k],
            peak_psd_g2_hz: pk,
            miles_grms: 0.0,
            miles: Vec::new(),
        });
        curves.series.push((format!("{} [g2/Hz]", p.name), v));
    }
    let mut margin_list = Vec::new();
    let mut interfaces = Vec::new();
    for i in &o.interfaces {
        let r = i.rows;
        let tz = ms(r[2]).sqrt();
        let sh = (ms(r[0]) + ms(r[1])).sqrt();
        let mo = (ms(r[3]) + ms(r[4])).sqrt();
        let c = &mut curves.interfaces;
        c.push((format!("{} tension [N2/Hz]", i.name), psd(r[2])));
        let (px, py) = (psd(r[0]), psd(r[1]));
        c.push((
            format!("{} shear [N2/Hz]", i.name),
            px.iter().zip(&py).map(|(a, b)| a + b).collect(),
        ));
        margin_list.extend(margins::interface(
            i,
            3.0 * (tz + mo * prep.face_moment_factor(i)),
            3.0 * sh,
            &prep.margins,
            &case,
        ));
        interfaces.push(InterfaceRandom {
            name: i.name.clone(),
            tension_rms_n: tz,
            tension_3sigma_n: 3.0 * tz,
            shear_rms_n: sh,
            shear_3sigma_n: 3.0 * sh,
            moment_rms_n_m: mo,
        });
    }
    let mut stations = Vec::new();
    let mut bar_ms = Vec::new();
    for st in &o.stations {
        let r = st.rows;
        let n = ms(r[0]).sqrt();
        let tq = ms(r[1]).sqrt();
        let mb = (ms(r[2]) + ms(r[3])).sqrt();
        let (py, pz) = (psd(r[2]), psd(r[3]));
        curves.bars.push((
            format!("{} bending [(N m)2/Hz]", st.name),
            py.iter().zip(&pz).map(|(a, b)| a + b).collect(),
        ));
        let s = prep.margins.clone();
        let vy = margins::bar_von_mises(st, &s, s.yield_factor, 3.0 * n, 3.0 * mb, 3.0 * tq);
        let vu = margins::bar_von_mises(st, &s, s.ultimate_factor, 3.0 * n, 3.0 * mb, 3.0 * tq);
        bar_ms.extend(margins::bar(st, &s, vy, vu, &case));
        stations.push(BarStationRandom {
            name: st.name.clone(),
            bar: st.bar.clone(),
            z_m: st.position_m[2],
            axial_rms_n: n,
            bending_rms_n_m: mb,
            stress_3sigma_pa: 3.0 * (n / st.area_m2 + mb / st.section_modulus_m3),
        });
    }
    margin_list.extend(margins::worst_per_item(bar_ms));
    Ok(RandomAxis {
        axis: axis_name(axis).into(),
        input_grms: crate::units::loglog_integral(&t).sqrt(),
        modes_used: 0,
        residual_vector: false,
        frequency_points: f.len(),
        responses,
        interfaces,
        bar_stations: stations,
        margins: margin_list,
        curves,
    })
}
