//! The 3-D frame element: section properties, local stiffness, consistent mass and geometric
//! stiffness, and the local-to-global rotation from the orientation vector.
//!
//! - Timoshenko bending (Przemieniecki's shear-deformable element) with the shear parameter
//!   Φ = 12·E·I/(k·G·A·L²) and Cowper's (1966) shear factors k: rectangle 10(1+ν)/(12+11ν),
//!   solid circle 6(1+ν)/(7+6ν), hollow circle 6(1+ν)(1+m²)²/((7+6ν)(1+m²)² + (20+12ν)m²) with
//!   m = d_i/d_o. Euler-Bernoulli is the same element with Φ = 0 and no rotary inertia.
//! - Consistent mass with rotary inertia for Timoshenko: the Φ-dependent matrices of
//!   Przemieniecki (1968, §11) as tabulated by Friedman & Kosmatka (1993).
//! - Torsion constant of a rectangle a ≥ b: the exact Saint-Venant series (Timoshenko &
//!   Goodier, Theory of Elasticity, §109): J = a·b³/3·[1 − (192/π⁵)(b/a)·Σ_{n odd} tanh(nπa/2b)/n⁵],
//!   summed until the terms fall below 1e-16 relative.
//! - Torsional mass per unit length ρ·(Iy + Iz) (polar moment), per DESIGN.md.
//! - Geometric stiffness: the consistent beam-column matrix N/(30L)·[36, 3L, …] in both bending
//!   planes plus the Wagner torsion term N·(Iy+Iz)/(A·L); N is the axial force, tension positive.
//!
//! Local DOF order: [u1 v1 w1 θx1 θy1 θz1 u2 v2 w2 θx2 θy2 θz2]. In the x–y plane θz = dv/dx; in the
//! x–z plane θy = −dw/dx, which flips the sign of the coupling terms.

use crate::spec::{Section, Theory};
use nalgebra::Vector3;

/// Cross-section properties in the local axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionProps {
    pub area: f64,
    /// Second moment about local y (bending in the x–z plane).
    pub iy: f64,
    /// Second moment about local z (bending in the x–y plane).
    pub iz: f64,
    pub j: f64,
    /// Timoshenko shear factor; `None` is shear-rigid.
    pub shear_factor: Option<f64>,
}

impl SectionProps {
    pub fn from_spec(s: &Section, poisson: f64) -> SectionProps {
        let nu = poisson;
        let pi = std::f64::consts::PI;
        match s.shape.as_str() {
            "rectangle" => {
                let (w, h) = (s.width_m.unwrap_or(0.0), s.height_m.unwrap_or(0.0));
                SectionProps {
                    area: w * h,
                    iy: w * h.powi(3) / 12.0,
                    iz: h * w.powi(3) / 12.0,
                    j: rectangle_torsion(w, h),
                    shear_factor: Some(10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)),
                }
            }
            "circle" => {
                let d = s.diameter_m.unwrap_or(0.0);
                let i = pi * d.powi(4) / 64.0;
                SectionProps {
                    area: pi * d * d / 4.0,
                    iy: i,
                    iz: i,
                    j: 2.0 * i,
                    shear_factor: Some(6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)),
                }
            }
            "tube" => {
                let (d_o, d_i) = (
                    s.outer_diameter_m.unwrap_or(0.0),
                    s.inner_diameter_m.unwrap_or(0.0),
                );
                tube(d_o, d_i, nu)
            }
            _ => SectionProps {
                area: s.area_m2.unwrap_or(0.0),
                iy: s.iy_m4.unwrap_or(0.0),
                iz: s.iz_m4.unwrap_or(0.0),
                j: s.j_m4.unwrap_or(0.0),
                shear_factor: s.shear_factor,
            },
        }
    }
}

/// Hollow circular section (Cowper's hollow-circle shear factor).
pub fn tube(d_o: f64, d_i: f64, nu: f64) -> SectionProps {
    let pi = std::f64::consts::PI;
    let i = pi * (d_o.powi(4) - d_i.powi(4)) / 64.0;
    let m = d_i / d_o;
    let m2 = (1.0 + m * m).powi(2);
    SectionProps {
        area: pi * (d_o * d_o - d_i * d_i) / 4.0,
        iy: i,
        iz: i,
        j: 2.0 * i,
        shear_factor: Some(
            6.0 * (1.0 + nu) * m2 / ((7.0 + 6.0 * nu) * m2 + (20.0 + 12.0 * nu) * m * m),
        ),
    }
}

/// Saint-Venant torsion constant of a solid rectangle (series formula, see module doc).
pub fn rectangle_torsion(w: f64, h: f64) -> f64 {
    let (a, b) = if w >= h { (w, h) } else { (h, w) };
    let pi = std::f64::consts::PI;
    // Terms fall as 1/n⁵: 1e-16 of the sum is reached by n ≈ 1600; the bound only guards
    // against a NaN dimension, for which the stopping test never holds.
    let mut sum = 0.0;
    for k in 0..4096 {
        let n = (2 * k + 1) as f64;
        let t = (n * pi * a / (2.0 * b)).tanh() / n.powi(5);
        sum += t;
        if t < 1e-16 * sum {
            break;
        }
    }
    a * b.powi(3) / 3.0 * (1.0 - 192.0 / pi.powi(5) * (b / a) * sum)
}

