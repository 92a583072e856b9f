//! Line contact (paper §3.3.1, Fig. 7d): where the bore lies along the bar, the normal force is
//! distributed along the overlap instead of sitting at the two bore edges.
//!
//! Model: between its two edges the bore axis is straight (rigid satellite) and the bar is
//! taken as the chord between its deflected centreline at the two edge heights, so the offset
//! bar − bore axis is e(s) = (1 − s)·e₀ + s·e₁ along the bore (s from 0 at the edge to 1 at
//! the other edge), and the penetration δ(s) = |e(s)| − c is convex in s. The overlap
//! {δ > 0} is therefore attached to the edges: a piece from an edge to the first root of
//! δ(s), or to the middle of the bore when the whole bore overlaps. Each touching edge carries
//! its piece, so the edges' onset and exit events, contact states and latched impact speeds
//! stay exactly those of the point contact.
//!
//! Load: p(s) = k δ(s) (1 + 3(1 − Ce²) δ̇(s) / (4 δ̇⁻)) per unit length (the linearised line
//! contact of two conformal cylinders, with the Lankarani–Nikravesh damping of the edge's
//! latched impact speed), integrated by Gauss–Legendre on the piece. The force at s acts on
//! the chord model's coordinates e₀, e₁ with weights 1 − s and s: on the satellite that is a
//! force at the two edge points whose resultant and moment are those of the force at s (a
//! rigid body), and on the bar the generalised force at the two edge heights. The load is
//! the gradient of the energy ∫ k δ²/2 ds over the pieces (the piece ends are roots of δ or
//! fixed), so the energy audit closes as for the point contact. Friction acts at the bore
//! wall at each Gauss point against the sliding velocity interpolated the same way.
//!
//! Once one edge of a column has left the bar tip the chord no longer exists: the other edge
//! falls back to the point contact, and the change of elastic energy at that event is booked
//! with the energy cut off at the tip.

use super::super::body::V3;
use super::Sim;
use super::edges::EdgeKin;
use super::forces::Loads;
use crate::spec::separation::MAX_LINE_POINTS;

/// Gauss–Legendre abscissae and weights on [−1, 1] for 1..=6 points (Abramowitz & Stegun,
/// Table 25.4).
const GAUSS: [&[(f64, f64)]; MAX_LINE_POINTS] = [
    &[(0.0, 2.0)],
    &[(-0.5773502691896258, 1.0), (0.5773502691896258, 1.0)],
    &[
        (-0.7745966692414834, 0.5555555555555556),
        (0.0, 0.8888888888888888),
        (0.7745966692414834, 0.5555555555555556),
    ],
    &[
        (-0.8611363115940526, 0.3478548451374539),
        (-0.3399810435848563, 0.6521451548625461),
        (0.3399810435848563, 0.6521451548625461),
        (0.8611363115940526, 0.3478548451374539),
    ],
    &[
        (-0.906179845938664, 0.2369268850561891),
        (-0.5384693101056831, 0.4786286704993665),
        (0.0, 0.5688888888888889),
        (0.5384693101056831, 0.4786286704993665),
        (0.906179845938664, 0.2369268850561891),
    ],
    &[
        (-0.932469514203152, 0.1713244923791704),
        (-0.6612093864662645, 0.3607615730481386),
        (-0.2386191860831969, 0.467913934572691),
        (0.2386191860831969, 0.467913934572691),
        (0.6612093864662645, 0.3607615730481386),
        (0.932469514203152, 0.1713244923791704),
    ],
];

/// Where the share of an edge ends, as s ∈ (0, 1] from the edge (offset `e0`, δ > 0) towards
/// the other edge (offset `e1`): the first root of |e(s)| = c, else the middle of the bore when
/// the other edge carries its own share, else the other edge.
pub(super) fn share_end(e0: [f64; 2], e1: [f64; 2], c: f64, other_touching: bool) -> f64 {
    let d = [e1[0] - e0[0], e1[1] - e0[1]];
    // f(s) = |e(s)|² − c² = a s² + b s + f0, with f0 > 0.
    let a = d[0] * d[0] + d[1] * d[1];
    let b = 2.0 * (e0[0] * d[0] + e0[1] * d[1]);
    let f0 = e0[0] * e0[0] + e0[1] * e0[1] - c * c;
    let root = if b >= 0.0 {
        // f grows from f(0) > 0 (a ≥ 0): no positive root.
        None
    } else {
        let disc = b * b - 4.0 * a * f0;
        // Both roots positive (product f0/a > 0, sum −b/a > 0); the smaller one, in the
        // form without cancellation: 2 f0 / (−b + √disc).
        (disc >= 0.0).then(|| 2.0 * f0 / (-b + disc.sqrt()))
    };
    match root {
        Some(r) if r < 1.0 => r,
        _ if other_touching => 0.5,
        _ => 1.0,
    }
}

