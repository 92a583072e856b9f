//! The modal basis of a base-driven response: the kept modes plus one residual vector per
//! excitation axis, their participation in the enforced base motion, and their damping.
//! Inputs: the FE model (`fem`) for the full mass matrix, and the modal system (`modal`) for
//! K (with K_G), M and the mass-normalised modes.
//!
//! Formulation (relative coordinates): every support moves with the table by the rigid
//! translation r·u_b along the axis. With u = u_rel + r·u_b and K·r = 0 (a rigid translation is
//! stress-free, K_G included, since it changes no length and no orientation), the free DOFs obey
//! M·ü_rel + C·u̇_rel + K·u_rel = −p·ü_b with p = Tᵀ·M_full·r_full: the inertia of the whole
//! structure, supported DOFs' mass coupling included. Per mode, q̈ + 2ζω·q̇ + ω²·q = −Γ·ü_b with
//! Γ = φᵀ·p.
//!
//! Residual vector (static correction of the truncated modes, as NASTRAN's RESVEC): the static
//! response to p, x = K⁻¹·p, made M-orthogonal to the kept modes and mass-normalised, enters the
//! basis as one more "mode" with its Rayleigh frequency ω² = ψᵀKψ. Because ψ is M- and
//! K-orthogonal to the kept modes, the augmented basis stays diagonal, and its static response
//! to p is exact (the quasi-static part of every truncated mode is recovered), for
//! accelerations and for forces alike.

use crate::error::{Error, ResponseError};
use crate::fem::model::{FeModel, dense};
use crate::modal::ModalSystem;
use crate::spec::analysis::DampingSpec;

/// The basis vectors of one axis, with what a modal sum needs.
#[derive(Debug, Clone)]
pub struct Basis {
    /// 0, 1, 2 = x, y, z.
    pub axis: usize,
    /// Reduced shapes (mass-normalised); the first `n_modes` are eigenmodes, the rest residual.
    pub shapes: Vec<Vec<f64>>,
    pub omega: Vec<f64>,
    pub zeta: Vec<f64>,
    /// Γ = ψᵀ·p.
    pub gamma: Vec<f64>,
    pub n_modes: usize,
}

impl Basis {
    pub fn len(&self) -> usize {
        self.shapes.len()
    }
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }
    pub fn frequency_hz(&self, j: usize) -> f64 {
        self.omega[j] / (2.0 * std::f64::consts::PI)
    }
    /// `(fn, ζ)` of the kept modes that the base motion excites: Γ² above 1e-9 of ΣΓ². Modes
    /// with a numerically zero participation (antisymmetric bar modes under a symmetric drive,
    /// say) show no peak, so a frequency grid need not cluster points around them.
    pub fn excited_modes(&self) -> Vec<(f64, f64)> {
        let total: f64 = self.gamma.iter().map(|g| g * g).sum();
        (0..self.n_modes)
            .filter(|&j| self.gamma[j] * self.gamma[j] > 1e-9 * total)
            .map(|j| (self.frequency_hz(j), self.zeta[j]))
            .collect()
    }

    /// Modal coordinates for a unit base acceleration (1 m/s²) at `f_hz`:
    /// q_j = −Γ_j / (ω_j² − ω² + 2iζ_jω_jω).
    pub fn coordinates(&self, f_hz: f64, out: &mut Vec<faer::c64>) {
        let w = 2.0 * std::f64::consts::PI * f_hz;
        out.clear();
        for j in 0..self.len() {
            let wj = self.omega[j];
            let re = wj * wj - w * w;
            let im = 2.0 * self.zeta[j] * wj * w;
            let d = re * re + im * im;
            // −Γ/(re + i·im) = −Γ·(re − i·im)/d
            out.push(faer::c64::new(
                -self.gamma[j] * re / d,
                self.gamma[j] * im / d,
            ));
        }
    }
}

