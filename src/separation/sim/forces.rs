//! The right-hand side of the equations of motion: the loads on every body (springs here,
//! contacts in `contact_forces`), the bars' modal equations, the rigid-body equations
//! (Newton, quaternion kinematics, Euler), and the dissipated powers the energy audit
//! integrates.

use super::super::body::{BODY_STATES, V3, angular_accel, quat_rate, v3_at};
use super::Sim;
use super::frames::Frame;

/// Buffers of the right-hand side, kept between calls so that it allocates nothing.
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) frames: Vec<Frame>,
    force: Vec<V3>,
    torque: Vec<V3>,
    q_gen: Vec<f64>,
}

/// The resultant force and torque (about the CG, world axes) on every body.
pub(super) struct Loads<'f> {
    pub(super) frames: &'f [Frame],
    force: &'f mut Vec<V3>,
    torque: &'f mut Vec<V3>,
    /// Which bodies move: only their loads are read (`rigid_body_rhs`).
    free: &'f [bool],
}

impl Loads<'_> {
    /// Adds force `f` (world) applied at the world point `at` of body `b`; nothing for a body
    /// that does not move (the fixed carrier takes the reaction of every contact).
    #[inline]
    pub(super) fn apply(&mut self, b: usize, f: V3, at: V3) {
        if !self.free[b] {
            return;
        }
        self.force[b] += f;
        self.torque[b] += (at - self.frames[b].x).cross(&f);
    }
}

