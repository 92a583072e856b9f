//! Kinematics of one bore edge against its guide bar: the edge point and its velocity (rigid
//! body), the offset to the deflected bar centreline, the penetration δ = |e| − c and its rate
//! δ̇, the contact normal, and the bar slope and deflection rate at the edge height.

use super::super::body::V3;
use super::Sim;
use super::frames::Frame;
use crate::spec::separation::MAX_BAR_MODES;

/// Geometry and kinematics of one bore edge against its bar.
pub(super) struct EdgeKin {
    /// Penetration δ = |e| − c.
    pub(super) delta: f64,
    pub(super) delta_dot: f64,
    /// Unit normal (carrier frame, horizontal) from the bore centre towards the bar.
    pub(super) n: [f64; 2],
    /// Offset from the edge point to the bar centreline and its rate (carrier x, y): the
    /// line contact interpolates them along the bore.
    pub(super) e: [f64; 2],
    pub(super) edot: [f64; 2],
    /// Height in the carrier frame.
    pub(super) z: f64,
    pub(super) p: V3,
    pub(super) vp: V3,
    /// Bar deflection slope and velocity at the edge height, x and y.
    pub(super) slope: [f64; 2],
    pub(super) udot: [f64; 2],
    /// Mode shapes at the edge height (for the generalised force on the bar).
    pub(super) phi: [f64; MAX_BAR_MODES],
}

impl EdgeKin {
    /// An edge known not to touch, at height z: δ is only known to be negative.
    fn apart(z: f64) -> EdgeKin {
        EdgeKin {
            delta: -f64::MIN_POSITIVE,
            delta_dot: 0.0,
            n: [0.0; 2],
            e: [0.0; 2],
            edot: [0.0; 2],
            z,
            p: V3::zeros(),
            vp: V3::zeros(),
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
pub(super) struct EdgeRigid {
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
            vp: V3::zeros(),
            vrel: V3::zeros(),
            phi: [0.0; MAX_BAR_MODES],
            dphi: [0.0; MAX_BAR_MODES],
        }
    }
}

impl Sim<'_> {
    /// Penetration and kinematics of edge (sat i 1-based, column j, end k) against bar j.
    /// With `touching_only`, an edge that does not touch returns a negative δ (not necessarily
    /// the exact one) and no kinematics: the right-hand side and the energy audit need nothing
    /// else from it. A latched satellite's edge takes its rigid part from the cache.
    // Eight arguments: the two frames are computed once per right-hand side and shared by
    // all edges; bundling them into a struct would only move the count.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn edge_kin(
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
    pub(super) fn edge_event(
        &self,
        y: &[f64],
        c0: &Frame,
        s: &Frame,
        ei: usize,
    ) -> (f64, f64, f64) {
        let (i, j, k) = Self::edge_index(ei);
        let built;
        let r = match &self.static_edges[ei] {
            Some(r) => r,
            None => {
                let (rb, p, pl) = self.edge_point(c0, s, i, j, k);
                built = self.edge_rigid(c0, s, rb, p, pl);
                &built
            }
        };
        let (delta, e, rr) = self.edge_delta(y, j, r);
        (delta, self.edge_rates(y, j, r, e, rr).delta_dot, r.pl[2])
    }

    /// (δ, δ̇) of edge `ei`.
    pub(super) fn kin_of(&self, y: &[f64], ei: usize) -> (f64, f64) {
        let (i, j, k) = Self::edge_index(ei);
        let ek = self.edge_kin(y, &self.frame(y, 0), &self.frame(y, i), i, j, k, false);
        (ek.delta, ek.delta_dot)
    }

    /// Edge k of column j of satellite i (frame `s`): its offset from the satellite's origin
    /// (world axes), its world point and that point in the carrier frame.
    #[inline(always)]
    pub(super) fn edge_point(
        &self,
        c0: &Frame,
        s: &Frame,
        i: usize,
        j: usize,
        k: usize,
    ) -> (V3, V3, V3) {
        let rb = s.r * self.edge_body[i - 1][j][k];
        let p = s.x + rb;
        (rb, p, self.to_carrier(c0, p))
    }