/// Element data in local axes.
#[derive(Debug, Clone, Copy)]
pub struct BeamProps {
    pub e: f64,
    pub g: f64,
    pub rho: f64,
    pub sec: SectionProps,
    pub theory: Theory,
}

pub type M12 = [[f64; 12]; 12];

fn phi(p: &BeamProps, i: f64, l: f64) -> f64 {
    match (p.theory, p.sec.shear_factor) {
        (Theory::Timoshenko, Some(k)) if k > 0.0 => 12.0 * p.e * i / (k * p.g * p.sec.area * l * l),
        _ => 0.0,
    }
}

/// 4×4 bending stiffness for (v1, θ1, v2, θ2) with θ = dv/dx.
fn bend_k(ei: f64, ph: f64, l: f64) -> [[f64; 4]; 4] {
    let c = ei / ((1.0 + ph) * l.powi(3));
    let l2 = l * l;
    [
        [12.0 * c, 6.0 * l * c, -12.0 * c, 6.0 * l * c],
        [
            6.0 * l * c,
            (4.0 + ph) * l2 * c,
            -6.0 * l * c,
            (2.0 - ph) * l2 * c,
        ],
        [-12.0 * c, -6.0 * l * c, 12.0 * c, -6.0 * l * c],
        [
            6.0 * l * c,
            (2.0 - ph) * l2 * c,
            -6.0 * l * c,
            (4.0 + ph) * l2 * c,
        ],
    ]
}

/// 4×4 consistent bending mass (translational + rotary) for (v1, θ1, v2, θ2).
fn bend_m(rho_a: f64, rho_i: f64, ph: f64, l: f64, rotary: bool) -> [[f64; 4]; 4] {
    let d = (1.0 + ph).powi(2);
    let ct = rho_a * l / d;
    let p2 = ph * ph;
    let m11 = 13.0 / 35.0 + 7.0 * ph / 10.0 + p2 / 3.0;
    let m12 = (11.0 / 210.0 + 11.0 * ph / 120.0 + p2 / 24.0) * l;
    let m13 = 9.0 / 70.0 + 3.0 * ph / 10.0 + p2 / 6.0;
    let m14 = -(13.0 / 420.0 + 3.0 * ph / 40.0 + p2 / 24.0) * l;
    let m22 = (1.0 / 105.0 + ph / 60.0 + p2 / 120.0) * l * l;
    let m24 = -(1.0 / 140.0 + ph / 60.0 + p2 / 120.0) * l * l;
    let mut m = [
        [m11, m12, m13, m14],
        [m12, m22, -m14, m24],
        [m13, -m14, m11, -m12],
        [m14, m24, -m12, m22],
    ];
    for row in m.iter_mut() {
        for x in row.iter_mut() {
            *x *= ct;
        }
    }
    if rotary {
        let cr = rho_i / (d * l);
        let r12 = (1.0 / 10.0 - ph / 2.0) * l;
        let r22 = (2.0 / 15.0 + ph / 6.0 + p2 / 3.0) * l * l;
        let r24 = (-1.0 / 30.0 - ph / 6.0 + p2 / 6.0) * l * l;
        let r = [
            [6.0 / 5.0, r12, -6.0 / 5.0, r12],
            [r12, r22, -r12, r24],
            [-6.0 / 5.0, -r12, 6.0 / 5.0, -r12],
            [r12, r24, -r12, r22],
        ];
        for a in 0..4 {
            for b in 0..4 {
                m[a][b] += cr * r[a][b];
            }
        }
    }
    m
}

/// 4×4 geometric stiffness of a beam-column, axial force `n` (tension positive).
fn bend_kg(n: f64, l: f64) -> [[f64; 4]; 4] {
    let c = n / (30.0 * l);
    let l2 = l * l;
    [
        [36.0 * c, 3.0 * l * c, -36.0 * c, 3.0 * l * c],
        [3.0 * l * c, 4.0 * l2 * c, -3.0 * l * c, -l2 * c],
        [-36.0 * c, -3.0 * l * c, 36.0 * c, -3.0 * l * c],
        [3.0 * l * c, -l2 * c, -3.0 * l * c, 4.0 * l2 * c],
    ]
}

/// Scatters a 4×4 plane block into the 12×12 matrix; `flip` applies θy = −dw/dx.
fn scatter(out: &mut M12, blk: &[[f64; 4]; 4], dofs: [usize; 4], flip: bool) {
    let s = if flip {
        [1.0, -1.0, 1.0, -1.0]
    } else {
        [1.0; 4]
    };
    for a in 0..4 {
        for b in 0..4 {
            out[dofs[a]][dofs[b]] += s[a] * s[b] * blk[a][b];
        }
    }
}

fn scatter2(out: &mut M12, v: f64, a: usize, b: usize, diag: f64, off: f64) {
    out[a][a] += v * diag;
    out[b][b] += v * diag;
    out[a][b] += v * off;
    out[b][a] += v * off;
}

