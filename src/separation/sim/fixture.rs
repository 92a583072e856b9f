//! Small hand-built models for the unit tests of the simulator: every number is written out
//! here, so a test can derive its reference values by hand from them.

use super::super::bar::ModalBar;
use super::super::contact::{ContactModel, ContactParams};
use super::super::params::{Model, SatelliteParams, SpringParams};
use crate::spec::Material;
use crate::spec::separation::DispersionSpec;

/// Spring rate of every fixture spring, N/m.
pub const SPRING_K: f64 = 700.0;
/// Spring stroke and latched compression, m (the spring pushes over its whole stroke).
pub const SPRING_STROKE: f64 = 0.08;

/// Two 150 kg satellites (inertia 16, 22, 30 kg·m², CG offset (0.01, −0.02, 0.03) m) on a
/// fixed carrier, columns at (±0.5, ±0.4) m, pitch 0.5 m, base 0.2 m, rigid 1.5 m bars,
/// 1 mm clearance, four springs per interface, nothing released.
pub fn two_satellites() -> Model {
    let satellite = |bottom_z_m| SatelliteParams {
        mass_kg: 150.0,
        inertia_kg_m2: [16.0, 22.0, 30.0],
        cg_offset_m: [0.01, -0.02, 0.03],
        bottom_z_m,
        initial_velocity_m_s: [0.0; 3],
        initial_rate_rad_s: [0.0; 3],
    };
    let springs = (1..=2)
        .flat_map(|interface| {
            (0..4).map(move |column| SpringParams {
                interface,
                column,
                stiffness_n_m: SPRING_K,
                stroke_m: SPRING_STROKE,
                compression_m: SPRING_STROKE,
            })
        })
        .collect();
    Model {
        satellites: vec![satellite(0.7), satellite(0.2)],
        carrier: None,
        columns_xy: [[0.5, 0.4], [-0.5, 0.4], [-0.5, -0.4], [0.5, -0.4]],
        pitch_m: 0.5,
        bore_length_m: 0.5,
        bore_radius_m: 0.0105,
        clearance_m: 1e-3,
        bar_length_m: 1.5,
        base_height_m: 0.2,
        bars: None,
        contact: ContactParams {
            stiffness: 1e9,
            exponent: 1.5,
            restitution: 0.5,
            friction: 0.1,
            v0: 1e-4,
            v1: 1e-3,
            min_impact_speed: 1e-4,
            model: ContactModel::Point,
            line_stiffness: 1e10,
            line_points: 4,
        },
        springs,
        release_times_s: vec![None, None],
        unlock_time_s: 0.0,
        tolerance: 1e-9,
        max_step_s: 1e-2,
        max_time_s: 1.0,
        max_steps: 100_000,
        output_interval_s: 0.01,
        stall_speed_m_s: 0.01,
        track_clearance_to_m: 0.0,
        dispersion: DispersionSpec::default(),
    }
}

/// [`two_satellites`] on flexible steel bars of 20 mm diameter with `modes` bending modes.
pub fn two_satellites_on_flexible_bars(modes: usize) -> Model {
    let steel = Material {
        name: "steel".into(),
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
        density_kg_m3: 7850.0,
        yield_strength_pa: None,
        ultimate_strength_pa: None,
    };
    let mut m = two_satellites();
    m.bars = Some(ModalBar::new(1.5, 0.02, &steel, 20, modes, 0.01).expect("steel bar modes"));
    m
}