    /// The rigid-body part of an edge's kinematics, from its offset `rb` (world axes), point
    /// `p` and point in the carrier frame `pl`.
    pub(super) fn edge_rigid(&self, c0: &Frame, s: &Frame, rb: V3, p: V3, pl: V3) -> EdgeRigid {
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
        r.vp = s.v + s.w.cross(&rb);
        r.vrel = self.velocity_in_carrier(c0, r.vp, r.p);
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
        let (delta, e, rr) = self.edge_delta(y, j, r);
        let mut ek = EdgeKin {
            delta,
            delta_dot: 0.0,
            n: [0.0; 2],
            e,
            edot: [0.0; 2],
            z: r.pl[2],
            p: r.p,
            vp: r.vp,
            slope: [0.0; 2],
            udot: [0.0; 2],
            phi: r.phi,
        };
        if touching_only && delta <= 0.0 {
            return ek;
        }
        let rates = self.edge_rates(y, j, r, e, rr);
        ek.n = rates.n;
        ek.edot = rates.edot;
        ek.slope = rates.slope;
        ek.udot = rates.udot;
        ek.delta_dot = rates.delta_dot;
        ek
    }

    /// The rates of an edge with offset `e` (length `rr`) from the deflected bar `j`: the
    /// bar's slope and deflection rate at the edge height, the contact normal, ė and δ̇.
    /// Small and by value, so that the events (every edge at every step) copy no `EdgeKin`.
    #[inline(always)]
    fn edge_rates(&self, y: &[f64], j: usize, r: &EdgeRigid, e: [f64; 2], rr: f64) -> EdgeRates {
        let nv = self.nm;
        let (mut slope, mut udot) = ([0.0; 2], [0.0; 2]);
        if self.m.bars.is_some() {
            // Bar j's modal coordinates (x modes, then y) and their rates; zipped so that no
            // index is checked (this runs for every edge at every step), each sum in mode order.
            let q0 = self.qidx(j, 0, 0);
            let (qx, qy) = y[q0..q0 + 2 * nv].split_at(nv);
            let (vx, vy) = y[q0 + 8 * nv..q0 + 10 * nv].split_at(nv);
            let modes = r.phi.iter().zip(&r.dphi).zip(qx.iter().zip(qy));
            for (((p, dp), (ax, ay)), (bx, by)) in modes.zip(vx.iter().zip(vy)) {
                slope[0] += dp * ax;
                udot[0] += p * bx;
                slope[1] += dp * ay;
                udot[1] += p * by;
            }
        }
        let n = if rr > 1e-300 {
            [e[0] / rr, e[1] / rr]
        } else {
            [0.0, 0.0]
        };
        let vrel = r.vrel;
        let edot = [
            udot[0] + slope[0] * vrel[2] - vrel[0],
            udot[1] + slope[1] * vrel[2] - vrel[1],
        ];
        EdgeRates {
            n,
            edot,
            slope,
            udot,
            delta_dot: n[0] * edot[0] + n[1] * edot[1],
        }
    }
}

/// The rate part of an edge's kinematics (see [`Sim::edge_rates`]).
struct EdgeRates {
    n: [f64; 2],
    edot: [f64; 2],
    slope: [f64; 2],
    udot: [f64; 2],
    delta_dot: f64,
}

#[cfg(test)]
mod tests {
    use super::super::super::params::Model;
    use super::super::fixture;
    use super::*;

