//! The separation model's parameters: one plain struct, [`Model`], built from a validated
//! scene by [`Model::from_scene`]. Geometry (satellites, columns, bores, bars, masses) comes
//! from `[stack]`; springs, schedule, contact, tolerance and dispersions from `[separation]`;
//! bar modes from `bar_modes::cantilever_bar_modes` (via [`ModalBar`]). Tests and the Monte Carlo
//! driver edit the public fields of a built model directly.

use super::bar::ModalBar;
use super::contact::ContactParams;
use crate::error::Error;
use crate::spec::Scene;
use crate::spec::separation::{self as sepspec, DispersionSpec};
use serde::Serialize;

/// One satellite (index 0 = satellite 1, the top one).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SatelliteParams {
    pub mass_kg: f64,
    /// Principal moments about the CG, body axes = stack axes at rest, kg·m².
    pub inertia_kg_m2: [f64; 3],
    /// CG offset from the centre of the satellite's column segment, m.
    pub cg_offset_m: [f64; 3],
    /// z of the bottom of the column segment at rest (from the bar root), m.
    pub bottom_z_m: f64,
    /// Initial velocity of the CG and body rate (zero in a scene; set by tests), m/s, rad/s.
    pub initial_velocity_m_s: [f64; 3],
    pub initial_rate_rad_s: [f64; 3],
}

/// One separation spring.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpringParams {
    /// Interface k (1-based): below satellite k.
    pub interface: usize,
    /// Column 0..4.
    pub column: usize,
    pub stiffness_n_m: f64,
    pub stroke_m: f64,
    /// Compression when latched: free length − installed length, m.
    pub compression_m: f64,
}

impl SpringParams {
    /// Extension at which the spring stops pushing: its end stop or its free length.
    pub fn end_of_action_m(&self) -> f64 {
        self.stroke_m.min(self.compression_m)
    }

    /// Work the spring has done after extending by `ext` from its latched position.
    pub fn work(&self, ext: f64) -> f64 {
        let e = ext.min(self.end_of_action_m());
        0.5 * self.stiffness_n_m * (self.compression_m.powi(2) - (self.compression_m - e).powi(2))
    }