/// One Gauss point of an edge's share: its place s along the bore, its weight (a length, m),
/// penetration, rate and normal.
struct LinePoint {
    s: f64,
    weight_m: f64,
    delta: f64,
    delta_dot: f64,
    n: [f64; 2],
}

impl Sim<'_> {
    /// The Gauss points of the share of edge `a` (against the other edge `b` of its bore) that
    /// overlap, for a bore of length `len_m`.
    fn line_points(
        &self,
        a: &EdgeKin,
        b: &EdgeKin,
        other_touching: bool,
        len_m: f64,
    ) -> impl Iterator<Item = LinePoint> {
        let c = self.m.clearance_m;
        let s_end = share_end(a.e, b.e, c, other_touching);
        let (e0, e1, d0, d1) = (a.e, b.e, a.edot, b.edot);
        GAUSS[self.m.contact.line_points - 1]
            .iter()
            .filter_map(move |&(xi, w)| {
                let s = 0.5 * s_end * (1.0 + xi);
                let e = [e0[0] + s * (e1[0] - e0[0]), e0[1] + s * (e1[1] - e0[1])];
                let r = (e[0] * e[0] + e[1] * e[1]).sqrt();
                let delta = r - c;
                (delta > 0.0).then(|| {
                    let n = [e[0] / r, e[1] / r];
                    let ed = [d0[0] + s * (d1[0] - d0[0]), d0[1] + s * (d1[1] - d0[1])];
                    LinePoint {
                        s,
                        weight_m: 0.5 * s_end * w * len_m,
                        delta,
                        delta_dot: n[0] * ed[0] + n[1] * ed[1],
                        n,
                    }
                })
            })
    }

    /// Length of the bores of satellite `i`, column `j` (between its two edges), m.
    pub(super) fn bore_length(&self, i: usize, j: usize) -> f64 {
        let e = &self.edge_body[i - 1][j];
        e[1][2] - e[0][2]
    }

    /// Whether edge `ei` carries a force now (see `update_touching`).
    pub(super) fn is_listed(&self, ei: usize) -> bool {
        self.touching.binary_search(&ei).is_ok()
    }

    /// Loads of the share of touching edge `ei` (satellite i, column j, end k) whose other
    /// edge is still on the bar; returns the powers of contact damping and friction.
    pub(super) fn line_loads(
        &self,
        y: &[f64],
        ei: usize,
        a: &EdgeKin,
        loads: &mut Loads,
        q_gen: &mut [f64],
    ) -> (f64, f64) {
        let (i, j, k) = Self::edge_index(ei);
        let frames = loads.frames;
        let c0 = frames[0];
        let b = self.edge_kin(y, &c0, &frames[i], i, j, 1 - k, false);
        let cp = &self.m.contact;
        let v_imp = self.edges[ei].impact_speed.unwrap_or(cp.min_impact_speed);
        let damp = 3.0 * (1.0 - cp.restitution * cp.restitution) / (4.0 * v_imp);
        let (mut p_contact, mut p_fric) = (0.0, 0.0);
        let len_m = self.bore_length(i, j);
        for lp in self.line_points(a, &b, self.is_listed(ei ^ 1), len_m) {
            let kd = cp.line_stiffness * lp.delta;
            let p = (kd * (1.0 + damp * lp.delta_dot)).max(0.0);
            let f = lp.weight_m * p;
            p_contact += lp.weight_m * (p - kd) * lp.delta_dot;
            let n = lp.n;
            for (ek, wt) in [(a, 1.0 - lp.s), (&b, lp.s)] {
                let fe = f * wt;
                let f_loc = V3::new(
                    fe * n[0],
                    fe * n[1],
                    -fe * (n[0] * ek.slope[0] + n[1] * ek.slope[1]),
                );
                let f_w = self.carrier_axes_to_world(&c0, f_loc);
                loads.apply(i, f_w, ek.p);
                loads.apply(0, -f_w, ek.p);
                self.bar_load(q_gen, j, ek, [-fe * n[0], -fe * n[1]]);
            }
            if cp.friction > 0.0 {
                let at = interpolate(a, &b, lp.s, n);
                let mut bar_f = [0.0; 2];
                if let Some(pf) = self.friction_load(&at, i, f, loads, &mut bar_f) {
                    p_fric += pf;
                    for (ek, wt) in [(a, 1.0 - lp.s), (&b, lp.s)] {
                        self.bar_load(q_gen, j, ek, [bar_f[0] * wt, bar_f[1] * wt]);
                    }
                }
            }
        }
        (p_contact, p_fric)
    }

    /// Generalised force on the modes of bar `j` of the lateral force `f` (carrier x, y) at
    /// the height of edge `ek`.
    pub(super) fn bar_load(&self, q_gen: &mut [f64], j: usize, ek: &EdgeKin, f: [f64; 2]) {
        for mo in 0..self.nm {
            q_gen[(j * 2) * self.nm + mo] += f[0] * ek.phi[mo];
            q_gen[(j * 2 + 1) * self.nm + mo] += f[1] * ek.phi[mo];
        }
    }

    /// ∫ k δ²/2 ds over the share of edge `ei` whose other edge is on the bar, J.
    pub(super) fn line_elastic_energy(&self, y: &[f64], ei: usize, a: &EdgeKin) -> f64 {
        let (i, j, k) = Self::edge_index(ei);
        let (c0, s) = (self.frame(y, 0), self.frame(y, i));
        let b = self.edge_kin(y, &c0, &s, i, j, 1 - k, false);
        let kl = self.m.contact.line_stiffness;
        self.line_points(a, &b, self.is_listed(ei ^ 1), self.bore_length(i, j))
            .map(|lp| lp.weight_m * 0.5 * kl * lp.delta * lp.delta)
            .sum()
    }
}