    /// Satellite 1 displaced 1.5 mm along +x, moving at v = (0.01, 0.02, 0.3) m/s and turning
    /// at ω = (0.1, −0.2, 0.05) rad/s (body = world axes at identity attitude), rigid bars.
    fn moving_satellite() -> (Model, Vec<f64>) {
        let m = fixture::two_satellites();
        let sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13] += 1.5e-3;
        y[13 + 7..13 + 13].copy_from_slice(&[0.01, 0.02, 0.3, 0.1, -0.2, 0.05]);
        (m, y)
    }

    /// The edge point velocity is v + ω × r with r the edge offset from the CG, by hand;
    /// tolerance a few roundings of the 0.3 m/s speed.
    #[test]
    fn edge_point_velocity_is_v_plus_omega_cross_r() {
        let (m, y) = moving_satellite();
        let mut sim = Sim::new(&m);
        sim.carrier_at_rest = true;
        let (c0, s) = (sim.frame_of(&y, 0), sim.frame_of(&y, 1));
        // Column 2 (−0.5, −0.4), top edge: r = (−0.5 − 0.01, −0.4 + 0.02, 0.25 − 0.03).
        let r = [-0.51, -0.38, 0.22];
        let (w, v) = ([0.1, -0.2, 0.05], [0.01, 0.02, 0.3]);
        let by_hand = [
            v[0] + (w[1] * r[2] - w[2] * r[1]),
            v[1] + (w[2] * r[0] - w[0] * r[2]),
            v[2] + (w[0] * r[1] - w[1] * r[0]),
        ];
        let ek = sim.edge_kin(&y, &c0, &s, 1, 2, 1, false);
        for a in 0..3 {
            assert!((ek.vp[a] - by_hand[a]).abs() < 1e-15, "{a}: {:?}", ek.vp);
        }
    }

    /// Penetration and its rate against a rigid bar, by hand: the satellite moved 1.5 mm
    /// towards +x, so the edges of the +x columns sit 1.5 mm off their bars, beyond the 1 mm
    /// clearance: δ = 0.5 mm, normal (−1, 0) (from the bore centre to the bar), and
    /// δ̇ = n · (−v_edge) = v_edge,x. Tolerance: roundings of millimetre differences.
    #[test]
    fn penetration_and_its_rate_against_a_rigid_bar() {
        let (m, y) = moving_satellite();
        let mut sim = Sim::new(&m);
        sim.carrier_at_rest = true;
        let (c0, s) = (sim.frame_of(&y, 0), sim.frame_of(&y, 1));
        // Column 0 (+0.5, +0.4), bottom edge: r = (0.49, 0.42, −0.28).
        let ek = sim.edge_kin(&y, &c0, &s, 1, 0, 0, false);
        assert!((ek.delta - 0.5e-3).abs() < 1e-15, "δ = {}", ek.delta);
        assert!((ek.n[0] + 1.0).abs() < 1e-12 && ek.n[1].abs() < 1e-12);
        let vx = 0.01 + (-0.2 * -0.28 - 0.05 * 0.42);
        assert!((ek.delta_dot - vx).abs() < 1e-12, "δ̇ = {}", ek.delta_dot);
        assert_eq!(sim.kin_of(&y, 0), (ek.delta, ek.delta_dot));
        assert_eq!(sim.edge_kin(&y, &c0, &s, 1, 0, 0, true).delta, ek.delta);
        // A translation moves every edge alike: the −x columns' edges sit 1.5 mm off too.
        let other = sim.edge_kin(&y, &c0, &s, 1, 1, 0, false);
        assert!((other.delta - 0.5e-3).abs() < 1e-15, "δ = {}", other.delta);
        // Displaced by 0.5 mm only, within the clearance: δ = −0.5 mm, and the touching-only
        // path gives some negative δ.
        let mut y2 = y.clone();
        y2[13] -= 1e-3;
        let s2 = sim.frame_of(&y2, 1);
        let apart = sim.edge_kin(&y2, &c0, &s2, 1, 0, 0, false);
        assert!((apart.delta + 0.5e-3).abs() < 1e-15, "δ = {}", apart.delta);
        assert!(sim.edge_kin(&y2, &c0, &s2, 1, 0, 0, true).delta < 0.0);
    }
}