    /// Force at extension `ext`: k·(compression − ext) until the end of action, then zero.
    pub fn force(&self, ext: f64) -> f64 {
        if ext >= self.end_of_action_m() {
            0.0
        } else {
            self.stiffness_n_m * (self.compression_m - ext)
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CarrierParams {
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
}

#[derive(Debug, Clone)]
pub struct Model {
    pub satellites: Vec<SatelliteParams>,
    /// `None`: the carrier is fixed (ground).
    pub carrier: Option<CarrierParams>,
    /// Column (and bar) axes x, y, ordered (+,+), (−,+), (−,−), (+,−).
    pub columns_xy: [[f64; 2]; 4],
    /// Height of one satellite's columns = stack pitch, m.
    pub pitch_m: f64,
    /// Guided length of a column's bore (its two contact edges), centred on the column, m.
    pub bore_length_m: f64,
    pub bore_radius_m: f64,
    /// Radial clearance bore − bar, m.
    pub clearance_m: f64,
    pub bar_length_m: f64,
    pub base_height_m: f64,
    /// `None`: rigid bars.
    pub bars: Option<ModalBar>,

    pub contact: ContactParams,
    /// Four springs per interface, interface-major: index (k − 1)·4 + column.
    pub springs: Vec<SpringParams>,
    /// Release time of interface k at index k − 1 (absolute, from the unlock command), s.
    pub release_times_s: Vec<Option<f64>>,
    pub unlock_time_s: f64,
    pub tolerance: f64,
    pub max_step_s: f64,
    pub max_time_s: f64,
    pub max_steps: usize,
    pub output_interval_s: f64,
    /// Below this axial speed on the bars, after moving, a satellite has stalled, m/s.
    pub stall_speed_m_s: f64,
    /// The run tracks the clearance of consecutive satellites until they are this far apart, m.
    pub track_clearance_to_m: f64,
    pub dispersion: DispersionSpec,
}

impl Model {
    /// Builds the model from a scene with `[stack]` and `[separation]`; every bad value is
    /// reported with its file, line and key.
    pub fn from_scene(scene: &Scene) -> Result<Model, Error> {
        let loc = scene.locator();
        let f = &scene.file;
        let Some(sep) = &f.separation else {
            return Err(loc
                .err("separation", "the scene has no [separation] section")
                .into());
        };
        let Some(stack) = &f.stack else {
            return Err(loc
                .err("separation", "[separation] needs a [stack] section: the satellite and bar geometry come from it")
                .into());
        };
        sepspec::validate(sep, stack, &f.limits(), &loc)?;
        let n = stack.satellites;
        let bar_material = f
            .material
            .iter()
            .find(|m| m.name == stack.bar_material)
            .ok_or_else(|| {
                loc.err(
                    "stack.bar_material",
                    format!("material `{}` is not defined", stack.bar_material),
                )
            })?;
        let bars = match sep.bar_modes.modes() {
            Some(nm) => Some(ModalBar::new(
                stack.bar_length_m,
                stack.bar_diameter_m,
                bar_material,
                sep.bar_elements,
                nm,
                sep.bar_damping_ratio,
            )?),
            None => None,
        };
        // `satellite_mass_kg` excludes the four load-bearing columns (the FE model gives them
        // their own mass); the released rigid body carries both. Columns as thin rods at the
        // corners, about the footprint centre; the CG shift they cause is the mass-weighted
        // mean of the satellite's offset and the (centred) column pattern.
        let col_mat = f
            .material
            .iter()
            .find(|m| m.name == stack.column_material)
            .ok_or_else(|| {
                loc.err(
                    "stack.column_material",
                    format!("material `{}` is not defined", stack.column_material),
                )
            })?;
        let col_area = std::f64::consts::PI / 4.0
            * (stack.column_outer_diameter_m.powi(2) - stack.column_inner_diameter_m.powi(2));
        let m_col = col_mat.density_kg_m3 * col_area * stack.satellite_pitch_m;
        let m_total = stack.satellite_mass_kg + 4.0 * m_col;
        let mut inertia = stack.satellite_inertia_kg_m2;
        let rod = stack.satellite_pitch_m.powi(2) / 12.0;
        for [x, y] in stack.column_xy() {
            inertia[0] += m_col * (y * y + rod);
            inertia[1] += m_col * (x * x + rod);
            inertia[2] += m_col * (x * x + y * y);
        }
        let cg = stack
            .satellite_cg_offset_m
            .map(|c| c * stack.satellite_mass_kg / m_total);
        let satellites = (1..=n)
            .map(|i| SatelliteParams {
                mass_kg: m_total,
                inertia_kg_m2: inertia,
                cg_offset_m: cg,
                bottom_z_m: stack.satellite_bottom_z(i),
                initial_velocity_m_s: [0.0; 3],
                initial_rate_rad_s: [0.0; 3],
            })
            .collect();
        let sp = &sep.spring;
        let free = sp
            .free_length_m
            .unwrap_or(sp.installed_length_m + sp.stroke_m);
        let mut springs = Vec::with_capacity(4 * n);
        for k in 1..=n {
            let o = sep.interface.iter().find(|o| o.interface == k);
            for j in 0..4 {
                let err = o
                    .and_then(|o| o.stiffness_error)
                    .map(|e| e[j])
                    .unwrap_or(sp.stiffness_error[j]);
                let stroke = o
                    .and_then(|o| o.stroke_m)
                    .map(|s| s[j])
                    .unwrap_or(sp.stroke_m);
                let fl = o
                    .and_then(|o| o.free_length_m)
                    .map(|s| s[j])
                    .unwrap_or(free);
                springs.push(SpringParams {
                    interface: k,
                    column: j,
                    stiffness_n_m: sp.stiffness_n_m * (1.0 + err),
                    stroke_m: stroke,
                    compression_m: fl - sp.installed_length_m,
                });
            }
        }
        let times = sepspec::release_times(sep, n);
        let c = &sep.contact;
        Ok(Model {
            satellites,
            carrier: sep.carrier.as_ref().map(|c| CarrierParams {
                mass_kg: c.mass_kg,
                inertia_kg_m2: c.inertia_kg_m2,
            }),
            columns_xy: stack.column_xy(),
            pitch_m: stack.satellite_pitch_m,
            bore_length_m: c.bore_length_m.unwrap_or(stack.satellite_pitch_m),
            bore_radius_m: 0.5 * stack.column_inner_diameter_m.max(stack.bar_diameter_m),
            clearance_m: c.clearance_m.unwrap_or_else(|| stack.radial_clearance_m()),
            bar_length_m: stack.bar_length_m,
            base_height_m: stack.base_height_m,
            bars,
            contact: ContactParams {
                stiffness: c.stiffness_n_m1_5,
                exponent: c.exponent,
                restitution: c.restitution,
                friction: c.friction,
                v0: c.v0_m_s,
                v1: c.v1_m_s,
                min_impact_speed: c.min_impact_speed_m_s,
                model: c.model,
                line_stiffness: c.line_stiffness_n_m2,
                line_points: c.line_points,
            },
            springs,
            release_times_s: times[1..].to_vec(),
            unlock_time_s: sep.unlock_time_s,
            tolerance: sep.tolerance,
            max_step_s: sep.max_step_s,
            max_time_s: sep.max_time_s,
            max_steps: sep.max_steps,
            output_interval_s: sep.output_interval_s,
            stall_speed_m_s: sep.stall_speed_m_s,
            track_clearance_to_m: sep.track_clearance_to_m,
            dispersion: sep.dispersion.clone(),
        })
    }

    /// Total work all springs can do (their energy between latched and end of action), J:
    /// the normaliser of the energy audit.
    pub fn spring_energy_j(&self) -> f64 {
        self.springs.iter().map(|s| s.work(f64::INFINITY)).sum()
    }

    pub fn n_satellites(&self) -> usize {
        self.satellites.len()
    }
}