/// The kinematics at s along the bore between edges `a` and `b` for the friction at a Gauss
/// point: the rigid-body point and velocity are exact linear interpolations, the bar
/// deflection rate that of the chord; normal `n` of the point.
fn interpolate(a: &EdgeKin, b: &EdgeKin, s: f64, n: [f64; 2]) -> EdgeKin {
    let lerp = |x: f64, y: f64| x + s * (y - x);
    EdgeKin {
        delta: 0.0,
        delta_dot: 0.0,
        n,
        e: [0.0; 2],
        edot: [0.0; 2],
        z: lerp(a.z, b.z),
        p: a.p + (b.p - a.p) * s,
        vp: a.vp + (b.vp - a.vp) * s,
        slope: [lerp(a.slope[0], b.slope[0]), lerp(a.slope[1], b.slope[1])],
        udot: [lerp(a.udot[0], b.udot[0]), lerp(a.udot[1], b.udot[1])],
        phi: a.phi,
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::body::BODY_STATES;
    use super::super::super::contact::ContactModel;
    use super::super::fixture;
    use super::*;

    /// The fixture's satellite 1 free, at rest, moved by `shift` (x) and turned by `theta`
    /// about y, line contact (k = 1e10 N/m², 4 points), rigid bars, every edge listed as
    /// touching at the floor impact speed.
    fn placed(shift: f64, theta: f64) -> (super::super::super::params::Model, Vec<f64>) {
        let mut m = fixture::two_satellites();
        m.contact.model = ContactModel::Line;
        let sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[BODY_STATES] += shift;
        let (c, s) = ((0.5 * theta).cos(), (0.5 * theta).sin());
        y[BODY_STATES + 3..BODY_STATES + 7].copy_from_slice(&[c, 0.0, s, 0.0]);
        m.contact.line_stiffness = 1e10;
        (m, y)
    }

    /// Force and torque on satellite 1 from its accelerations (identity inertia axes at rest:
    /// Euler's equations reduce to τ = I ω̇ at ω = 0, rotated back to world axes).
    fn resultant(sim: &Sim, y: &[f64]) -> (V3, V3) {
        let mut dy = vec![0.0; sim.dim];
        sim.rhs(y, &mut dy);
        let o = BODY_STATES;
        let (mass, inertia) = sim.mass_properties(1);
        let f = V3::new(dy[o + 7], dy[o + 8], dy[o + 9]) * mass;
        let wd = V3::new(dy[o + 10], dy[o + 11], dy[o + 12]);
        let tb = V3::new(inertia[0] * wd[0], inertia[1] * wd[1], inertia[2] * wd[2]);
        (f, sim.frame_of(y, 1).r * tb)
    }

    /// A bore lying along its bar, pushed 1.5 mm against 1 mm of clearance: a uniform
    /// penetration δ = 0.5 mm over the bore length L = 0.5 m. Closed form of a uniform
    /// distributed load: each column carries k·L·δ along −x, acting at the middle of the bore,
    /// so the torque about the CG is Σ (r_mid × F); elastic energy k·L·δ²/2 per column.
    /// Tolerance: roundings (1e-9 relative).
    #[test]
    fn a_bore_along_its_bar_carries_the_uniform_load_resultant() {
        let (m, y) = placed(1.5e-3, 0.0);
        let mut sim = Sim::new(&m);
        sim.free[1] = true;
        sim.touching = (0..8).collect();
        let (f, tau) = resultant(&sim, &y);
        let (k, len, delta) = (1e10, 0.5, 0.5e-3);
        let col = k * len * delta;
        assert!((f[0] + 4.0 * col).abs() < 1e-9 * col, "{f:?}");
        assert!(f[1].abs() < 1e-9 * col && f[2].abs() < 1e-9 * col, "{f:?}");
        let cg = m.satellites[0].cg_offset_m;
        let mut by_hand = V3::zeros();
        for xy in m.columns_xy {
            let r_mid = V3::new(xy[0] - cg[0], xy[1] - cg[1], -cg[2]);
            by_hand += r_mid.cross(&V3::new(-col, 0.0, 0.0));
        }
        assert!(
            (tau - by_hand).norm() < 1e-9 * col,
            "{tau:?} against {by_hand:?}"
        );
        let e = sim.energy(&y).contact_elastic_j;
        let e_hand = 4.0 * 0.5 * k * len * delta * delta;
        assert!((e - e_hand).abs() < 1e-9 * e_hand, "{e} against {e_hand}");
    }

    /// A tilted bore touching at its bottom edges only: δ falls linearly from δ₀ at the
    /// bottom edge to δ₁ < 0 at the top, so the overlap ends at s* = δ₀/(δ₀ − δ₁) and the load
    /// is a triangle: resultant k·L·δ₀·s*/2 acting at s*/3 from the edge, elastic energy
    /// k·L·δ₀²·s*/6. δ₀, δ₁ are read from the edge kinematics (tested in `edges`); the rest
    /// is the closed form. Tolerance 1e-9 relative: four Gauss points integrate the linear
    /// load and its moment exactly.
    #[test]
    fn a_tilted_bore_carries_the_triangular_load_resultant() {
        let theta = -2e-3;
        let (m, y) = placed(1.2e-3, theta);
        let mut sim = Sim::new(&m);
        sim.free[1] = true;
        let (c0, s1) = (sim.frame_of(&y, 0), sim.frame_of(&y, 1));
        let mut f_hand = V3::zeros();
        let mut tau_hand = V3::zeros();
        let mut e_hand = 0.0;
        let (k, len) = (1e10, 0.5);
        for j in 0..4 {
            let a = sim.edge_kin(&y, &c0, &s1, 1, j, 0, false);
            let b = sim.edge_kin(&y, &c0, &s1, 1, j, 1, false);
            assert!(
                a.delta > 0.0 && b.delta < 0.0,
                "column {j}: {} {}",
                a.delta,
                b.delta
            );
            assert!(a.e[1].abs() < 1e-15 && (a.e[0] * b.e[0]) > 0.0);
            sim.touching.push(2 * j);
            let s_star = a.delta / (a.delta - b.delta);
            let fm = k * len * a.delta * s_star / 2.0;
            let at = a.p + (b.p - a.p) * (s_star / 3.0);
            let fv = c0.r * V3::new(fm * a.n[0], fm * a.n[1], 0.0);
            f_hand += fv;
            tau_hand += (at - s1.x).cross(&fv);
            e_hand += k * len * a.delta * a.delta * s_star / 6.0;
        }
        let (f, tau) = resultant(&sim, &y);
        let scale = f_hand.norm();
        assert!(
            (f - f_hand).norm() < 1e-9 * scale,
            "{f:?} against {f_hand:?}"
        );
        assert!(
            (tau - tau_hand).norm() < 1e-9 * scale,
            "{tau:?} against {tau_hand:?}"
        );
        let e = sim.energy(&y).contact_elastic_j;
        assert!((e - e_hand).abs() < 1e-9 * e_hand, "{e} against {e_hand}");
    }

    /// The share of an edge ends at the first root of |e(s)| = c, by hand: e₀ = (1.5, 0),
    /// e₁ = (0.5, 0), c = 1 → s = 0.5; with the other edge also pressed and no root, the
    /// middle; with neither, the other edge.
    #[test]
    fn a_share_ends_at_the_first_root_or_the_middle() {
        assert!((share_end([1.5, 0.0], [0.5, 0.0], 1.0, false) - 0.5).abs() < 1e-15);
        assert_eq!(share_end([1.5, 0.0], [1.2, 0.0], 1.0, true), 0.5);
        assert_eq!(share_end([1.5, 0.0], [1.2, 0.0], 1.0, false), 1.0);
        // Crossing the bar: e goes from (1.5, 0) to (−1.5, 0) through 0: root at s = 1/6.
        let s = share_end([1.5, 0.0], [-1.5, 0.0], 1.0, true);
        assert!((s - 1.0 / 6.0).abs() < 1e-15, "{s}");
    }
}