impl Sim<'_> {
    pub(super) fn rhs(&self, y: &[f64], dy: &mut [f64]) {
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
        force.resize(nb, V3::zeros());
        torque.clear();
        torque.resize(nb, V3::zeros());
        self.update_frames(y, frames);
        let mut loads = Loads {
            frames,
            force,
            torque,
            free: &self.free,
        };
        self.spring_loads(&mut loads);
        q_gen.clear();
        q_gen.resize(8 * self.nm, 0.0);
        let (p_contact, p_fric) = self.contact_loads(y, &mut loads, q_gen);
        let p_bar = self.bar_rhs(y, q_gen, dy);
        self.rigid_body_rhs(y, &loads, dy);
        dy[self.en_off] = p_contact;
        dy[self.en_off + 1] = p_fric;
        dy[self.en_off + 2] = p_bar;
    }

    /// The frames at `y` into `frames`. The frames of bodies that do not move stay from call
    /// to call (`rebuild_static` empties the buffer when the set changes).
    pub(super) fn update_frames(&self, y: &[f64], frames: &mut Vec<Frame>) {
        let nb = self.n + 1;
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
    }

    /// Body below interface `interface`: the next satellite, or the carrier (body 0).
    pub(super) fn lower_body(&self, interface: usize) -> usize {
        if interface < self.n { interface + 1 } else { 0 }
    }

    /// Extension of spring `si` from its latched position, with its upper seat (world) and the
    /// lower body's axis along which it pushes.
    #[inline]
    pub(super) fn spring_ext(&self, frames: &[Frame], si: usize) -> (f64, V3, V3) {
        let s = &self.m.springs[si];
        let up = &frames[s.interface];
        let low = &frames[self.lower_body(s.interface)];
        let pu = up.x + up.r * self.spring_up[si];
        let pl = self.static_spring_low[si].unwrap_or_else(|| low.x + low.r * self.spring_low[si]);
        let zl: V3 = low.r.column(2).into();
        ((pu - pl).dot(&zl), pu, zl)
    }

    /// Springs that push (released, short of their end of action): +F on the upper body,
    /// −F on the lower one, both at the upper spring point, along the lower body's axis.
    fn spring_loads(&self, loads: &mut Loads) {
        for (si, s) in self.m.springs.iter().enumerate() {
            if !self.spring_on[si] {
                continue;
            }
            let (ext, pu, zl) = self.spring_ext(loads.frames, si);
            let f = s.force(ext);
            if f != 0.0 {
                let fv = zl * f;
                loads.apply(s.interface, fv, pu);
                loads.apply(self.lower_body(s.interface), -fv, pu);
            }
        }
    }

    /// Bars: q̈ + 2ζω q̇ + ω² q = Q (unit modal mass), with Q the generalised contact forces
    /// `q_gen`. Returns the power dissipated by the modal damping.
    fn bar_rhs(&self, y: &[f64], q_gen: &[f64], dy: &mut [f64]) -> f64 {
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
        p_bar
    }

    /// Mass and principal inertia of body `b`.
    pub(super) fn mass_properties(&self, b: usize) -> (f64, V3) {
        if b == 0 {
            let cp = self
                .m
                .carrier
                .as_ref()
                .expect("a free body 0 is a free carrier");
            (cp.mass_kg, cp.inertia_kg_m2.into())
        } else {
            let s = &self.m.satellites[b - 1];
            (s.mass_kg, s.inertia_kg_m2.into())
        }
    }

    /// Derivatives of the free bodies: ẋ = v, q̇ = ½ q ⊗ ω, v̇ = F/m, and Euler's equations
    /// in body axes.
    fn rigid_body_rhs(&self, y: &[f64], loads: &Loads, dy: &mut [f64]) {
        for b in 0..=self.n {
            if !self.free[b] {
                continue;
            }
            let (mass, inertia) = self.mass_properties(b);
            let o = BODY_STATES * b;
            let wb = v3_at(y, o + 10);
            dy[o..o + 3].copy_from_slice(&y[o + 7..o + 10]);
            dy[o + 3..o + 7].copy_from_slice(&quat_rate(&y[o + 3..o + 7], wb));
            let a = loads.force[b] * (1.0 / mass);
            dy[o + 7..o + 10].copy_from_slice(a.as_slice());
            let tb = loads.frames[b].r.tr_mul(&loads.torque[b]);
            dy[o + 10..o + 13].copy_from_slice(angular_accel(inertia, wb, tb).as_slice());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{self, SPRING_K, SPRING_STROKE};
    use super::*;

    /// Satellite 2 released alone and free, 1 cm above its latched position: each of its four
    /// springs on the carrier pushes k (s − 0.01) by Hooke's law (k = 700 N/m, compression
    /// s = 0.08 m), so v̇_z = 4 k (s − 0.01) / m; the springs of interface 1 are not released.
    /// The seats are symmetric about the column pattern but the CG is offset, so the torque
    /// is r × F summed by hand. Tolerance: roundings of the sums.
    #[test]
    fn spring_force_follows_hookes_law() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[26 + 2] += 0.01;
        sim.free[2] = true;
        for si in 4..8 {
            sim.spring_on[si] = true;
        }
        let mut dy = vec![0.0; sim.dim];
        sim.rhs(&y, &mut dy);
        let f = SPRING_K * (SPRING_STROKE - 0.01);
        let (mass, inertia) = (150.0, [16.0, 22.0, 30.0]);
        assert!(
            (dy[26 + 9] - 4.0 * f / mass).abs() < 1e-13,
            "{}",
            dy[26 + 9]
        );
        assert_eq!(&dy[26 + 7..26 + 9], &[0.0, 0.0]);
        // Torque about the CG: Σ (seat − CG) × (0, 0, f) = (Σ r_y f, −Σ r_x f, 0) with
        // r = column − CG offset: Σ r_x = −4 · 0.01, Σ r_y = 4 · 0.02.
        let t = [4.0 * 0.02 * f, 4.0 * 0.01 * f, 0.0];
        for a in 0..3 {
            let w_dot = t[a] / inertia[a];
            assert!(
                (dy[26 + 10 + a] - w_dot).abs() < 1e-13,
                "{a}: {:?}",
                &dy[36..39]
            );
        }
        // Satellite 1 is latched: no derivative.
        assert!(dy[13..26].iter().all(|&d| d == 0.0));
        // Past the end of action the spring stops pushing.
        y[26 + 2] += SPRING_STROKE;
        sim.rhs(&y, &mut dy);
        assert_eq!(dy[26 + 9], 0.0);
    }

    /// A free satellite spinning about its principal z axis with no load: ω̇ = 0 (Euler,
    /// ω × Iω = 0 for ω along a principal axis), v̇ = 0, q̇ = ½ q ⊗ (0, ω) = (0, 0, 0, ω/2)
    /// at the identity, and the position rate is the velocity. Exact.
    #[test]
    fn a_free_body_without_loads_keeps_its_motion() {
        let m = fixture::two_satellites();
        let mut sim = Sim::new(&m);
        let mut y = sim.initial_state();
        y[13 + 7..13 + 13].copy_from_slice(&[0.1, 0.0, 0.2, 0.0, 0.0, 0.4]);
        sim.free[1] = true;
        let mut dy = vec![0.0; sim.dim];
        sim.rhs(&y, &mut dy);
        assert_eq!(
            &dy[13..26],
            &[
                0.1, 0.0, 0.2, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            ]
        );
    }
}
