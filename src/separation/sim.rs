//! One separation run: state layout, right-hand side, events, the step loop, and the results.
//!
//! Pipeline of [`run`] (stages in order):
//! 1. lay out the state: 13 entries per body (body 0 = carrier, body i = satellite i), then
//!    the bar modal coordinates and velocities (4 bars × x, y × modes), then three dissipation
//!    integrals (contact damping, friction, bar damping) for the energy audit;
//! 2. integrate with Dormand–Prince 5(4) between scheduled releases; at each release the
//!    springs of the released interfaces start acting and the freed satellites start moving,
//!    and the frames and edge kinematics of the bodies that stay latched are cached (a body
//!    that is not free has a zero derivative, so the cache is exact);
//! 3. after every accepted step, evaluate the event functions (penetration δ of every bore
//!    edge, height of every edge above the bar tip, extension of every active spring against
//!    its end of action); the earliest sign change is located on the dense output, the step is
//!    re-taken exactly to it, the discrete state changes (impact speed latched, edge past the
//!    tip, …) and the FSAL stage is refreshed;
//! 4. update the contact states (eq. 38) and the per-satellite records; check the state is
//!    finite (else stop with the time and body);
//! 5. stop when every released satellite has left the bars (or at `max_time_s`).
//!
//! Inputs: a [`Model`] (from `params`). Geometry: z is the stack axis; a satellite's bore
//! edges are the bottom and top of its four columns; the bar centreline at height z is the
//! column axis plus the modal deflection u(z). The bore is treated as a circle normal to z (tilts
//! stay within clearance/pitch ≈ 1e-3 rad, a cosine error of 1e-6 of the clearance).
//!
//! Energy consistency: every contact force is applied equal and opposite at one material point
//! and along the gradient of δ (including the bar-slope term), and every spring force pair at
//! the upper spring point, so the audit closes to the integration error.

use super::bar::ModalBar;
use super::body::*;
use super::contact::{ContactState, EdgeContact, Transitions};
use super::integrator::{Dopri5, Stats, StepFailure};
use super::params::Model;
use crate::error::SeparationError;
use crate::spec::separation::MAX_BAR_MODES;
use serde::Serialize;

/// Events located within this time of the earliest one in a step are processed together, s.
/// At the 0.01 m/s impact speeds of the reference scene an edge moves 1e-10 m in that time.
const SIMULTANEOUS_S: f64 = 1e-8;

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

/// Runs the release described by `model`.
pub fn run(model: &Model, opts: &RunOptions) -> Result<SeparationResult, SeparationError> {
    let mut sim = Sim::new(model);
    sim.run(opts)
}

struct Sim<'a> {
    m: &'a Model,
    n: usize,
    nm: usize,
    bar_off: usize,
    en_off: usize,
    dim: usize,
    /// Body-frame edge points (relative to the CG) per satellite: [column][bottom, top].
    edge_body: Vec<[[V3; 2]; 4]>,
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

/// Geometry and kinematics of one bore edge against its bar.
struct EdgeKin {
    /// Penetration δ = |e| − c.
    delta: f64,
    delta_dot: f64,
    /// Unit normal (carrier frame, horizontal) from the bore centre towards the bar.
    n: [f64; 2],
    /// Height in the carrier frame.
    z: f64,
    p: V3,
    vp: V3,
    /// Bar deflection slope and velocity at the edge height, x and y.
    slope: [f64; 2],
    udot: [f64; 2],
    /// Mode shapes at the edge height (for the generalised force on the bar).
    phi: [f64; MAX_BAR_MODES],
}

impl EdgeKin {
    /// An edge known not to touch, at height z: δ is only known to be negative.
    fn apart(z: f64) -> EdgeKin {
        EdgeKin {
            delta: -f64::MIN_POSITIVE,
            delta_dot: 0.0,
            n: [0.0; 2],
            z,
            p: [0.0; 3],
            vp: [0.0; 3],
            slope: [0.0; 2],
            udot: [0.0; 2],
            phi: [0.0; MAX_BAR_MODES],
        }
    }
}

/// The rigid-body part of an edge's kinematics (positions and velocities of the edge point,
/// the mode shapes at its height). Constant while the satellite is latched to a fixed carrier:
/// then it is computed once, from the same state and by the same formulas as
/// [`Sim::edge_kin`] would use, so the cache changes no bit of the results.
#[derive(Clone, Copy)]
struct EdgeRigid {
    p: V3,
    pl: V3,
    vp: V3,
    vrel: V3,
    phi: [f64; MAX_BAR_MODES],
    dphi: [f64; MAX_BAR_MODES],
}

impl EdgeRigid {
    /// An edge at `p` (world) / `pl` (carrier frame), velocities and mode shapes still zero.
    fn at(p: V3, pl: V3) -> EdgeRigid {
        EdgeRigid {
            p,
            pl,
            vp: [0.0; 3],
            vrel: [0.0; 3],
            phi: [0.0; MAX_BAR_MODES],
            dphi: [0.0; MAX_BAR_MODES],
        }
    }
}

/// Buffers of the right-hand side, kept between calls so that it allocates nothing.
#[derive(Default)]
struct Scratch {
    frames: Vec<Frame>,
    force: Vec<V3>,
    torque: Vec<V3>,
    q_gen: Vec<f64>,
}

#[derive(Clone, Copy)]
struct Frame {
    x: V3,
    r: M3,
    v: V3,
    w: V3,
}

