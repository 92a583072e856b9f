//! The results of one run: per satellite (speeds, rates, exit), the energy audit, the axial
//! clearances between neighbours, the integrator's statistics and the sampled histories.

use super::super::contact::Transitions;
use super::super::integrator::Stats;
use serde::Serialize;

/// Options of one run beyond the model.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Sample the CSV histories every `model.output_interval_s`.
    pub record_history: bool,
}

/// Results of one satellite.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SatelliteResult {
    /// 1 = top satellite.
    pub index: usize,
    /// Absolute time of its electromagnet release (from the unlock command), s.
    pub release_time_s: Option<f64>,
    pub max_speed_m_s: f64,
    pub max_accel_m_s2: f64,
    /// Largest angular rate during the run, deg/s.
    pub peak_rate_deg_s: f64,
    /// Speed when the satellite leaves the bars (or at the end of the run), m/s.
    pub final_speed_m_s: f64,
    /// Angular rate magnitude at bar exit (the tip-off rate), deg/s.
    pub final_rate_deg_s: f64,
    pub final_velocity_m_s: [f64; 3],
    /// Body-axis rates at exit, deg/s.
    pub final_rate_body_deg_s: [f64; 3],
    /// Time from its release until its last bore edge passes the bar tip, s.
    pub exit_time_s: Option<f64>,
    /// Contact onsets on its bore edges.
    pub contacts: usize,
}

/// The energy audit: spring work = kinetic + bar + contact elastic + losses (+ residual).
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Default)]
pub struct EnergyAudit {
    pub spring_work_j: f64,
    pub kinetic_j: f64,
    pub bar_j: f64,
    pub contact_elastic_j: f64,
    pub contact_damping_loss_j: f64,
    pub friction_loss_j: f64,
    pub bar_damping_loss_j: f64,
    /// Elastic energy of contacts cut off when a bore edge leaves the bar tip while pressed.
    pub tip_cut_loss_j: f64,
    pub residual_j: f64,
    /// |residual| / total spring energy of the scene, at the end.
    pub relative_residual: f64,
    /// Largest |residual| / total spring energy over all accepted steps.
    pub max_relative_residual: f64,
}

/// Axial clearance between consecutive satellites k (above) and k + 1 after both are released.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct PairClearance {
    pub upper: usize,
    pub min_clearance_m: f64,
    /// Relative axial speed at the end of the run; positive = the lower one is catching up.
    pub closing_speed_m_s: f64,
}

/// Sampled histories for CSV output.
#[derive(Debug, Clone, Default)]
pub struct History {
    pub times_s: Vec<f64>,
    /// `satellites[i][sample]` = [x, y, z, vx, vy, vz, speed, wx, wy, wz (body, deg/s), rate deg/s].
    pub satellites: Vec<Vec<[f64; 11]>>,
    /// [spring work, kinetic, bar, contact elastic, losses, residual], J.
    pub energy: Vec<[f64; 6]>,
}

/// The results of one run.
#[derive(Debug, Clone, Serialize)]
pub struct SeparationResult {
    pub satellites: Vec<SatelliteResult>,
    pub energy: EnergyAudit,
    pub transitions: Transitions,
    pub stats: Stats,
    pub end_time_s: f64,
    pub pair_clearances: Vec<PairClearance>,
    /// Smallest of the pair clearances, m.
    pub min_clearance_m: Option<f64>,
    #[serde(skip)]
    pub history: Option<History>,
}
