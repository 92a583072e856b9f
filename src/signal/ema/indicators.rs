//! Mode-quality indicators of complex shape vectors: the modal assurance criterion between two
//! shapes, the modal phase collinearity (MPC) and the mean phase deviation (MPD) of one shape.
//! A real (normal) mode scores MPC = 1 and MPD = 0°; with a single channel both are trivially
//! perfect and say nothing.

use realfft::num_complex::Complex64;

/// MAC = |ψ₁ᴴψ₂|² / (ψ₁ᴴψ₁ · ψ₂ᴴψ₂) (Allemang & Brown, IMAC 1982); 0 for a zero vector.
pub fn mac(a: &[Complex64], b: &[Complex64]) -> f64 {
    let dot: Complex64 = a.iter().zip(b).map(|(x, y)| x.conj() * y).sum();
    let na: f64 = a.iter().map(|x| x.norm_sqr()).sum();
    let nb: f64 = b.iter().map(|x| x.norm_sqr()).sum();
    if na > 0.0 && nb > 0.0 {
        (dot.norm_sqr() / (na * nb)).min(1.0)
    } else {
        0.0
    }
}

/// The 2×2 covariance of the points (Re ψ, Im ψ) about the origin: (Sxx, Syy, Sxy).
fn covariance(v: &[Complex64]) -> (f64, f64, f64) {
    v.iter().fold((0.0, 0.0, 0.0), |(xx, yy, xy), z| {
        (xx + z.re * z.re, yy + z.im * z.im, xy + z.re * z.im)
    })
}

/// Eigenvalues (λ₁ ≥ λ₂) and the unit eigenvector of λ₁ of [[Sxx, Sxy], [Sxy, Syy]].
fn principal(v: &[Complex64]) -> (f64, f64, (f64, f64)) {
    let (xx, yy, xy) = covariance(v);
    let mean = 0.5 * (xx + yy);
    let rad = (0.25 * (xx - yy).powi(2) + xy * xy).sqrt();
    let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
    (mean + rad, mean - rad, (angle.cos(), angle.sin()))
}

/// MPC = ((λ₁ − λ₂)/(λ₁ + λ₂))², λ the eigenvalues of the covariance of (Re ψ, Im ψ): 1 when
/// every component lies on one line through the origin in the complex plane (Pappa, Elliott &
/// Schenk, "Consistent-mode indicator for the eigensystem realization algorithm", JGCD 1993,
/// in its eigenvalue form). 0 for a zero vector.
pub fn mpc(v: &[Complex64]) -> f64 {
    let (l1, l2, _) = principal(v);
    if l1 + l2 > 0.0 {
        ((l1 - l2) / (l1 + l2)).powi(2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// MPD: the magnitude-weighted mean angle, in degrees, between each component and the
/// principal line of the shape in the complex plane (0° for a real mode, 90° at most).
pub fn mpd_deg(v: &[Complex64]) -> f64 {
    let (_, _, (c, s)) = principal(v);
    let (mut num, mut den) = (0.0, 0.0);
    for z in v {
        let m = z.norm();
        if m > 0.0 {
            let cosang = ((z.re * c + z.im * s).abs() / m).min(1.0);
            num += m * cosang.acos();
            den += m;
        }
    }
    if den > 0.0 {
        (num / den).to_degrees()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    #[test]
    fn real_mode_rotated_is_collinear() {
        // A real shape times e^{j·0.7}: every component on one line; MPC 1, MPD 0 exactly
        // up to rounding (definition).
        let rot = Complex64::from_polar(1.0, 0.7);
        let v: Vec<_> = [1.0, -0.5, 0.25].iter().map(|&a| rot * a).collect();
        assert!((mpc(&v) - 1.0).abs() < 1e-12);
        assert!(mpd_deg(&v) < 1e-6);
        assert!((mac(&v, &[c(2.0, 0.0), c(-1.0, 0.0), c(0.5, 0.0)]) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn quadrature_components_are_not_collinear() {
        // Two equal components 90° apart: λ₁ = λ₂, so MPC = 0; each lies 45° off the
        // principal line, so MPD = 45° (geometry).
        let v = [c(1.0, 0.0), c(0.0, 1.0)];
        assert!(mpc(&v) < 1e-12);
        assert!((mpd_deg(&v) - 45.0).abs() < 1e-9);
        assert_eq!(mac(&v, &[c(0.0, 0.0), c(0.0, 0.0)]), 0.0);
    }
}
