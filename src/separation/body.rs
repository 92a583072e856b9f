//! Rigid-body kinematics for the satellites (and a free carrier): unit quaternions for a
//! singularity-free attitude, rotation matrices, and the small 3-vector algebra the force
//! assembly needs. Pure functions; the state layout lives in `sim`.
//!
//! Why hand-written and not nalgebra: these are a dozen one-line formulas on `[f64; 3]` that
//! sit inside the right-hand side; plain arrays keep the state a flat `&[f64]` slice for the
//! integrator without conversions.

pub type V3 = [f64; 3];
pub type M3 = [[f64; 3]; 3];

/// Number of state entries per rigid body: position (3), quaternion w,x,y,z (4), velocity (3),
/// angular velocity in body axes (3).
pub const BODY_STATES: usize = 13;

#[inline]
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
pub fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// Rotation matrix (body → world) of the quaternion `q = [w, x, y, z]`, normalised here so a
/// slow drift of |q| in the integrated state never distorts the body.
#[inline]
pub fn rotation(q: &[f64]) -> M3 {
    let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let s = 2.0 / n2;
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    [
        [
            1.0 - s * (y * y + z * z),
            s * (x * y - w * z),
            s * (x * z + w * y),
        ],
        [
            s * (x * y + w * z),
            1.0 - s * (x * x + z * z),
            s * (y * z - w * x),
        ],
        [
            s * (x * z - w * y),
            s * (y * z + w * x),
            1.0 - s * (x * x + y * y),
        ],
    ]
}

#[inline]
pub fn mul(m: &M3, v: V3) -> V3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// mᵀ·v.
#[inline]
pub fn mul_t(m: &M3, v: V3) -> V3 {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// q̇ = ½ q ⊗ (0, ω_body).
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
    let iw = [inertia[0] * w[0], inertia[1] * w[1], inertia[2] * w[2]];
    let g = cross(w, iw);
    [
        (torque_body[0] - g[0]) / inertia[0],
        (torque_body[1] - g[1]) / inertia[1],
        (torque_body[2] - g[2]) / inertia[2],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternion_rotation_is_orthonormal_and_right_handed() {
        let h = (0.3f64).sin();
        let q = [0.3f64.cos(), h * 0.6, h * 0.0, h * 0.8];
        let r = rotation(&q);
        let x = mul(&r, [1.0, 0.0, 0.0]);
        let y = mul(&r, [0.0, 1.0, 0.0]);
        let z = mul(&r, [0.0, 0.0, 1.0]);
        assert!((dot(x, y)).abs() < 1e-15 && (norm(z) - 1.0).abs() < 1e-15);
        let c = cross(x, y);
        assert!(norm(sub(c, z)) < 1e-15);
        // Rotation by 0.6 rad about (0.6, 0, 0.8) leaves the axis fixed.
        let a = mul(&r, [0.6, 0.0, 0.8]);
        assert!(norm(sub(a, [0.6, 0.0, 0.8])) < 1e-15);
    }
}