const XY: [usize; 4] = [1, 5, 7, 11];
const XZ: [usize; 4] = [2, 4, 8, 10];

/// Local stiffness matrix.
pub fn local_k(p: &BeamProps, l: f64) -> M12 {
    let mut k = [[0.0; 12]; 12];
    scatter2(&mut k, p.e * p.sec.area / l, 0, 6, 1.0, -1.0);
    scatter2(&mut k, p.g * p.sec.j / l, 3, 9, 1.0, -1.0);
    scatter(
        &mut k,
        &bend_k(p.e * p.sec.iz, phi(p, p.sec.iz, l), l),
        XY,
        false,
    );
    scatter(
        &mut k,
        &bend_k(p.e * p.sec.iy, phi(p, p.sec.iy, l), l),
        XZ,
        true,
    );
    k
}

/// Local consistent mass matrix.
pub fn local_m(p: &BeamProps, l: f64) -> M12 {
    let mut m = [[0.0; 12]; 12];
    let rho_a = p.rho * p.sec.area;
    scatter2(&mut m, rho_a * l / 6.0, 0, 6, 2.0, 1.0);
    scatter2(
        &mut m,
        p.rho * (p.sec.iy + p.sec.iz) * l / 6.0,
        3,
        9,
        2.0,
        1.0,
    );
    let rotary = p.theory == Theory::Timoshenko;
    scatter(
        &mut m,
        &bend_m(rho_a, p.rho * p.sec.iz, phi(p, p.sec.iz, l), l, rotary),
        XY,
        false,
    );
    scatter(
        &mut m,
        &bend_m(rho_a, p.rho * p.sec.iy, phi(p, p.sec.iy, l), l, rotary),
        XZ,
        true,
    );
    m
}

/// Local geometric stiffness for axial force `n` (tension positive).
pub fn local_kg(p: &BeamProps, n: f64, l: f64) -> M12 {
    let mut k = [[0.0; 12]; 12];
    let g = bend_kg(n, l);
    scatter(&mut k, &g, XY, false);
    scatter(&mut k, &g, XZ, true);
    scatter2(
        &mut k,
        n * (p.sec.iy + p.sec.iz) / (p.sec.area * l),
        3,
        9,
        1.0,
        -1.0,
    );
    k
}

/// Rows are the local x, y, z axes in global coordinates (OpenSees `vecxz` convention:
/// local z is the part of `orientation` perpendicular to the axis, local y = z × x).
pub fn rotation(a: [f64; 3], b: [f64; 3], orientation: [f64; 3]) -> [[f64; 3]; 3] {
    let x = axis(a, b);
    let o = Vector3::from(orientation);
    let z = (o - x * o.dot(&x)).normalize();
    let y = z.cross(&x);
    [x.into(), y.into(), z.into()]
}

/// Unit vector from `a` to `b`.
fn axis(a: [f64; 3], b: [f64; 3]) -> Vector3<f64> {
    (Vector3::from(b) - Vector3::from(a)).normalize()
}

/// Default orientation: global z, or global y for a member along z.
pub fn default_orientation(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let x = axis(a, b);
    if x[2].abs() > 0.999 {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Kglobal = Tᵀ·Klocal·T with T = diag(R, R, R, R).
pub fn to_global(kl: &M12, r: &[[f64; 3]; 3]) -> M12 {
    // tmp = Klocal·T
    let mut tmp = [[0.0; 12]; 12];
    for i in 0..12 {
        for bj in 0..4 {
            for c in 0..3 {
                let mut s = 0.0;
                for k in 0..3 {
                    s += kl[i][3 * bj + k] * r[k][c];
                }
                tmp[i][3 * bj + c] = s;
            }
        }
    }
    let mut out = [[0.0; 12]; 12];
    for bi in 0..4 {
        for c in 0..3 {
            for j in 0..12 {
                let mut s = 0.0;
                for k in 0..3 {
                    s += r[k][c] * tmp[3 * bi + k][j];
                }
                out[3 * bi + c][j] = s;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_torsion_constant() {
        // Timoshenko & Goodier: J = 0.1406·a⁴ for a square (k1 = 0.141 for b/a = 1).
        let j = rectangle_torsion(1.0, 1.0);
        assert!((j - 0.140577).abs() < 1e-5, "{j}");
    }

    #[test]
    fn rigid_translation_has_no_strain_energy() {
        let p = BeamProps {
            e: 210e9,
            g: 80e9,
            rho: 7850.0,
            sec: SectionProps {
                area: 4e-4,
                iy: 1.3e-8,
                iz: 1.3e-8,
                j: 2.2e-8,
                shear_factor: Some(0.85),
            },
            theory: Theory::Timoshenko,
        };
        let l = 0.7;
        let r = rotation([0.0; 3], [0.3, 0.5, 0.2], [0.0, 0.0, 1.0]);
        let kg = to_global(&local_k(&p, l), &r);
        let mut v = [0.0; 12];
        v[0] = 1.0;
        v[6] = 1.0;
        for row in kg.iter() {
            let f: f64 = row.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
            assert!(f.abs() < 1e-3, "translation produces force {f}");
        }
    }
}
