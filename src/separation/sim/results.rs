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
    /// Keep the acceleration of every body at every accepted step (the release shock).
    pub record_acceleration: bool,
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
    /// Slowest axial speed while its bores were on the bars, after it first moved at twice
    /// the stall speed; `None` if it never did, m/s.
    pub min_engaged_speed_m_s: Option<f64>,
    /// Where and how it stalled on the bars, if it did.
    pub stall: Option<Stall>,
    /// It stalled on the bars, or was released and never left them.
    pub wedged: bool,
}

/// A satellite that stopped on the bars: when, where, and what held it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Stall {
    /// From its release, s.
    pub time_s: f64,
    /// Axial travel from its latched position, m.
    pub travel_m: f64,
    pub axial_speed_m_s: f64,
    /// The bore edges pressed against their bars at that moment, largest load first.
    pub loads: Vec<EdgeLoad>,
    /// Friction coefficient of the run.
    pub friction: f64,
}

impl SatelliteResult {
    /// Released, not stalled, and still sliding up the bars (faster than `stall_speed`) when
    /// the run ended: the run was too short to show its exit.
    pub fn cut_short(&self, stall_speed: f64) -> bool {
        self.release_time_s.is_some()
            && self.exit_time_s.is_none()
            && self.stall.is_none()
            && self.final_speed_m_s > stall_speed
    }
}

impl Stall {
    /// "stalled 4.21 s after its release, 0.412 m up the bars, held by friction (μ = 0.30) at
    /// column 1 bottom edge 12.3 N, column 3 top edge 11.0 N".
    pub fn describe(&self) -> String {
        let held = if self.loads.is_empty() {
            "with no bore edge pressed (it stopped between contacts)".to_string()
        } else {
            let edges: Vec<String> = self
                .loads
                .iter()
                .map(|l| {
                    format!(
                        "column {} {} edge {:.1} N",
                        l.column, l.edge, l.normal_force_n
                    )
                })
                .collect();
            format!(
                "held by friction (μ = {:.2}) at {}",
                self.friction,
                edges.join(", ")
            )
        };
        format!(
            "stalled {:.2} s after its release, {:.3} m up the bars, {held}",
            self.time_s, self.travel_m
        )
    }
}

/// The normal force of one bore edge on its bar.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct EdgeLoad {
    /// Column 1..4.
    pub column: usize,
    /// `bottom` or `top` edge of the bore.
    pub edge: &'static str,
    pub normal_force_n: f64,
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
    /// When (from the unlock command) their gap first reached `track_clearance_to_m`; `None`:
    /// not within the run, whose end then bounds the tracking, s.
    pub apart_time_s: Option<f64>,
    /// Their axial gap at the end of the run, m.
    pub final_gap_m: f64,
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

/// The translational acceleration of every body's CG (body 0 = carrier, body i = satellite
/// i), from the forces acting on it divided by its mass, at every accepted step end. At a
/// step end where a discrete change (a release, a contact onset or exit) switches a force,
/// two samples share the time: the value before the change, then the value after it.
#[derive(Debug, Clone, Default)]
pub struct AccelHistory {
    pub times_s: Vec<f64>,
    /// `bodies[body][sample]` = [ax, ay, az] in the carrier frame, m/s².
    pub bodies: Vec<Vec<[f64; 3]>>,
}

impl SeparationResult {
    /// The smallest clearance between consecutive satellites over the run, or 0 when a pair
    /// that was not yet `track_clearance_to_m` apart at the end is closing: in free flight it
    /// will touch. `None` with fewer than two released satellites.
    pub fn projected_min_clearance_m(&self) -> Option<f64> {
        let closing = self
            .pair_clearances
            .iter()
            .any(|p| p.apart_time_s.is_none() && p.closing_speed_m_s > 0.0);
        self.min_clearance_m
            .map(|c| if closing { c.min(0.0) } else { c })
    }
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
    /// Every tracked pair reached `track_clearance_to_m` before the run ended.
    pub clearance_tracked_to_distance: bool,
    #[serde(skip)]
    pub history: Option<History>,
    #[serde(skip)]
    pub acceleration: Option<AccelHistory>,
    /// The release shock (`separation::shock`), when asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shock: Option<crate::separation::shock::ReleaseShock>,
    /// What makes this run's numbers untrustworthy (an energy audit that does not close,
    /// satellites passing through each other), one sentence each.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// An energy residual above this fraction of the spring energy means the integration did not
/// conserve energy: the default tolerance keeps it below 1e-6 (docs/separation.md), and the
/// speeds move by more than a percent well before the audit reaches this.
pub const MAX_TRUSTED_RESIDUAL: f64 = 1e-3;

impl SeparationResult {
    /// The run's warnings, from its energy audit, its pair clearances and satellites the end
    /// of the run (`max_time_s`) caught still moving on the bars (faster than `stall_speed`).
    pub fn find_warnings(&self, stall_speed: f64, max_time_s: f64) -> Vec<String> {
        let mut w = Vec::new();
        for s in self.satellites.iter().filter(|s| s.cut_short(stall_speed)) {
            w.push(format!(
                "satellite {} is still moving up the bars at {:.3} m/s when the run ends at \
                 max_time_s = {max_time_s} s: its exit speed, tip-off rate and clearances are not \
                 known; raise `separation.max_time_s`",
                s.index, s.final_speed_m_s
            ));
        }
        let r = self.energy.max_relative_residual;
        if r > MAX_TRUSTED_RESIDUAL {
            w.push(format!(
                "the energy audit does not close: its residual reaches {r:.3e} of the spring energy \
                 (above {MAX_TRUSTED_RESIDUAL:e}; the default tolerance keeps it below 1e-6), so the \
                 speeds, rates and clearances are not converged; tighten `separation.tolerance`"
            ));
        }
        for p in self
            .pair_clearances
            .iter()
            .filter(|p| p.min_clearance_m < 0.0)
        {
            w.push(format!(
                "satellites {} and {} pass through each other (clearance {:.3} mm): contact \
                 between satellites is not modelled, so their motion after that is not physical; \
                 release them further apart in time (`separation.release_interval_s`)",
                p.upper,
                p.upper + 1,
                p.min_clearance_m * 1e3
            ));
        }
        w
    }
}
