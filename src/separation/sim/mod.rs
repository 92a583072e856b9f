//! One separation run: state layout, right-hand side, events, the step loop, and the results.
//!
//! Pipeline of [`run`] (stages in order, with the file that does each):
//! 1. lay out the state (`layout`): 13 entries per body (body 0 = carrier, body i =
//!    satellite i), then the bar modal coordinates and velocities (4 bars × x, y × modes), then
//!    three dissipation integrals (contact damping, friction, bar damping) for the energy audit;
//! 2. integrate with Dormand–Prince 5(4) between scheduled releases (`stepping`); at each
//!    release (`releases`) the springs of the released interfaces start acting and the freed
//!    satellites start moving, and the frames and edge kinematics of the bodies that stay
//!    latched are cached (`statics`; a body that is not free has a zero derivative, so the
//!    cache is exact). The right-hand side is `forces` (springs, bar modes, rigid bodies) and
//!    `contact_forces` (bore edges on bars), on the kinematics of `frames` and `edges`;
//! 3. after every accepted step, evaluate the event functions (`events`: penetration δ of every
//!    bore edge, height of every edge above the bar tip, extension of every active spring
//!    against its end of action); the earliest sign change is located on the dense output
//!    (`locate`), the step is re-taken exactly to it, the discrete state changes (`discrete`:
//!    impact speed latched, edge past the tip, …) and the FSAL stage is refreshed;
//! 4. update the contact states (eq. 38, `discrete`) and the per-satellite records
//!    (`records`); check the state is finite (else stop with the time and body);
//! 5. watch for satellites that stall on the bars (`wedging`); stop when every released
//!    satellite has left the bars or stalled and consecutive satellites are
//!    `track_clearance_to_m` apart (or at `max_time_s`), and assemble the results (`records`,
//!    types in `results`); the energy audit is `energy`.
//!
//! Inputs: a [`Model`] (from `params`). Geometry: z is the stack axis; a satellite's bore
//! edges are the bottom and top of its four columns (`points`); the bar centreline at height
//! z is the column axis plus the modal deflection u(z). The bore is treated as a circle normal
//! to z (tilts stay within clearance/pitch ≈ 1e-3 rad, a cosine error of 1e-6 of the
//! clearance).
//!
//! Energy consistency: every contact force is applied equal and opposite at one material point
//! and along the gradient of δ (including the bar-slope term), and every spring force pair at
//! the upper spring point, so the audit closes to the integration error.

mod contact_forces;
mod discrete;
mod edges;
mod energy;
mod events;
#[cfg(test)]
mod fixture;
mod forces;
mod frames;
mod layout;
mod line_contact;
mod locate;
mod points;
mod records;
mod releases;
mod results;
mod statics;
mod stepping;
mod stiffness_scale;
mod wedging;

pub use results::{
    AccelHistory, EdgeLoad, EnergyAudit, History, PairClearance, RunOptions, SatelliteResult,
    SeparationResult, Stall,
};

use super::bar::ModalBar;
use super::body::{BODY_STATES, V3};
use super::contact::{EdgeContact, Transitions};
use super::params::Model;
use crate::error::SeparationError;
use edges::EdgeRigid;
use forces::Scratch;
use frames::Frame;

/// Runs the release described by `model`.
pub fn run(model: &Model, opts: &RunOptions) -> Result<SeparationResult, SeparationError> {
    let mut sim = Sim::new(model);
    sim.run(opts)
}

/// The simulator: the model, the state layout, the discrete state (releases, springs, contact
/// states) and the caches of the bodies that do not move. Its methods are spread over the
/// files of this folder, one job each.
struct Sim<'a> {
    m: &'a Model,
    n: usize,
    nm: usize,
    bar_off: usize,
    en_off: usize,
    dim: usize,
    /// Body-frame edge points (relative to the CG) per satellite: [column][bottom, top].
    edge_body: Vec<[[V3; 2]; 4]>,
    /// Body-frame column ends per satellite: [column][bottom, top] (the axial gaps).
    column_ends: Vec<[[V3; 2]; 4]>,
    /// Per spring: the spring point on the upper body and on the lower body, each in its frame.
    spring_up: Vec<V3>,
    spring_low: Vec<V3>,
    free: Vec<bool>,
    released: Vec<bool>,
    /// Per spring: released and short of its end of action, so that it pushes. Switched at the
    /// located events of its extension (either way), so the right-hand side skips the springs
    /// that have done their work (most of them for most of a run) without computing their
    /// extension; a spring that comes back within its stroke switches on again at that event.
    spring_on: Vec<bool>,
    edges: Vec<EdgeContact>,
    /// The edges that carry a force, ascending (see `update_touching`). Only they do: every
    /// onset and exit is a located event that ends a step, so within a step the set is fixed,
    /// and a trial step that runs past an onset integrates the free motion, which is exact up
    /// to the onset that the dense output then locates.
    touching: Vec<usize>,
    transitions: Transitions,
    contacts: Vec<usize>,
    exit: Vec<Option<(f64, V3, V3)>>,
    /// Satellites that stalled on the bars (`wedging`).
    stalled: Vec<bool>,
    tip_cut_loss: f64,
    e_ref: f64,
    /// Frames of the bodies that do not move (latched satellites, fixed carrier), by body.
    static_frames: Vec<Option<Frame>>,
    /// Rigid-body kinematics of the edges of latched satellites, by edge.
    static_edges: Vec<Option<EdgeRigid>>,
    /// Lower spring points of springs whose lower body does not move, by spring (computed
    /// as `spring_ext` would from the same frame).
    static_spring_low: Vec<Option<V3>>,
    /// c²(1 − 1e-12): below it an edge certainly does not touch.
    clearance_sq_safe: f64,
    /// The carrier is fixed, at the origin, with the identity attitude (see `to_carrier`).
    carrier_at_rest: bool,
    scratch: std::cell::RefCell<Scratch>,
}

impl<'a> Sim<'a> {
    fn new(m: &'a Model) -> Sim<'a> {
        let n = m.n_satellites();
        let nm = m.bars.as_ref().map_or(0, ModalBar::n_modes);
        let bar_off = BODY_STATES * (n + 1);
        let en_off = bar_off + 16 * nm;
        let (spring_up, spring_low) = points::spring_points(m);
        Sim {
            m,
            n,
            nm,
            bar_off,
            en_off,
            dim: en_off + 3,
            edge_body: points::edge_points(m),
            column_ends: points::column_end_points(m),
            spring_up,
            spring_low,
            free: vec![false; n + 1],
            released: vec![false; n + 1],
            spring_on: vec![false; m.springs.len()],
            edges: vec![EdgeContact::default(); 8 * n],
            touching: Vec::new(),
            transitions: Transitions::default(),
            contacts: vec![0; n],
            exit: vec![None; n],
            stalled: vec![false; n],
            tip_cut_loss: 0.0,
            e_ref: m.spring_energy_j().max(1e-30),
            static_frames: vec![None; n + 1],
            static_edges: vec![None; 8 * n],
            static_spring_low: vec![None; m.springs.len()],
            clearance_sq_safe: m.clearance_m * m.clearance_m * (1.0 - 1e-12),
            carrier_at_rest: false,
            scratch: Default::default(),
        }
    }

    /// Satellite (1-based), column and end (0 = bottom, 1 = top) of edge `ei`: edges are
    /// numbered satellite-major, eight per satellite.
    #[inline(always)]
    fn edge_index(ei: usize) -> (usize, usize, usize) {
        (ei / 8 + 1, (ei % 8) / 2, ei % 2)
    }
}