/// Effective load vector p = Tᵀ·M_full·r of a unit base acceleration along `axis` (reduced DOFs).
pub fn influence_load(model: &FeModel, sys: &ModalSystem, axis: usize) -> Vec<f64> {
    let n_full = model.n_full();
    let mut mr = vec![0.0; n_full];
    for &(i, j, v) in &model.mass() {
        if j % 6 == axis {
            mr[i] += v;
        }
    }
    sys.reduction.reduce_vec(&mr)
}

/// Builds the basis for `axis` from the first `n_modes` modes of `sys` (all when `None`),
/// with a residual vector when `residual` is set.
pub fn build(
    model: &FeModel,
    sys: &ModalSystem,
    axis: usize,
    damping: &DampingSpec,
    n_modes: Option<usize>,
    residual: bool,
) -> Result<Basis, Error> {
    let n = sys.reduction.n_red;
    let modes = &sys.result.modes;
    let keep = n_modes.unwrap_or(modes.len()).min(modes.len());
    let p = influence_load(model, sys, axis);
    let mut shapes = Vec::with_capacity(keep + 1);
    let mut omega = Vec::with_capacity(keep + 1);
    let mut gamma = Vec::with_capacity(keep + 1);
    for m in &modes[..keep] {
        if m.eigenvalue <= 0.0 {
            return Err(ResponseError::Invalid(format!(
                "key `support`: mode {} has a non-positive eigenvalue ({:.3e} rad²/s², a rigid-body mode): the supports leave the model free to move, so it cannot be driven by them; hold every rigid-body direction with a [[support]]",
                m.index, m.eigenvalue
            ))
            .into());
        }
        shapes.push(m.shape.clone());
        omega.push(m.eigenvalue.sqrt());
        gamma.push(dot(&m.shape, &p));
    }
    if residual {
        let kd = dense(n, &sys.k);
        let x = crate::modal::dense::solve_spd(&kd, &p).map_err(|_| {
            ResponseError::Invalid(
                "key `support`: the stiffness matrix is not positive definite: the structure is not fully supported, so no static residual vector exists; hold every rigid-body direction with a [[support]]".into(),
            )
        })?;
        let mv = |v: &[f64]| -> Vec<f64> {
            let mut out = vec![0.0; n];
            for &(i, j, a) in &sys.m {
                out[i] += a * v[j];
            }
            out
        };
        let mut r = x.clone();
        // Two Gram–Schmidt passes against the kept modes (M inner product).
        for _ in 0..2 {
            let mr = mv(&r);
            for s in &shapes {
                let c = dot(s, &mr);
                r.iter_mut().zip(s).for_each(|(a, b)| *a -= c * b);
            }
        }
        let mr = mv(&r);
        let norm2 = dot(&r, &mr);
        let xnorm2 = dot(&x, &mv(&x));
        // Nothing left when the kept modes span the static response (e.g. all modes kept).
        if norm2 > 1e-16 * xnorm2 && norm2 > 0.0 {
            let s = 1.0 / norm2.sqrt();
            r.iter_mut().for_each(|a| *a *= s);
            let mut kr = vec![0.0; n];
            for &(i, j, a) in &sys.k {
                kr[i] += a * r[j];
            }
            let w2 = dot(&r, &kr);
            if w2 > 0.0 {
                omega.push(w2.sqrt());
                gamma.push(dot(&r, &p));
                shapes.push(r);
            }
        }
    }
    // Modes by their number; the residual vector (past the kept modes) takes the base ζ.
    let zeta = omega
        .iter()
        .enumerate()
        .map(|(j, w)| {
            let f = w / (2.0 * std::f64::consts::PI);
            match modes[..keep].get(j) {
                Some(m) => damping.zeta_of_mode(m.index, f),
                None => damping.zeta_at(f),
            }
        })
        .collect();
    Ok(Basis {
        axis,
        shapes,
        omega,
        zeta,
        gamma,
        n_modes: keep,
    })
}

pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
