//! The parametric `[stack]` section: N flat satellites stacked on a carrier platform, four
//! corner load-bearing columns per satellite, four guide bars through the columns, and the
//! compression device's preload. The FE expansion lives in `fem::stack`; the separation
//! simulation reads the same geometry, so both describe one piece of hardware.
//!
//! Axes: z is the stacking (axial) axis, pointing from the carrier platform towards the
//! compression device; x and y are the lateral axes of the satellite footprint.
//! Satellite 1 is the top one (next to the compression device, released first); satellite N
//! sits on the carrier platform and travels the whole bar length when released.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StackSpec {
    /// Number of satellites.
    pub satellites: usize,
    /// Mass of one satellite without its four load-bearing columns (their mass comes from the
    /// column material and section), kg.
    pub satellite_mass_kg: f64,
    /// Principal moments of inertia about the satellite's CG, axes x, y, z, kg·m².
    pub satellite_inertia_kg_m2: [f64; 3],
    /// CG offset from the centre of the satellite's column segment (mid-height, footprint
    /// centre), m.
    #[serde(default)]
    pub satellite_cg_offset_m: [f64; 3],
    /// Axial pitch of the stack = height of one satellite's load-bearing columns, m.
    pub satellite_pitch_m: f64,
    /// Centre-to-centre distance of the corner columns along x and y, m.
    pub column_spacing_m: [f64; 2],
    pub column_outer_diameter_m: f64,
    pub column_inner_diameter_m: f64,
    /// Name of a `[[material]]`.
    pub column_material: String,
    /// Guide bar: solid circular section.
    pub bar_diameter_m: f64,
    /// From the fixed base on the carrier platform to the compression device, m.
    pub bar_length_m: f64,
    /// Name of a `[[material]]`.
    pub bar_material: String,
    /// Height of the lowest satellite's column bottom above the bar root (the carrier
    /// platform / adapter interface), m.
    #[serde(default)]
    pub base_height_m: f64,
    /// Total preload of the compression device, shared by the four bars, N.
    pub preload_total_n: f64,
    /// Stiffness of one preloaded column-to-column (or column-to-platform) joint.
    pub interface: InterfaceSpec,
    /// Beam elements per column segment.
    #[serde(default = "two")]
    pub column_elements: usize,
    /// Beam elements per satellite pitch along each guide bar.
    #[serde(default = "two")]
    pub bar_elements_per_satellite: usize,
}

fn two() -> usize {
    2
}

/// A preloaded joint as a spring: axial (z), shear (x, y) and rotational stiffness.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    pub axial_stiffness_n_m: f64,
    pub shear_stiffness_n_m: f64,
    /// About the lateral axes (x, y), N·m/rad.
    pub rotational_stiffness_n_m_rad: f64,
    /// About the column axis (z), N·m/rad.
    pub torsional_stiffness_n_m_rad: f64,
}

impl StackSpec {
    /// Positions (x, y) of the four columns, ordered (+,+), (−,+), (−,−), (+,−).
    pub fn column_xy(&self) -> [[f64; 2]; 4] {
        let (hx, hy) = (
            0.5 * self.column_spacing_m[0],
            0.5 * self.column_spacing_m[1],
        );
        [[hx, hy], [-hx, hy], [-hx, -hy], [hx, -hy]]
    }

    /// z of the bottom of satellite `i` (1 = top, N = bottom), measured from the bar root.
    pub fn satellite_bottom_z(&self, i: usize) -> f64 {
        self.base_height_m + (self.satellites - i) as f64 * self.satellite_pitch_m
    }

    /// Radial clearance between a column bore and a centred guide bar, m.
    pub fn radial_clearance_m(&self) -> f64 {
        0.5 * (self.column_inner_diameter_m - self.bar_diameter_m)
    }
}
