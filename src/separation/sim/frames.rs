//! Body frames read from the state: position, rotation (body → world), velocity and angular
//! velocity in world axes of each body, and the map of a world point into the carrier frame.

use super::super::body::{BODY_STATES, M3, V3, rotation, v3_at};
use super::Sim;

/// One body's frame at one state.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    /// Position of the CG, world.
    pub(super) x: V3,
    /// Rotation body → world.
    pub(super) r: M3,
    /// Velocity of the CG, world.
    pub(super) v: V3,
    /// Angular velocity, world axes.
    pub(super) w: V3,
}

impl Sim<'_> {
    /// The frame of body `b`: from the cache when the body does not move.
    #[inline]
    pub(super) fn frame(&self, y: &[f64], b: usize) -> Frame {
        if let Some(f) = self.static_frames[b] {
            return f;
        }
        self.frame_of(y, b)
    }

    /// The frame of body `b` computed from the state.
    #[inline]
    pub(super) fn frame_of(&self, y: &[f64], b: usize) -> Frame {
        let o = BODY_STATES * b;
        let r = rotation(&y[o + 3..o + 7]);
        Frame {
            x: v3_at(y, o),
            v: v3_at(y, o + 7),
            w: r * v3_at(y, o + 10),
            r,
        }
    }

    /// The frames of every body, carrier first.
    pub(super) fn frames(&self, y: &[f64]) -> Vec<Frame> {
        (0..=self.n).map(|b| self.frame(y, b)).collect()
    }

    /// A world point in the carrier frame. A fixed carrier at the origin with the identity
    /// attitude (the usual case) maps every finite point onto itself exactly, so the transform
    /// is skipped: it runs for every moving edge in every right-hand side.
    #[inline(always)]
    pub(super) fn to_carrier(&self, c0: &Frame, p: V3) -> V3 {
        if self.carrier_at_rest {
            p
        } else {
            c0.r.tr_mul(&(p - c0.x))
        }
    }

    /// A vector in carrier axes turned into world axes; the identity for a carrier at rest
    /// (as in [`Self::to_carrier`]): the contact forces of every touching edge go through it.
    #[inline(always)]
    pub(super) fn carrier_axes_to_world(&self, c0: &Frame, v: V3) -> V3 {
        if self.carrier_at_rest { v } else { c0.r * v }
    }

    /// The velocity `v` (world) of the world point `p` relative to the carrier, in carrier
    /// axes; `v` itself for a carrier at rest (as in [`Self::to_carrier`]).
    #[inline(always)]
    pub(super) fn velocity_in_carrier(&self, c0: &Frame, v: V3, p: V3) -> V3 {
        if self.carrier_at_rest {
            v
        } else {
            c0.r.tr_mul(&(v - c0.v - c0.w.cross(&(p - c0.x))))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture;
    use super::*;

    /// A satellite turned by a quarter turn about z and spinning about its body x: the frame
    /// maps body x to world y and gives the world angular velocity along world y (by hand:
    /// R = Rz(90°), ω_world = R ω_body). Tolerance: the rounding of cos 45°, sin 45°.
    #[test]
    fn frame_rotates_the_body_rate_into_world_axes() {
        let m = fixture::two_satellites();
        let sim = Sim::new(&m);
        let mut y = sim.initial_state();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        y[13 + 3..13 + 7].copy_from_slice(&[h, 0.0, 0.0, h]);
        y[13 + 10] = 2.0;
        let f = sim.frame_of(&y, 1);
        assert!((f.r * V3::x() - V3::y()).norm() < 1e-15);
        assert!((f.w - V3::new(0.0, 2.0, 0.0)).norm() < 1e-15);
        // Right-handed: body x × body y = body z stays world z.
        let z = (f.r * V3::x()).cross(&(f.r * V3::y()));
        assert!((z - V3::z()).norm() < 1e-15);
        assert_eq!(f.x, V3::new(0.01, -0.02, 0.7 + 0.25 + 0.03));
    }

    /// A carrier displaced by (1, 2, 3) and turned a quarter turn about z: the world point
    /// (1, 3, 3) is one metre along the carrier's x axis (by hand: Rᵀ (p − x)).
    #[test]
    fn a_world_point_maps_into_a_moved_carrier_frame() {
        let m = fixture::two_satellites();
        let sim = Sim::new(&m);
        let mut y = sim.initial_state();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        y[..7].copy_from_slice(&[1.0, 2.0, 3.0, h, 0.0, 0.0, h]);
        let c0 = sim.frame_of(&y, 0);
        let p = sim.to_carrier(&c0, V3::new(1.0, 3.0, 3.0));
        assert!((p - V3::x()).norm() < 1e-15);
    }
}