impl<'a> Sim<'a> {
    fn new(m: &'a Model) -> Sim<'a> {
        let n = m.n_satellites();
        let nm = m.bars.as_ref().map_or(0, ModalBar::n_modes);
        let bar_off = BODY_STATES * (n + 1);
        let en_off = bar_off + 16 * nm;
        let dim = en_off + 3;
        let hp = 0.5 * m.pitch_m;
        let edge_body = m
            .satellites
            .iter()
            .map(|s| {
                let c = s.cg_offset_m;
                let mut e = [[[0.0; 3]; 2]; 4];
                for (j, xy) in m.columns_xy.iter().enumerate() {
                    e[j][0] = [xy[0] - c[0], xy[1] - c[1], -hp - c[2]];
                    e[j][1] = [xy[0] - c[0], xy[1] - c[1], hp - c[2]];
                }
                e
            })
            .collect();
        let mut spring_up = Vec::new();
        let mut spring_low = Vec::new();
        for s in &m.springs {
            let xy = m.columns_xy[s.column];
            let cu = m.satellites[s.interface - 1].cg_offset_m;
            spring_up.push([xy[0] - cu[0], xy[1] - cu[1], -hp - cu[2]]);
            if s.interface < n {
                let cl = m.satellites[s.interface].cg_offset_m;
                spring_low.push([xy[0] - cl[0], xy[1] - cl[1], hp - cl[2]]);
            } else {
                // Carrier frame: origin at the bar root (= the carrier's CG).
                spring_low.push([xy[0], xy[1], m.base_height_m]);
            }
        }
        Sim {
            m,
            n,
            nm,
            bar_off,
            en_off,
            dim,
            edge_body,
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

    fn initial_state(&self) -> Vec<f64> {
        let mut y = vec![0.0; self.dim];
        y[3] = 1.0;
        for (i, s) in self.m.satellites.iter().enumerate() {
            let o = BODY_STATES * (i + 1);
            let c = s.cg_offset_m;
            y[o] = c[0];
            y[o + 1] = c[1];
            y[o + 2] = s.bottom_z_m + 0.5 * self.m.pitch_m + c[2];
            y[o + 3] = 1.0;
            y[o + 7..o + 10].copy_from_slice(&s.initial_velocity_m_s);
            y[o + 10..o + 13].copy_from_slice(&s.initial_rate_rad_s);
        }
        y
    }

    /// Absolute tolerances: the relative tolerance times a physical scale per state kind
    /// (position 1 m, attitude 1, velocity 0.1 m/s, rate 0.01 rad/s, bar deflection 1 mm and
    /// deflection rate 1 mm/s in modal units, energies the scene's spring energy).
    fn atol(&self, tol: f64) -> Vec<f64> {
        let mut a = vec![0.0; self.dim];
        for b in 0..=self.n {
            let o = BODY_STATES * b;
            a[o..o + 3].fill(tol);
            a[o + 3..o + 7].fill(tol);
            a[o + 7..o + 10].fill(tol * 0.1);
            a[o + 10..o + 13].fill(tol * 0.01);
        }
        if let Some(bar) = &self.m.bars {
            let modal_mass_scale = bar.shapes[0].eval(bar.length_m).0.abs().recip().max(1e-12);
            a[self.bar_off..self.en_off].fill(tol * 1e-3 * modal_mass_scale);
        }
        a[self.en_off..].fill(tol * self.e_ref);
        a
    }

    #[inline]
    fn frame(&self, y: &[f64], b: usize) -> Frame {
        if let Some(f) = self.static_frames[b] {
            return f;
        }
        self.frame_of(y, b)
    }

    #[inline]
    fn frame_of(&self, y: &[f64], b: usize) -> Frame {
        let o = BODY_STATES * b;
        let r = rotation(&y[o + 3..o + 7]);
        let wb = [y[o + 10], y[o + 11], y[o + 12]];
        Frame {
            x: [y[o], y[o + 1], y[o + 2]],
            v: [y[o + 7], y[o + 8], y[o + 9]],
            w: mul(&r, wb),
            r,
        }
    }

    #[inline]
    fn qidx(&self, bar: usize, dir: usize, mode: usize) -> usize {
        self.bar_off + (bar * 2 + dir) * self.nm + mode
    }

    /// Penetration and kinematics of edge (sat i 1-based, column j, end k) against bar j.
    /// With `touching_only`, an edge that does not touch returns a negative δ (not necessarily
    /// the exact one) and no kinematics: the right-hand side and the energy audit need nothing
    /// else from it. A
    /// latched satellite's edge takes its rigid part from the cache.
    // Eight arguments: the two frames are computed once per right-hand side and shared by
    // all edges; bundling them into a struct would only move the count.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn edge_kin(
        &self,
        y: &[f64],
        c0: &Frame,
        s: &Frame,
        i: usize,
        j: usize,
        k: usize,
        touching_only: bool,
    ) -> EdgeKin {
        if let Some(r) = &self.static_edges[(i - 1) * 8 + j * 2 + k] {
            return self.edge_bar(y, j, r, touching_only);
        }
        let (rb, p, pl) = self.edge_point(c0, s, i, j, k);
        let mut r = EdgeRigid::at(p, pl);
        if let Some(bar) = &self.m.bars {
            bar.eval_phi(pl[2], &mut r.phi);
        }
        if touching_only {
            if !self.may_touch(y, j, &r) {
                return EdgeKin::apart(pl[2]);
            }
            let ek = self.edge_bar(y, j, &r, true);
            if ek.delta <= 0.0 {
                return ek;
            }
        }
        // Slopes and velocities enter δ̇ only: finish the edge with them.
        if let Some(bar) = &self.m.bars {
            bar.eval_dphi(pl[2], &mut r.dphi);
        }
        self.edge_velocity(c0, s, rb, &mut r);
        self.edge_bar(y, j, &r, false)
    }

    /// (δ, δ̇, height) of edge `ei`, exactly, as [`Self::edge_kin`] without `touching_only`
    /// gives them (same formulas, same order), without its intermediate results.
    #[inline]
    fn edge_event(&self, y: &[f64], c0: &Frame, s: &Frame, ei: usize) -> (f64, f64, f64) {
        let (i, j, k) = (ei / 8 + 1, (ei % 8) / 2, ei % 2);
        let built;
        let r = match &self.static_edges[ei] {
            Some(r) => r,
            None => {
                let (rb, p, pl) = self.edge_point(c0, s, i, j, k);
                built = self.edge_rigid(c0, s, rb, p, pl);
                &built
            }
        };
        let ek = self.edge_bar(y, j, r, false);
        (ek.delta, ek.delta_dot, ek.z)
    }

    /// Edge k of column j of satellite i (frame `s`): its offset from the satellite's origin
    /// (world axes), its world point and that point in the carrier frame.
    #[inline(always)]
    fn edge_point(&self, c0: &Frame, s: &Frame, i: usize, j: usize, k: usize) -> (V3, V3, V3) {
        let rb = mul(&s.r, self.edge_body[i - 1][j][k]);
        let p = add(s.x, rb);
        (rb, p, self.to_carrier(c0, p))
    }

    /// The rigid-body part of an edge's kinematics, from its offset `rb` (world axes), point
    /// `p` and point in the carrier frame `pl`.
    fn edge_rigid(&self, c0: &Frame, s: &Frame, rb: V3, p: V3, pl: V3) -> EdgeRigid {
        let mut r = EdgeRigid::at(p, pl);
        self.edge_velocity(c0, s, rb, &mut r);
        if let Some(bar) = &self.m.bars {
            bar.eval_all(pl[2], &mut r.phi, &mut r.dphi);
        }
        r
    }

    /// Velocity of the edge point, world and relative to the carrier in its frame.
    #[inline]
    fn edge_velocity(&self, c0: &Frame, s: &Frame, rb: V3, r: &mut EdgeRigid) {
        r.vp = add(s.v, cross(s.w, rb));
        r.vrel = if self.carrier_at_rest {
            r.vp
        } else {
            mul_t(&c0.r, sub(sub(r.vp, c0.v), cross(c0.w, sub(r.p, c0.x))))
        };
    }

    /// A world point in the carrier frame. A fixed carrier at the origin with the identity
    /// attitude (the usual case) maps every finite point onto itself exactly, so the transform
    /// is skipped: it runs for every moving edge in every right-hand side.
    #[inline(always)]
    fn to_carrier(&self, c0: &Frame, p: V3) -> V3 {
        if self.carrier_at_rest {
            p
        } else {
            mul_t(&c0.r, sub(p, c0.x))
        }
    }

    /// False when the edge certainly does not touch (δ < 0), decided without the square root
    /// (whose latency dominates the test): |e|² below c²(1 − 1e-12) means |e| < c even after
    /// the rounding of both sides.
    #[inline(always)]
    fn may_touch(&self, y: &[f64], j: usize, r: &EdgeRigid) -> bool {
        let e = self.edge_offset(y, j, r);
        e[0] * e[0] + e[1] * e[1] >= self.clearance_sq_safe
    }

    /// Offset from the edge point to the deflected centreline of bar `j`, carrier x and y.
    #[inline(always)]
    fn edge_offset(&self, y: &[f64], j: usize, r: &EdgeRigid) -> [f64; 2] {
        let (pl, phi) = (r.pl, &r.phi);
        let col = self.m.columns_xy[j];
        let mut u = [0.0; 2];
        if self.m.bars.is_some() {
            let q = &y[self.qidx(j, 0, 0)..self.qidx(j, 2, 0)];
            let (qx, qy) = q.split_at(self.nm);
            // Zipped: no bounds check per mode (this runs for every edge in every call).
            for ((p, a), b) in phi.iter().zip(qx).zip(qy) {
                u[0] += p * a;
                u[1] += p * b;
            }
        }
        [col[0] + u[0] - pl[0], col[1] + u[1] - pl[1]]
    }

    /// δ of an edge against the deflected bar `j`, with the offset bar − edge and its length.
    #[inline(always)]
    fn edge_delta(&self, y: &[f64], j: usize, r: &EdgeRigid) -> (f64, [f64; 2], f64) {
        let e = self.edge_offset(y, j, r);
        let rr = (e[0] * e[0] + e[1] * e[1]).sqrt();
        (rr - self.m.clearance_m, e, rr)
    }

    /// Penetration and kinematics of an edge against the deflected bar `j`; with
    /// `touching_only` and δ ≤ 0, only δ.
    #[inline]
    fn edge_bar(&self, y: &[f64], j: usize, r: &EdgeRigid, touching_only: bool) -> EdgeKin {
        let (pl, vrel) = (r.pl, r.vrel);
        let nv = self.nm;
        let (delta, e, rr) = self.edge_delta(y, j, r);
        let mut ek = EdgeKin {
            delta,
            delta_dot: 0.0,
            n: [0.0; 2],
            z: pl[2],
            p: r.p,
            vp: r.vp,
            slope: [0.0; 2],
            udot: [0.0; 2],
            phi: r.phi,
        };
        if touching_only && delta <= 0.0 {
            return ek;
        }
        if self.m.bars.is_some() {
            for mo in 0..nv {
                for d in 0..2 {
                    let qi = self.qidx(j, d, mo);
                    ek.slope[d] += r.dphi[mo] * y[qi];
                    ek.udot[d] += r.phi[mo] * y[qi + 8 * nv];
                }
            }
        }
        let (slope, udot) = (ek.slope, ek.udot);
        let n = if rr > 1e-300 {
            [e[0] / rr, e[1] / rr]
        } else {
            [0.0, 0.0]
        };
        ek.n = n;
        ek.delta_dot = n[0] * (udot[0] + slope[0] * vrel[2] - vrel[0])
            + n[1] * (udot[1] + slope[1] * vrel[2] - vrel[1]);
        ek
    }

    /// Rebuilds the caches of the bodies that do not move, after a change of `free`. A body
    /// that is not free has a zero derivative, so its state stays bit-for-bit what it is now.
    fn rebuild_static(&mut self, y: &[f64]) {
        self.scratch.get_mut().frames.clear();
        self.carrier_at_rest = false;
        for b in 0..=self.n {
            self.static_frames[b] = None;
        }
        for e in self.static_edges.iter_mut() {
            *e = None;
        }
        self.static_spring_low.fill(None);
        if self.free[0] {
            return;
        }
        let mut frames = vec![None; self.n + 1];
        for (b, f) in frames.iter_mut().enumerate() {
            if !self.free[b] {
                *f = Some(self.frame_of(y, b));
            }
        }
        let c0 = frames[0].expect("the carrier is fixed");
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        self.carrier_at_rest =
            c0.r == identity && c0.x == [0.0; 3] && c0.v == [0.0; 3] && c0.w == [0.0; 3];
        for i in 1..=self.n {
            let Some(s) = frames[i] else { continue };
            for j in 0..4 {
                for k in 0..2 {
                    let (rb, p, pl) = self.edge_point(&c0, &s, i, j, k);
                    self.static_edges[(i - 1) * 8 + j * 2 + k] =
                        Some(self.edge_rigid(&c0, &s, rb, p, pl));
                }
            }
        }
        for (si, s) in self.m.springs.iter().enumerate() {
            if let Some(low) = frames[self.lower_body(s.interface)] {
                self.static_spring_low[si] = Some(add(low.x, mul(&low.r, self.spring_low[si])));
            }
        }
        self.static_frames = frames;
    }

    fn lower_body(&self, interface: usize) -> usize {
        if interface < self.n { interface + 1 } else { 0 }
    }

    /// Extension of spring `si` from its latched position.
    #[inline]
    fn spring_ext(&self, frames: &[Frame], si: usize) -> (f64, V3, V3) {
        let s = &self.m.springs[si];
        let up = &frames[s.interface];
        let low = &frames[self.lower_body(s.interface)];
        let pu = add(up.x, mul(&up.r, self.spring_up[si]));
        let pl = self.static_spring_low[si]
            .unwrap_or_else(|| add(low.x, mul(&low.r, self.spring_low[si])));
        let zl = [low.r[0][2], low.r[1][2], low.r[2][2]];
        (dot(sub(pu, pl), zl), pu, zl)
    }

    fn rhs(&self, y: &[f64], dy: &mut [f64]) {
        dy.fill(0.0);
        let nb = self.n + 1;
        let mut sc = self.scratch.borrow_mut();
        let Scratch {
            frames,
            force,
            torque,
            q_gen,
        } = &mut *sc;
        force.clear();
        force.resize(nb, [0.0; 3]);
        torque.clear();
        torque.resize(nb, [0.0; 3]);
        // The frames of bodies that do not move stay from call to call (`rebuild_static`
        // empties the buffer when the set changes).
        if frames.len() != nb {
            frames.clear();
            frames.extend((0..nb).map(|b| self.frame(y, b)));
        } else {
            for (b, f) in frames.iter_mut().enumerate() {
                if self.static_frames[b].is_none() {
                    *f = self.frame_of(y, b);
                }
            }
        }
        let frames = &*frames;
        let apply = |b: usize, f: V3, at: V3, force: &mut Vec<V3>, torque: &mut Vec<V3>| {
            force[b] = add(force[b], f);
            torque[b] = add(torque[b], cross(sub(at, frames[b].x), f));
        };
        // Springs that push (released, short of their end of action): +F on the upper body,
        // −F on the lower one, both at the upper spring point, along the lower body's axis.
        for (si, s) in self.m.springs.iter().enumerate() {
            if !self.spring_on[si] {
                continue;
            }
            let (ext, pu, zl) = self.spring_ext(frames, si);
            let f = s.force(ext);
            if f != 0.0 {
                let fv = scale(zl, f);
                apply(s.interface, fv, pu, force, torque);
                apply(
                    self.lower_body(s.interface),
                    scale(fv, -1.0),
                    pu,
                    force,
                    torque,
                );
            }
        }
        // Contacts.
        let c = &self.m.contact;
        q_gen.clear();
        q_gen.resize(8 * self.nm, 0.0);
        let (mut p_contact, mut p_fric) = (0.0, 0.0);
        let c0 = &frames[0];
        let len = self.m.bar_length_m;
        for &ei in &self.touching {
            let (i, j, k) = (ei / 8 + 1, (ei % 8) / 2, ei % 2);
            let s = &frames[i];
            let ec = &self.edges[ei];
            // Full kinematics at once: a listed edge almost always touches, so a δ-only
            // pre-screen would only compute δ twice more.
            let ek = self.edge_kin(y, c0, s, i, j, k, false);
            if ek.delta <= 0.0 || ek.z < 0.0 || ek.z > len {
                continue;
            }
            let v_imp = ec.impact_speed.unwrap_or(c.min_impact_speed);
            let (fnrm, fel) = c.normal_and_elastic(ek.delta, ek.delta_dot, v_imp);
            p_contact += (fnrm - fel) * ek.delta_dot;
            let n = ek.n;
            // −F·∇δ: lateral along n, axial from the bar slope.
            let f_loc = [
                fnrm * n[0],
                fnrm * n[1],
                -fnrm * (n[0] * ek.slope[0] + n[1] * ek.slope[1]),
            ];
            let f_w = mul(&c0.r, f_loc);
            apply(i, f_w, ek.p, force, torque);
            apply(0, scale(f_w, -1.0), ek.p, force, torque);
            let mut bar_f = [-fnrm * n[0], -fnrm * n[1]];
            if c.friction > 0.0 {
                let rc = mul(
                    &c0.r,
                    [
                        self.m.bore_radius_m * n[0],
                        self.m.bore_radius_m * n[1],
                        0.0,
                    ],
                );
                let cpt = add(ek.p, rc);
                let vc = add(ek.vp, cross(s.w, rc));
                let vrel_w = sub(sub(vc, c0.v), cross(c0.w, sub(cpt, c0.x)));
                let vr = mul_t(&c0.r, vrel_w);
                let vr = [vr[0] - ek.udot[0], vr[1] - ek.udot[1], vr[2]];
                let vn = vr[0] * n[0] + vr[1] * n[1];
                let vt = [vr[0] - vn * n[0], vr[1] - vn * n[1], vr[2]];
                let vtm = norm(vt);
                let cd = c.friction_factor(vtm);
                if cd > 0.0 {
                    let ft = c.friction * cd * fnrm;
                    let ft_loc = scale(vt, -ft / vtm);
                    let ft_w = mul(&c0.r, ft_loc);
                    apply(i, ft_w, cpt, force, torque);
                    apply(0, scale(ft_w, -1.0), cpt, force, torque);
                    bar_f[0] -= ft_loc[0];
                    bar_f[1] -= ft_loc[1];
                    p_fric += ft * vtm;
                }
            }
            for mo in 0..self.nm {
                q_gen[(j * 2) * self.nm + mo] += bar_f[0] * ek.phi[mo];
                q_gen[(j * 2 + 1) * self.nm + mo] += bar_f[1] * ek.phi[mo];
            }
        }

        // Bars: q̈ + 2ζω q̇ + ω² q = Q (unit modal mass).
        let mut p_bar = 0.0;
        if let Some(bar) = &self.m.bars {
            let nq = 8 * self.nm;
            for bd in 0..8 {
                for mo in 0..self.nm {
                    let qi = self.bar_off + bd * self.nm + mo;
                    let w = bar.omega[mo];
                    let qd = y[qi + nq];
                    let cdamp = 2.0 * bar.damping_ratio * w;
                    dy[qi] = qd;
                    dy[qi + nq] = q_gen[bd * self.nm + mo] - cdamp * qd - w * w * y[qi];
                    p_bar += cdamp * qd * qd;
                }
            }
        }
        // Rigid bodies.
        for b in 0..nb {
            if !self.free[b] {
                continue;
            }
            let (mass, inertia) = if b == 0 {
                let cp = self
                    .m
                    .carrier
                    .as_ref()
                    .expect("a free body 0 is a free carrier");
                (cp.mass_kg, cp.inertia_kg_m2)
            } else {
                (
                    self.m.satellites[b - 1].mass_kg,
                    self.m.satellites[b - 1].inertia_kg_m2,
                )
            };
            let o = BODY_STATES * b;
            let wb = [y[o + 10], y[o + 11], y[o + 12]];
            dy[o..o + 3].copy_from_slice(&y[o + 7..o + 10]);
            dy[o + 3..o + 7].copy_from_slice(&quat_rate(&y[o + 3..o + 7], wb));
            let a = scale(force[b], 1.0 / mass);
            dy[o + 7..o + 10].copy_from_slice(&a);
            let tb = mul_t(&frames[b].r, torque[b]);
            dy[o + 10..o + 13].copy_from_slice(&angular_accel(inertia, wb, tb));
        }
        dy[self.en_off] = p_contact;
        dy[self.en_off + 1] = p_fric;
        dy[self.en_off + 2] = p_bar;
    }

    // Event functions: [0, 8n) penetration of each edge, [8n, 16n) height of each edge above
    // the bar tip, [16n, 16n + 4n) spring extension minus end of action.
    fn n_events(&self) -> usize {
        20 * self.n
    }

    fn event_value(&self, y: &[f64], idx: usize, frames: &[Frame]) -> f64 {
        let n8 = 8 * self.n;
        if idx < 2 * n8 {
            let ei = idx % n8;
            let (i, j, k) = (ei / 8 + 1, (ei % 8) / 2, ei % 2);
            let ek = self.edge_kin(y, &frames[0], &frames[i], i, j, k, false);
            if idx < n8 {
                ek.delta
            } else {
                ek.z - self.m.bar_length_m
            }
        } else {
            let si = idx - 2 * n8;
            self.spring_ext(frames, si).0 - self.m.springs[si].end_of_action_m()
        }
    }

    /// [`Self::event_value`] computing only the frames that event needs (root location
    /// evaluates one event many times).
    fn event_value_at(&self, y: &[f64], idx: usize) -> f64 {
        let n8 = 8 * self.n;
        if idx < 2 * n8 {
            let ei = idx % n8;
            let (i, j, k) = (ei / 8 + 1, (ei % 8) / 2, ei % 2);
            let ek = self.edge_kin(y, &self.frame(y, 0), &self.frame(y, i), i, j, k, false);
            if idx < n8 {
                ek.delta
            } else {
                ek.z - self.m.bar_length_m
            }
        } else {
            let si = idx - 2 * n8;
            self.spring_ext(&self.frames(y), si).0 - self.m.springs[si].end_of_action_m()
        }
    }

    fn frames(&self, y: &[f64]) -> Vec<Frame> {
        (0..=self.n).map(|b| self.frame(y, b)).collect()
    }

    /// All event values into `g`, and the rate δ̇ of every edge's penetration into `gd` (for
    /// the hidden-contact test). Every edge is evaluated exactly (δ and δ̇), touching or not.
    fn events(&self, y: &[f64], g: &mut [f64], gd: &mut [f64]) {
        let frames = self.frames(y);
        let n8 = 8 * self.n;
        for ei in 0..n8 {
            // `crossed`, the hidden-contact test and the state maintenance skip an edge past
            // the tip: its values are never read.
            if self.edges[ei].past_tip {
                continue;
            }
            let (delta, delta_dot, z) = self.edge_event(y, &frames[0], &frames[ei / 8 + 1], ei);
            g[ei] = delta;
            gd[ei] = delta_dot;
            g[n8 + ei] = z - self.m.bar_length_m;
        }
        for (idx, gi) in g.iter_mut().enumerate().skip(2 * n8) {
            *gi = self.event_value(y, idx, &frames);
        }
    }

    /// A contact hidden inside a step: δ < 0 at both ends, but the cubic Hermite interpolant of
    /// δ (values and rates at both ends) rises above zero in between. Returns the θ ∈ (0, 1)
    /// of the interpolant's maximum when it is positive.
    fn hidden_contact(g0: f64, d0: f64, g1: f64, d1: f64, h: f64) -> Option<f64> {
        let a = 2.0 * g0 + h * d0 - 2.0 * g1 + h * d1;
        let b = -3.0 * g0 - 2.0 * h * d0 + 3.0 * g1 - h * d1;
        let c = h * d0;
        let p = |t: f64| ((a * t + b) * t + c) * t + g0;
        // Roots of p' = 3a θ² + 2b θ + c.
        let mut cands = [f64::NAN; 2];
        if a.abs() < 1e-300 {
            if b.abs() > 1e-300 {
                cands[0] = -c / (2.0 * b);
            }
        } else {
            let disc = 4.0 * b * b - 12.0 * a * c;
            if disc >= 0.0 {
                let sq = disc.sqrt();
                cands[0] = (-2.0 * b + sq) / (6.0 * a);
                cands[1] = (-2.0 * b - sq) / (6.0 * a);
            }
        }
        cands
            .into_iter()
            .filter(|t| *t > 0.0 && *t < 1.0 && p(*t) > 0.0)
            .reduce(f64::min)
    }

    /// Whether event `idx` is live and crossed between `a` (before) and `b` (after).
    fn crossed(&self, idx: usize, a: f64, b: f64) -> bool {
        let n8 = 8 * self.n;
        if idx < n8 {
            let e = &self.edges[idx];
            if e.past_tip {
                return false;
            }
            let touching = matches!(e.state, ContactState::Collision | ContactState::Contact);
            // Onset of a free edge, or exit of a touching one; and the onset of an edge
            // switched on at δ < 0: the state after a re-taken step differs from the dense
            // output that located its onset by the step's local error, so an onset can land a
            // hair early, and the δ^1.5 corner it then crosses inside a step must be located
            // as well (it also re-latches the impact speed there).
            (!touching && a < 0.0 && b >= 0.0) || (touching && (a > 0.0) != (b > 0.0))
        } else if idx < 2 * n8 {
            let ei = idx - n8;
            !self.edges[ei].past_tip && self.free[ei / 8 + 1] && a < 0.0 && b >= 0.0
        } else {
            let si = idx - 2 * n8;
            self.released[self.m.springs[si].interface]
                && if self.spring_on[si] {
                    a < 0.0 && b >= 0.0
                } else {
                    a >= 0.0 && b < 0.0
                }
        }
    }

    fn energy(&self, y: &[f64]) -> EnergyAudit {
        let mut e = EnergyAudit::default();
        let frames = self.frames(y);
        for (si, s) in self.m.springs.iter().enumerate() {
            if self.released[s.interface] {
                e.spring_work_j += s.work(self.spring_ext(&frames, si).0);
            }
        }
        for b in 0..=self.n {
            if !self.free[b] {
                continue;
            }
            let (mass, inertia) = if b == 0 {
                let cp = self.m.carrier.as_ref().expect("free carrier");
                (cp.mass_kg, cp.inertia_kg_m2)
            } else {
                (
                    self.m.satellites[b - 1].mass_kg,
                    self.m.satellites[b - 1].inertia_kg_m2,
                )
            };
            let o = BODY_STATES * b;
            let v = [y[o + 7], y[o + 8], y[o + 9]];
            e.kinetic_j += 0.5 * mass * dot(v, v);
            for a in 0..3 {
                e.kinetic_j += 0.5 * inertia[a] * y[o + 10 + a].powi(2);
            }
        }
        if let Some(bar) = &self.m.bars {
            let nq = 8 * self.nm;
            for bd in 0..8 {
                for mo in 0..self.nm {
                    let qi = self.bar_off + bd * self.nm + mo;
                    e.bar_j += 0.5 * y[qi + nq].powi(2) + 0.5 * (bar.omega[mo] * y[qi]).powi(2);
                }
            }
        }
        for i in 1..=self.n {
            for j in 0..4 {
                for k in 0..2 {
                    if self.edges[(i - 1) * 8 + j * 2 + k].past_tip {
                        continue;
                    }
                    let ek = self.edge_kin(y, &frames[0], &frames[i], i, j, k, true);
                    if ek.z >= 0.0 && ek.z <= self.m.bar_length_m {
                        e.contact_elastic_j += self.m.contact.elastic_energy(ek.delta);
                    }
                }
            }
        }
        e.contact_damping_loss_j = y[self.en_off];
        e.friction_loss_j = y[self.en_off + 1];
        e.bar_damping_loss_j = y[self.en_off + 2];
        e.tip_cut_loss_j = self.tip_cut_loss;
        e.residual_j = e.spring_work_j
            - (e.kinetic_j
                + e.bar_j
                + e.contact_elastic_j
                + e.contact_damping_loss_j
                + e.friction_loss_j
                + e.bar_damping_loss_j
                + e.tip_cut_loss_j);
        e.relative_residual = e.residual_j.abs() / self.e_ref;
        e
    }

    /// Applies the releases due at time t: springs switch on, bodies whose latch chain to the
    /// fixed carrier is broken start moving.
    fn apply_releases(&mut self, t: f64) {
        for k in 1..=self.n {
            if !self.released[k] && self.m.release_times_s[k - 1].is_some_and(|tk| tk <= t) {
                self.released[k] = true;
                for (si, s) in self.m.springs.iter().enumerate() {
                    if s.interface == k {
                        self.spring_on[si] = true;
                    }
                }
            }
        }
        // Groups of latched bodies; body n + 1 stands for the carrier (index 0).
        let n = self.n;
        let mut start = 1;
        while start <= n + 1 {
            let mut end = start;
            while end <= n && !self.released[end] {
                end += 1;
            }
            let has_carrier = end == n + 1;
            let single = end == start;
            let moving = single && !(has_carrier && self.m.carrier.is_none());
            if moving {
                self.free[if has_carrier { 0 } else { start }] = true;
            }
            start = end + 1;
        }
    }

    fn non_finite(&self, t: f64, y: &[f64]) -> Option<SeparationError> {
        let bad = y.iter().position(|v| !v.is_finite())?;
        let body = if bad < self.bar_off {
            let b = bad / BODY_STATES;
            if b == 0 {
                "the carrier".to_string()
            } else {
                format!("satellite {b}")
            }
        } else if bad < self.en_off {
            let r = bad - self.bar_off;
            let r = r % (8 * self.nm);
            let bd = r / self.nm;
            format!(
                "guide bar {} ({}), mode {}",
                bd / 2 + 1,
                if bd.is_multiple_of(2) { "x" } else { "y" },
                r % self.nm + 1
            )
        } else {
            "the energy accumulators".to_string()
        };
        Some(SeparationError::NonFinite { time_s: t, body })
    }

    fn run(&mut self, opts: &RunOptions) -> Result<SeparationResult, SeparationError> {
        let m = self.m;
        let n = self.n;
        let n8 = 8 * n;
        let y0 = self.initial_state();
        // Bodies given an initial velocity (tests) move from the start, as if released.
        for (i, s) in m.satellites.iter().enumerate() {
            if s.initial_velocity_m_s != [0.0; 3] || s.initial_rate_rad_s != [0.0; 3] {
                self.free[i + 1] = true;
            }
        }
        let atol = self.atol(m.tolerance);
        let mut releases: Vec<f64> = m
            .release_times_s
            .iter()
            .flatten()
            .copied()
            .filter(|&t| t < m.max_time_s)
            .collect();
        releases.sort_by(f64::total_cmp);
        releases.dedup();
        // Releases due at t = 0 apply before the first step.
        let mut next_release = 0;
        while next_release < releases.len() && releases[next_release] <= 0.0 {
            self.apply_releases(0.0);
            next_release += 1;
        }
        self.rebuild_static(&y0);
        let mut ig = {
            let this = &*self;
            let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
            Dopri5::new(&mut f, 0.0, y0, m.tolerance, atol, m.max_step_s)
        };
        let ne = self.n_events();
        let mut g0 = vec![0.0; ne];
        let mut g1 = vec![0.0; ne];
        let mut gd0 = vec![0.0; n8];
        let mut gd1 = vec![0.0; n8];
        self.events(&ig.y, &mut g0, &mut gd0);
        self.update_touching(&g0[..n8]);
        let mut max_speed = vec![0.0f64; n];
        let mut max_acc = vec![0.0f64; n];
        let mut peak_rate = vec![0.0f64; n];
        let mut pair_min = vec![f64::INFINITY; n.saturating_sub(1)];
        let mut max_rel_residual = 0.0f64;
        let mut hist = opts.record_history.then(|| History {
            satellites: vec![Vec::new(); n],
            ..Default::default()
        });
        let mut next_sample = 0.0;
        let mut ybuf = vec![0.0; self.dim];
        let mut touched = vec![false; n8];
        let mut located: Vec<(usize, f64)> = Vec::new();
        let mut h_contact = f64::INFINITY;
        loop {
            let released_any = self.released.iter().any(|&r| r);
            let pending = next_release < releases.len();
            let all_out = (1..=n)
                .filter(|&i| self.free[i])
                .all(|i| self.exit[i - 1].is_some());
            if (released_any && all_out && !pending) || ig.t >= m.max_time_s {
                break;
            }
            if ig.stats.steps >= m.max_steps {
                return Err(SeparationError::TooManySteps {
                    time_s: ig.t,
                    max_steps: m.max_steps,
                });
            }
            // A non-finite derivative at an accepted state (e.g. a zero inertia under a torque)
            // stops the run here, before any step spreads it.
            if let Some(e) = self.non_finite(ig.t, ig.derivative()) {
                return Err(e);
            }
            let t_limit = if pending {
                releases[next_release]
            } else {
                m.max_time_s
            };
            {
                let this = &*self;
                let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
                ig.step(&mut f, t_limit).map_err(|e| match e {
                    StepFailure::TooSmall { t, h } => SeparationError::StepTooSmall {
                        time_s: t,
                        step_s: h,
                    },
                    StepFailure::NonFinite { t, index } => {
                        let mut probe = vec![0.0; this.dim];
                        probe[index] = f64::NAN;
                        this.non_finite(t, &probe).expect("a NaN was placed")
                    }
                })?;
            }
            if let Some(e) = self.non_finite(ig.t, &ig.y) {
                return Err(e);
            }
            // The scale of the next onset's first step (below).
            if !self.touching.is_empty() {
                h_contact = ig.t - ig.t_prev();
            }
            // Events: locate the earliest crossing on the dense output and re-take to it.
            self.events(&ig.y, &mut g1, &mut gd1);
            let t0 = ig.t_prev();
            let t1 = ig.t;
            let mut t_event = f64::INFINITY;
            let mut first = usize::MAX;
            located.clear();
            for idx in 0..ne {
                if self.crossed(idx, g0[idx], g1[idx]) {
                    let te = self.locate(&ig, idx, t0, t1, g0[idx], g1[idx], &mut ybuf);
                    located.push((idx, te));
                    if te < t_event {
                        t_event = te;
                        first = idx;
                    }
                } else if idx < n8
                    && g0[idx] < 0.0
                    && g1[idx] < 0.0
                    && !self.edges[idx].past_tip
                    && !matches!(
                        self.edges[idx].state,
                        ContactState::Collision | ContactState::Contact
                    )
                {
                    // A short pulse can open and close between two step ends (a free-flight
                    // step is far longer than a contact): look inside the step.
                    if let Some(th) =
                        Self::hidden_contact(g0[idx], gd0[idx], g1[idx], gd1[idx], t1 - t0)
                    {
                        let tm = t0 + th * (t1 - t0);
                        ig.dense(tm, &mut ybuf);
                        let gm = self.event_value_at(&ybuf, idx);
                        if gm >= 0.0 {
                            self.transitions.hidden_onsets += 1;
                            let te = self.locate(&ig, idx, t0, tm, g0[idx], gm, &mut ybuf);
                            located.push((idx, te));
                            if te < t_event {
                                t_event = te;
                                first = idx;
                            }
                        }
                    }
                }
            }
            let mut events_at_t: Vec<usize> = Vec::new();
            if t_event.is_finite() {
                if t_event < t1 {
                    let this = &*self;
                    let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
                    ig.retake(&mut f, t_event);
                    if let Some(e) = self.non_finite(ig.t, &ig.y) {
                        return Err(e);
                    }
                    self.events(&ig.y, &mut g1, &mut gd1);
                }
                // Every event whose sign has crossed at this point, and every event located
                // within SIMULTANEOUS of the earliest one: symmetric edges that touch at the
                // same instant must be latched at the same state, not one after another with
                // slivers of steps in between (which breaks the symmetry the physics has).
                for idx in 0..ne {
                    let near = located
                        .iter()
                        .any(|&(i, te)| i == idx && te <= t_event + SIMULTANEOUS_S);
                    if near || self.crossed(idx, g0[idx], g1[idx]) {
                        events_at_t.push(idx);
                    }
                }
                if events_at_t.is_empty() {
                    events_at_t.push(first);
                }
            }
            // History samples of this (possibly re-taken) step.
            if let Some(h) = hist.as_mut() {
                while next_sample <= ig.t + 1e-12 {
                    ig.dense(next_sample.min(ig.t), &mut ybuf);
                    self.record(h, next_sample, &ybuf);
                    next_sample += m.output_interval_s;
                }
            }
            let t = ig.t;
            // Discrete changes at the event point.
            touched.fill(false);
            let mut changed = !events_at_t.is_empty();
            for &idx in &events_at_t {
                if idx < n8 {
                    let ek = self.kin_of(&ig.y, idx);
                    let e = &mut self.edges[idx];
                    touched[idx] = true;
                    let touching =
                        matches!(e.state, ContactState::Collision | ContactState::Contact);
                    if touching && g0[idx] <= 0.0 {
                        e.impact_speed = Some(ek.1.max(m.contact.min_impact_speed));
                    } else if touching {
                        self.transitions.record(e.state, ContactState::Detached);
                        e.state = ContactState::Detached;
                        e.impact_speed = None;
                    } else {
                        self.transitions.record(e.state, ContactState::Collision);
                        e.state = ContactState::Collision;
                        e.impact_speed = Some(ek.1.max(m.contact.min_impact_speed));
                        self.contacts[idx / 8] += 1;
                    }
                } else if idx < 2 * n8 {
                    let ei = idx - n8;
                    touched[ei] = true;
                    let (delta, _) = self.kin_of(&ig.y, ei);
                    let e = &mut self.edges[ei];
                    e.past_tip = true;
                    if matches!(e.state, ContactState::Collision | ContactState::Contact) {
                        self.tip_cut_loss += m.contact.elastic_energy(delta);
                        self.transitions.record(e.state, ContactState::Detached);
                        e.state = ContactState::Detached;
                        e.impact_speed = None;
                    }
                    let i = ei / 8;
                    if self.exit[i].is_none()
                        && self.edges[i * 8..i * 8 + 8].iter().all(|e| e.past_tip)
                    {
                        let o = BODY_STATES * (i + 1);
                        self.exit[i] = Some((
                            t,
                            [ig.y[o + 7], ig.y[o + 8], ig.y[o + 9]],
                            [ig.y[o + 10], ig.y[o + 11], ig.y[o + 12]],
                        ));
                    }
                } else {
                    // A spring reaching its end of action switches off (one coming back within
                    // it switches on); the step ends on the switch, and the FSAL refresh below
                    // restarts after it.
                    let si = idx - 2 * n8;
                    self.spring_on[si] = !self.spring_on[si];
                }
            }
            // Contact-state maintenance at the step end (eq. 38) for edges without an event.
            for ei in 0..n8 {
                if touched[ei] || self.edges[ei].past_tip {
                    continue;
                }
                // δ at this point is the event value just computed (exact when near).
                let delta = g1[ei];
                let state = self.edges[ei].state;
                let next = match (state, delta > 0.0) {
                    (ContactState::Collision, true) => Some(ContactState::Contact),
                    (ContactState::Collision, false) | (ContactState::Contact, false) => {
                        Some(ContactState::Detached)
                    }
                    (ContactState::Detached, false) => Some(ContactState::Free),
                    (ContactState::Detached, true) | (ContactState::Free, true) => {
                        Some(ContactState::Collision)
                    }
                    _ => None,
                };
                if let Some(s) = next {
                    let ddot = if s == ContactState::Collision {
                        self.kin_of(&ig.y, ei).1
                    } else {
                        0.0
                    };
                    let e = &mut self.edges[ei];
                    self.transitions.record(e.state, s);
                    if s == ContactState::Collision {
                        // Missed onset (zero clearance, or a graze inside one step): latch now.
                        self.transitions.late_onsets += 1;
                        e.impact_speed = Some(ddot.max(m.contact.min_impact_speed));
                        self.contacts[ei / 8] += 1;
                        changed = true;
                    }
                    if s == ContactState::Detached {
                        e.impact_speed = None;
                        changed = true;
                    }
                    e.state = s;
                }
            }
            // Release due exactly now.
            if pending && t >= releases[next_release] {
                self.apply_releases(t);
                self.rebuild_static(&ig.y);
                next_release += 1;
                changed = true;
            }
            self.update_touching(&g1[..n8]);
            if changed {
                // A step that starts on an onset starts on the δ^1.5 corner of the force,
                // where the embedded estimate of DOPRI5 misjudges the error: for a force
                // growing as t^1.5 from the step start the velocity error is 11.3× the
                // estimate (the quadrature error of t^1.5 under the tableau's weights against
                // that of its embedded pair). Its size comes from the pulses before it: half
                // the last step taken in contact, which the controller sized on a pulse.
                if h_contact.is_finite() && events_at_t.iter().any(|&i| i < n8 && g0[i] < 0.0) {
                    ig.limit_next_step(0.5 * h_contact);
                }
                let this = &*self;
                let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| this.rhs(y, dy);
                ig.refresh(&mut f);
            }
            // Event values depend on the continuous state only: the discrete changes above
            // leave them as they are.
            g0.copy_from_slice(&g1);
            gd0.copy_from_slice(&gd1);
            // Records.
            let dyv = ig.derivative();
            for i in 0..n {
                if !self.free[i + 1] {
                    continue;
                }
                let o = BODY_STATES * (i + 1);
                let v = [ig.y[o + 7], ig.y[o + 8], ig.y[o + 9]];
                let w = [ig.y[o + 10], ig.y[o + 11], ig.y[o + 12]];
                max_speed[i] = max_speed[i].max(norm(v));
                max_acc[i] = max_acc[i].max(norm([dyv[o + 7], dyv[o + 8], dyv[o + 9]]));
                peak_rate[i] = peak_rate[i].max(norm(w).to_degrees());
            }
            for (k, pm) in pair_min.iter_mut().enumerate() {
                if self.free[k + 1] && self.free[k + 2] {
                    *pm = pm.min(self.pair_gap(&ig.y, k + 1));
                }
            }
            // The audit costs about one right-hand side: sample it every 8th step.
            if ig.stats.steps % 8 == 0 {
                let en = self.energy(&ig.y);
                max_rel_residual = max_rel_residual.max(en.relative_residual);
            }
        }
        // Results.
        let y = &ig.y;
        let satellites = (0..n)
            .map(|i| {
                let o = BODY_STATES * (i + 1);
                let (t_exit, v, w) = self.exit[i].unwrap_or((
                    ig.t,
                    [y[o + 7], y[o + 8], y[o + 9]],
                    [y[o + 10], y[o + 11], y[o + 12]],
                ));
                let rel = m.release_times_s[i];
                SatelliteResult {
                    index: i + 1,
                    release_time_s: rel,
                    max_speed_m_s: max_speed[i],
                    max_accel_m_s2: max_acc[i],
                    peak_rate_deg_s: peak_rate[i],
                    final_speed_m_s: norm(v),
                    final_rate_deg_s: norm(w).to_degrees(),
                    final_velocity_m_s: v,
                    final_rate_body_deg_s: scale(w, 180.0 / std::f64::consts::PI),
                    exit_time_s: self.exit[i].map(|_| t_exit - rel.unwrap_or(0.0)),
                    contacts: self.contacts[i],
                }
            })
            .collect();
        let mut energy = self.energy(y);
        energy.max_relative_residual = max_rel_residual.max(energy.relative_residual);
        let pair_clearances: Vec<PairClearance> = (0..n.saturating_sub(1))
            .filter(|&k| pair_min[k].is_finite())
            .map(|k| {
                let (ou, ol) = (BODY_STATES * (k + 1), BODY_STATES * (k + 2));
                PairClearance {
                    upper: k + 1,
                    min_clearance_m: pair_min[k],
                    closing_speed_m_s: y[ol + 9] - y[ou + 9],
                }
            })
            .collect();
        let min_clearance_m = pair_clearances
            .iter()
            .map(|p| p.min_clearance_m)
            .reduce(f64::min);
        Ok(SeparationResult {
            satellites,
            energy,
            transitions: self.transitions,
            stats: ig.stats,
            end_time_s: ig.t,
            pair_clearances,
            min_clearance_m,
            history: hist,
        })
    }

    /// The edges whose force the right-hand side evaluates from here on: those in collision
    /// or contact, and those sitting at δ ≥ 0 without a state (an edge that starts at the bar,
    /// as with zero clearance, has no crossing to locate: it touches from its first step, and
    /// the state maintenance latches it at that step's end). `g` holds δ of every edge now.
    fn update_touching(&mut self, g: &[f64]) {
        self.touching.clear();
        for (ei, (e, &d)) in self.edges.iter().zip(g).enumerate() {
            if !e.past_tip
                && (d >= 0.0 || matches!(e.state, ContactState::Collision | ContactState::Contact))
            {
                self.touching.push(ei);
            }
        }
    }

    /// (δ, δ̇) of edge `ei`.
    fn kin_of(&self, y: &[f64], ei: usize) -> (f64, f64) {
        let (i, j, k) = (ei / 8 + 1, (ei % 8) / 2, ei % 2);
        let ek = self.edge_kin(y, &self.frame(y, 0), &self.frame(y, i), i, j, k, false);
        (ek.delta, ek.delta_dot)
    }

    /// Smallest axial gap between satellite `k`'s column bottoms and satellite k + 1's tops.
    fn pair_gap(&self, y: &[f64], k: usize) -> f64 {
        let (a, b) = (self.frame(y, k), self.frame(y, k + 1));
        (0..4)
            .map(|j| {
                let pa = add(a.x, mul(&a.r, self.edge_body[k - 1][j][0]));
                let pb = add(b.x, mul(&b.r, self.edge_body[k][j][1]));
                pa[2] - pb[2]
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Root of event `idx` in (t0, t1] on the dense output (Illinois false position); returns
    /// the end of the final bracket on the crossed side.
    #[allow(clippy::too_many_arguments)]
    fn locate(
        &self,
        ig: &Dopri5,
        idx: usize,
        t0: f64,
        t1: f64,
        g0: f64,
        g1: f64,
        buf: &mut [f64],
    ) -> f64 {
        let (mut a, mut b, mut ga, mut gb) = (t0, t1, g0, g1);
        let tol = 1e-13 * t1.abs().max(1.0);
        let mut side = 0i32;
        for _ in 0..200 {
            if b - a <= tol {
                break;
            }
            let mut t = (a * gb - b * ga) / (gb - ga);
            if !(t > a && t < b) {
                t = 0.5 * (a + b);
            }
            ig.dense(t, buf);
            let g = self.event_value_at(buf, idx);
            let crossed_here = if g0 < 0.0 { g >= 0.0 } else { g <= 0.0 };
            if crossed_here {
                b = t;
                gb = g;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            } else {
                a = t;
                ga = g;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            }
        }
        b
    }

    fn record(&self, h: &mut History, t: f64, y: &[f64]) {
        h.times_s.push(t);
        for i in 0..self.n {
            let o = BODY_STATES * (i + 1);
            let v = [y[o + 7], y[o + 8], y[o + 9]];
            let w = [y[o + 10], y[o + 11], y[o + 12]];
            h.satellites[i].push([
                y[o],
                y[o + 1],
                y[o + 2],
                v[0],
                v[1],
                v[2],
                norm(v),
                w[0].to_degrees(),
                w[1].to_degrees(),
                w[2].to_degrees(),
                norm(w).to_degrees(),
            ]);
        }
        let e = self.energy(y);
        let losses =
            e.contact_damping_loss_j + e.friction_loss_j + e.bar_damping_loss_j + e.tip_cut_loss_j;
        h.energy.push([
            e.spring_work_j,
            e.kinetic_j,
            e.bar_j,
            e.contact_elastic_j,
            losses,
            e.residual_j,
        ]);
    }
}
