//! Rigid-body kinematics for the satellites (and a free carrier) on nalgebra's fixed-size
//! types: quaternions for a singularity-free attitude (their rotation matrix and rate written
//! out, see [`rotation`]), Euler's equations. Pure functions; the state layout lives in `sim::layout`, and these read a body's
//! entries straight out of the flat state slice the integrator works on.

use nalgebra::{Matrix3, Vector3};

pub type V3 = Vector3<f64>;
pub type M3 = Matrix3<f64>;

/// Number of state entries per rigid body: position (3), quaternion w,x,y,z (4), velocity (3),
/// angular velocity in body axes (3).
pub const BODY_STATES: usize = 13;

/// The 3-vector at `s[at..at + 3]`.
#[inline(always)]
pub fn v3_at(s: &[f64], at: usize) -> V3 {
    V3::from_column_slice(&s[at..at + 3])
}

/// Rotation matrix (body → world) of the quaternion `q = [w, x, y, z]`, normalised here so a
/// slow drift of |q| in the integrated state never distorts the body. Written out rather than
/// `UnitQuaternion::new_normalize(..).to_rotation_matrix()`: that rounds differently (a square
/// root, then the unit-quaternion formula), and the contact sequence of a release amplifies a
/// last-bit change to 3e-7 of the exit rates even on rigid bars.
#[inline]
pub fn rotation(q: &[f64]) -> M3 {
    let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let s = 2.0 / n2;
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    M3::new(
        1.0 - s * (y * y + z * z),
        s * (x * y - w * z),
        s * (x * z + w * y),
        s * (x * y + w * z),
        1.0 - s * (x * x + z * z),
        s * (y * z - w * x),
        s * (x * z - w * y),
        s * (y * z + w * x),
        1.0 - s * (x * x + y * y),
    )
}

/// q̇ = ½ q ⊗ (0, ω_body), as `[w, x, y, z]`; written out for the same reason as
/// [`rotation`] (the quaternion product sums its terms in another order).
#[inline]
pub fn quat_rate(q: &[f64], w: V3) -> [f64; 4] {
    [
        -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]),
        0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]),
        0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]),
        0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]),
    ]
}

/// Euler's equations in principal body axes: I ω̇ = τ − ω × Iω.
#[inline]
pub fn angular_accel(inertia: V3, w: V3, torque_body: V3) -> V3 {
    let iw = inertia.component_mul(&w);
    (torque_body - w.cross(&iw)).component_div(&inertia)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Quaternion, UnitQuaternion};

    /// The quaternion stored as `[w, x, y, z]` in `q`.
    fn quaternion(q: &[f64]) -> Quaternion<f64> {
        Quaternion::new(q[0], q[1], q[2], q[3])
    }

    /// A rotation by 0.6 rad about the unit axis (0.6, 0, 0.8): orthonormal, right-handed, and
    /// the axis is fixed (by definition of a rotation). Tolerance: roundings of unit vectors.
    #[test]
    fn quaternion_rotation_is_orthonormal_and_right_handed() {
        let h = (0.3f64).sin();
        let q = [0.3f64.cos(), h * 0.6, h * 0.0, h * 0.8];
        let r = rotation(&q);
        let (x, y, z) = (r * V3::x(), r * V3::y(), r * V3::z());
        assert!(x.dot(&y).abs() < 1e-15 && (z.norm() - 1.0).abs() < 1e-15);
        assert!((x.cross(&y) - z).norm() < 1e-15);
        let axis = V3::new(0.6, 0.0, 0.8);
        assert!((r * axis - axis).norm() < 1e-15);
    }

    /// The written-out matrix and rate are nalgebra's unit-quaternion rotation and
    /// quaternion product, to roundings, for an unnormalised q (|q| ≈ 1.14).
    #[test]
    fn rotation_matches_the_unit_quaternion_rotation() {
        let q = [0.55, -0.33, 0.77, 0.55];
        let r = rotation(&q);
        let u = UnitQuaternion::new_normalize(quaternion(&q))
            .to_rotation_matrix()
            .into_inner();
        assert!((r - u).abs().max() < 1e-15, "{r} vs {u}");
        let w = V3::new(0.2, -0.4, 0.6);
        let by_product = quaternion(&q) * Quaternion::from_imag(w) * 0.5;
        let d = quat_rate(&q, w);
        let by_product = [by_product.w, by_product.i, by_product.j, by_product.k];
        for a in 0..4 {
            assert!(
                (d[a] - by_product[a]).abs() < 1e-15,
                "{d:?} vs {by_product:?}"
            );
        }
    }

    /// q̇ = ½ q ⊗ (0, ω) at the identity is (0, ω/2), and for a quarter turn about z spinning
    /// about body x it is ½ (cos 45°, 0, 0, sin 45°) ⊗ (0, ω, 0, 0), by hand.
    #[test]
    fn quaternion_rate_is_half_the_product_with_the_body_rate() {
        let w = V3::new(0.2, -0.4, 0.6);
        assert_eq!(quat_rate(&[1.0, 0.0, 0.0, 0.0], w), [-0.0, 0.1, -0.2, 0.3]);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let d = quat_rate(&[h, 0.0, 0.0, h], V3::new(2.0, 0.0, 0.0));
        // (h + h k)(2 i) = 2h i + 2h (k i) = 2h i + 2h j.
        assert_eq!(d, [0.0, h, h, 0.0]);
    }
}
