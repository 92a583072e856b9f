//! Modal analysis of an assembled FE model: prestress (static solve -> axial forces -> K_G),
//! the linear buckling factor, the eigen-solve, and the modal quantities an engineer reads:
//! frequencies, mass-normalised shapes with a fixed sign, participation factors and effective
//! masses for the six rigid-body directions about the model's centre of mass.
//! Input: a `fem::FeModel`. Small models go to the dense solvers (`dense`), large ones to the
//! sparse ones (`sparse`: LDLᵀ, shift-invert block Lanczos with a Sturm-count proof); see
//! [`auto_prefers_sparse`] for how `SolverChoice::Auto` chooses.

mod by_class;
pub mod checks;
pub mod correlation;
pub mod dense;
mod mirrors;
pub mod sparse;
pub mod updating;

use crate::error::{FemError, ModalError};
use crate::fem::model::{FeModel, Reduction, Triplets, dense as to_dense};
use crate::spec::SolverChoice;
use serde::Serialize;

/// Cost model of `SolverChoice::Auto`, measured with `satqual bench modal` on the 2-core
/// development machine (its crossover table in reports/bench/modal.md: generated frame towers of
/// 492–2214 DOFs asking for the lowest tenth of their modes, at most 100).
///
/// The dense solver always computes every mode: t ≈ [`DENSE_S_PER_DOF3`]·n³ (1.5e-10 s on the
/// 1476- and 2214-DOF towers, 3.2e-10 on the 492-DOF one where the fixed costs show; the
/// stacks' 2.7–3.5e-10 include their dense buckling solve).
pub const DENSE_S_PER_DOF3: f64 = 2.0e-10;
/// The dense path's work on the modes it keeps (M-orthonormalisation by Gram–Schmidt and the
/// residual checks, ∝ n·k²) adds [`DENSE_S_PER_DOF_MODE2`]·n·k: negligible for the towers'
/// 100 modes, but on the 6-satellite stack at 2 kHz (692 DOFs, 300 kept) it is most of the
/// dense time (0.116 and 0.222 s measured in two bench runs against 0.066 s for the n³ term:
/// 0.8e-9 and 2.5e-9 s per DOF·mode²).
pub const DENSE_S_PER_DOF_MODE2: f64 = 1.5e-9;
/// The sparse solver's cost grows with the modes it must find: t ≈ [`SPARSE_S_PER_DOF_MODE`]
/// ·n·max(k, [`SPARSE_MIN_MODES`]) (towers: 2.6–2.8e-7 s per DOF and mode at 100 modes, 5.4e-7
/// at 49; the 1440-DOF tower asking for 12 modes took 0.02–0.03 s, as for about 50 modes: a
/// Lanczos run never has fewer than a few blocks of vectors).
pub const SPARSE_S_PER_DOF_MODE: f64 = 3.5e-7;
pub const SPARSE_MIN_MODES: usize = 50;
/// Up to this many reduced DOFs `Auto` uses the dense solver whatever the request: it costs a
/// few milliseconds there (2e-10·300³ ≈ 5 ms), returns every mode with its rigid-body and
/// conditioning checks, and needs no Sturm proof. It keeps the verification scenes (≤ 240
/// DOFs) and the 2-satellite shaker model (284) on the path their goldens were made with.
pub const AUTO_DENSE_DOFS: usize = 300;
/// Up to this many reduced DOFs `Auto` solves a model past its buckling load densely (see
/// `analyze`): the cost model's count cannot see its negative modes.
pub const AUTO_UNSTABLE_DENSE_DOFS: usize = 1500;

/// Whether `Auto` takes the sparse path for `k` modes of an n-DOF model: when its modelled
/// cost is below the dense one's. On the 6-satellite stack at 2 kHz (692 DOFs, 300 modes) the
/// sparse path is modelled at 0.073 s against 0.16 s dense (measured 0.08–0.12 s sparse,
/// 0.12–0.22 s dense).
pub fn auto_prefers_sparse(n: usize, k: usize) -> bool {
    let (nf, kf) = (n as f64, k as f64);
    let sparse = SPARSE_S_PER_DOF_MODE * nf * kf.max(SPARSE_MIN_MODES as f64);
    let dense = DENSE_S_PER_DOF3 * nf.powi(3) + DENSE_S_PER_DOF_MODE2 * nf * kf * kf;
    n > AUTO_DENSE_DOFS && sparse < dense
}

/// What to extract.
#[derive(Debug, Clone, Default)]
pub struct ModalOptions {
    pub fmax_hz: Option<f64>,
    pub modes: Option<usize>,
    pub solver: SolverChoice,
    /// Refuse a prestress above the buckling load right after the buckling solve, with
    /// [`ModalError::BeyondBuckling`], instead of extracting the modes of an unstable
    /// structure first (the open-bore 120-satellite stack spent ~20 s on 5476 of them).
    pub stop_beyond_buckling: bool,
    /// Keep the mode shapes, or only what the modes sum up.
    pub shapes: Shapes,
}

/// Six rigid-body directions, in the order x, y, z, rx, ry, rz.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Default)]
pub struct Dir6 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub rx: f64,
    pub ry: f64,
    pub rz: f64,
}

impl Dir6 {
    pub fn from_array(a: [f64; 6]) -> Dir6 {
        Dir6 {
            x: a[0],
            y: a[1],
            z: a[2],
            rx: a[3],
            ry: a[4],
            rz: a[5],
        }
    }
    pub fn to_array(self) -> [f64; 6] {
        [self.x, self.y, self.z, self.rx, self.ry, self.rz]
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Mode {
    /// 1-based.
    pub index: usize,
    pub frequency_hz: f64,
    /// Γ = φᵀ·M·D for the rigid-body vectors D about the centre of mass.
    pub participation: Dir6,
    /// Γ² (kg for translations, kg·m² for rotations).
    pub effective_mass: Dir6,
    /// Γ² over the total mass (translations) or total inertia about the CM (rotations).
    pub effective_mass_fraction: Dir6,
    /// A rigid-body (or mechanism) mode: λ zero to round-off, reported at 0 Hz.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub rigid_body: bool,
    /// Mass-normalised shape over the reduced DOFs; the largest component is positive.
    #[serde(skip)]
    pub shape: Vec<f64>,
    #[serde(skip)]
    pub eigenvalue: f64,
}

impl Mode {
    /// The direction (x, y, z, rx, ry, rz) of the mode's largest effective-mass fraction;
    /// `None` for a mode that moves no mass along any of them (a mechanism).
    pub fn dominant_direction(&self) -> Option<&'static str> {
        let frac = self.effective_mass_fraction.to_array();
        let best = (0..6).fold(0, |b, a| if frac[a] > frac[b] { a } else { b });
        (frac[best] > 0.0).then_some(crate::spec::analysis::MODE_DIRECTIONS[best])
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct MemberForce {
    pub name: String,
    /// Axial force at the member's first element, tension positive, N.
    pub axial_force_n: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct SpringForce {
    pub name: String,
    /// N in x, y, z; N·m about x, y, z. Negative axial = compression of a joint whose second
    /// node is above its first.
    pub force_n: [f64; 6],
}

#[derive(Debug, Clone, Serialize)]
pub struct PrestressSummary {
    /// Smallest λ with (K + λ·K_G)·φ = 0: the static loads may be multiplied by λ before the
    /// structure buckles. `None` when the prestress does not destabilise it.
    pub buckling_factor: Option<f64>,
    /// The model the factor was taken on, when not the modes' own (a finer column mesh).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buckling_model: Option<String>,
    pub members: Vec<MemberForce>,
    /// Internal forces of the springs (joints), k·(u₂ − u₁) per global component.
    pub springs: Vec<SpringForce>,
    /// Axial force of every element, tension positive, N.
    #[serde(skip)]
    pub element_axial_n: Vec<f64>,
    /// Static displacement in the full DOF space.
    #[serde(skip)]
    pub displacement: Vec<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ModalResult {
    pub total_mass_kg: f64,
    pub center_of_mass_m: [f64; 3],
    /// Diagonal of Dᵀ·M·D over the free DOFs: what the effective masses of all modes sum to.
    pub rigid_body_mass: Dir6,
    /// Diagonal of Dᵀ·M·D over all DOFs (supported ones included).
    pub total_rigid_body_mass: Dir6,
    pub dofs: usize,
    pub solver: String,
    pub modes: Vec<Mode>,
    /// How many of the modes are rigid-body modes (0 Hz): an unsupported or partly supported
    /// model, or a mechanism.
    #[serde(skip_serializing_if = "is_zero")]
    pub rigid_body_modes: usize,
    /// The direction (x, y, z, rx, ry, rz) each rigid-body mode moves in most, by effective
    /// mass; `none` for a mechanism that moves no mass along any of them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub rigid_body_directions: Vec<String>,
    /// Rigid-body motions the supports leave free: zero modes beyond these are mechanisms or
    /// round-off, and a warning says so.
    #[serde(skip)]
    pub free_rigid_motions: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub prestress: Option<PrestressSummary>,
    /// What the dense solver did (shift, MAXRATIO, backward error); absent for the sparse one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dense: Option<checks::DenseStats>,
    /// Numerical warnings (poor conditioning, modes not solved to working precision).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// What the sparse solver did (Sturm count and its shift, factorizations, backward
    /// error); absent for the dense solver.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sparse: Option<sparse::SparseStats>,
}

/// The pieces of a modal solve that later analyses (response, load recovery) reuse.
#[derive(Debug, Clone)]
pub struct ModalSystem {
    pub reduction: Reduction,
    /// Reduced stiffness including K_G when prestressed.
    pub k: Triplets,
    pub m: Triplets,
    pub result: ModalResult,
}

/// The failed pivot `index` of a factorization of M (`massless`) or of K − σM, as its node and DOF.
fn dof_err(model: &FeModel, red: &Reduction, index: usize, massless: bool) -> FemError {
    let (node, dof, dof_name) = model.dof_label(red.red_to_full[index]);
    if massless {
        FemError::MasslessDof {
            node,
            dof,
            dof_name,
            mass: 0.0,
            largest: 0.0,
        }
    } else {
        FemError::Unconstrained {
            node,
            dof,
            dof_name,
        }
    }
}

/// Runs the prestress and the eigen-solve.
pub fn analyze(model: &FeModel, opts: &ModalOptions) -> Result<ModalSystem, crate::Error> {
    let red = model.reduction()?;
    if red.n_red == 0 {
        return Err(FemError::NoFreeDofs.into());
    }
    let k_full = model.stiffness();
    let m_full = model.mass();
    let k0 = red.reduce(&k_full);
    let m = red.reduce(&m_full);
    check_every_dof_has_mass(model, &red, &m)?;
    let use_sparse = use_sparse_solver(opts, red.n_red, (&k0, &m))?;

    let loads = model.load_vector();
    let prestressed = loads.iter().any(|&f| f != 0.0);
    let mut k = k0.clone();
    let mut prestress = None;
    if prestressed {
        let (summary, kg) = solve_prestress(model, &red, &k0, &loads, use_sparse, opts)?;
        k.extend(kg);
        prestress = Some(summary);
    }
    // Past buckling (a caller that opted out of stopping) K + K_G has negative eigenvalues
    // that the count taken for the cost model could not see, and the sparse solver must first
    // find a shift below all of them: `Auto` keeps such a model dense up to
    // AUTO_UNSTABLE_DENSE_DOFS, as it was before the cost model.
    let unstable = prestress
        .as_ref()
        .and_then(|p| p.buckling_factor)
        .is_some_and(|f| f < 1.0);
    let use_sparse = use_sparse
        && !(unstable
            && matches!(opts.solver, SolverChoice::Auto)
            && red.n_red <= AUTO_UNSTABLE_DENSE_DOFS);
    let result = if use_sparse {
        sparse_modes(model, &red, &m_full, (&k, &m), opts, prestress)?
    } else {
        dense_modes(model, &red, &m_full, (&k, &m), opts, prestress)?
    };
    Ok(ModalSystem {
        reduction: red,
        k,
        m,
        result,
    })
}

/// A DOF with no mass at all cannot be in a generalized eigenproblem with positive M.
fn check_every_dof_has_mass(
    model: &FeModel,
    red: &Reduction,
    m: &Triplets,
) -> Result<(), crate::Error> {
    let mut diag = vec![0.0; red.n_red];
    for &(i, j, v) in m {
        if i == j {
            diag[i] += v;
        }
    }
    let scale = diag.iter().copied().fold(0.0, f64::max);
    if let Some(i) = diag.iter().position(|&d| d <= 1e-14 * scale) {
        let (node, dof, dof_name) = model.dof_label(red.red_to_full[i]);
        return Err(FemError::MasslessDof {
            node,
            dof,
            dof_name,
            mass: diag[i],
            largest: scale,
        }
        .into());
    }
    Ok(())
}

/// Whether the request goes to the sparse solver, which needs a bounded band of modes.
fn use_sparse_solver(
    opts: &ModalOptions,
    n_red: usize,
    (k0, m): (&Triplets, &Triplets),
) -> Result<bool, crate::Error> {
    let use_sparse = match opts.solver {
        SolverChoice::Dense => false,
        SolverChoice::Sparse => true,
        // "All modes" is a dense job; a bounded request goes where the cost model says.
        SolverChoice::Auto if n_red <= AUTO_DENSE_DOFS => false,
        SolverChoice::Auto => match requested_modes(opts, n_red, (k0, m)) {
            Some(k) => auto_prefers_sparse(n_red, k),
            None => false,
        },
    };
    if use_sparse && opts.fmax_hz.is_none() && opts.modes.is_none() {
        return Err(ModalError::Invalid(format!(
            "the sparse solver needs [modal] fmax_hz or modes (or --fmax / --modes): it extracts a band of modes, not all {n_red} of this model; use solver = \"dense\" for all of them"
        ))
        .into());
    }
    Ok(use_sparse)
}

/// How many modes a bounded request asks for: `modes`, or the Sturm count of the unstressed
/// stiffness at (2π·fmax)² (one sparse LDLᵀ, a millisecond next to either solve; the prestress
/// moves the count a little, which the cost model does not need). `None` for "all modes", or
/// when the count cannot be taken (the solver chosen then reports the problem itself).
fn requested_modes(
    opts: &ModalOptions,
    n: usize,
    (k0, m): (&Triplets, &Triplets),
) -> Option<usize> {
    let counted = opts.fmax_hz.and_then(|f| {
        let kc = sparse::SymCsc::from_triplets(n, k0);
        let mc = sparse::SymCsc::from_triplets(n, m);
        let pencil = sparse::Pencil::new(&kc, Some(&mc)).ok()?;
        let lmax = (2.0 * std::f64::consts::PI * f).powi(2);
        pencil.factor(lmax).ok().map(|fac| fac.negative)
    });
    match (opts.modes, opts.fmax_hz) {
        (Some(k), None) => Some(k),
        (Some(k), Some(_)) => Some(counted.map_or(k, |c| c.min(k))),
        (None, Some(_)) => Some(counted.unwrap_or(n)),
        (None, None) => None,
    }
}

/// A sparse-solver failure in the model's terms: a pivot becomes the node and DOF it sits on.
fn sparse_err(
    model: &FeModel,
    red: &Reduction,
    e: sparse::SparseError,
    massless: bool,
) -> crate::Error {
    match e {
        sparse::SparseError::NotPositiveDefinite { index } => {
            dof_err(model, red, index, massless).into()
        }
        sparse::SparseError::SingularNear {
            sigma,
            index,
            relative_pivot,
        } => ModalError::NoConvergence(format!(
            "K − σM stays singular near σ = {sigma:e} rad²/s²: the pivot of {} keeps {relative_pivot:.1e} of its diagonal entry, \
             below round-off; the stiffness has lost its digits there: a mechanism, a spring many decades stiffer than its \
             neighbours (use [[rigid]]), or elements far shorter than their section (a mesh finer than double precision resolves: use fewer elements)",
            checks::dof_name(model, red, index)
        ))
        .into(),
        sparse::SparseError::Modal(m) => m.into(),
    }
}

/// A dense-solver failure in the model's terms; `what` names the solve that did not converge.
fn dense_err(
    model: &FeModel,
    red: &Reduction,
    e: dense::DenseError,
    massless: bool,
    what: &str,
) -> crate::Error {
    match e {
        dense::DenseError::NotPositiveDefinite { index } => {
            crate::Error::from(dof_err(model, red, index, massless))
        }
        dense::DenseError::NoConvergence => ModalError::NoConvergence(what.into()).into(),
    }
}

/// The prestress: the static solve, the element axial forces and K_G from them, the buckling
/// factor, and the member and joint forces. Returns the summary and the reduced K_G.
fn solve_prestress(
    model: &FeModel,
    red: &Reduction,
    k0: &Triplets,
    loads: &[f64],
    use_sparse: bool,
    opts: &ModalOptions,
) -> Result<(PrestressSummary, Triplets), crate::Error> {
    let (u, axial, kg) = static_state(model, red, loads, use_sparse)?;
    let lambda = buckling(model, red, k0, &kg, use_sparse)?;
    refuse_beyond_buckling(lambda, opts)?;
    let mut members: Vec<MemberForce> = Vec::new();
    for (e, b) in model.beams.iter().enumerate() {
        if members.len() <= b.member {
            members.push(MemberForce {
                name: model.member_names[b.member].clone(),
                axial_force_n: axial[e],
            });
        }
    }
    let springs = model
        .spring_forces(&u)
        .into_iter()
        .zip(&model.spring_names)
        .map(|(f, name)| SpringForce {
            name: name.clone(),
            force_n: f,
        })
        .collect();
    let summary = PrestressSummary {
        buckling_factor: lambda,
        buckling_model: None,
        members,
        springs,
        element_axial_n: axial,
        displacement: u,
    };
    Ok((summary, kg))
}

/// The buckling factor of a model under its static loads alone (no modes): the static
/// solve, the geometric stiffness of its axial forces and the buckling eigenproblem, on the
/// sparse path above `AUTO_DENSE_DOFS`. `None` when the loads do not destabilise it (or it
/// has none).
pub fn buckling_factor_of(model: &FeModel) -> Result<Option<f64>, crate::Error> {
    let red = model.reduction()?;
    let loads = model.load_vector();
    if red.n_red == 0 || loads.iter().all(|&f| f == 0.0) {
        return Ok(None);
    }
    let use_sparse = red.n_red > AUTO_DENSE_DOFS;
    let k0 = red.reduce(&model.stiffness());
    let (_, _, kg) = static_state(model, &red, &loads, use_sparse)?;
    buckling(model, &red, &k0, &kg, use_sparse)
}

/// The static state under the loads: the displacement (full DOF space), the element axial
/// forces, and the reduced geometric stiffness K_G they make.
fn static_state(
    model: &FeModel,
    red: &Reduction,
    loads: &[f64],
    use_sparse: bool,
) -> Result<(Vec<f64>, Vec<f64>, Triplets), crate::Error> {
    let u = red.expand(&static_displacement(model, red, loads, use_sparse)?);
    let axial = element_axial_forces(model, &u);
    let kg = red.reduce(&model.geometric_stiffness(&axial));
    Ok((u, axial, kg))
}

/// [`ModalError::BeyondBuckling`] for a buckling factor below 1 when `opts` asks to stop there.
pub fn refuse_beyond_buckling(
    factor: Option<f64>,
    opts: &ModalOptions,
) -> Result<(), crate::Error> {
    match factor {
        Some(f) if opts.stop_beyond_buckling && f < 1.0 => {
            Err(ModalError::BeyondBuckling { factor: f }.into())
        }
        _ => Ok(()),
    }
}

/// The reduced static displacement under the loads. The static solve cuts the preloaded
/// joints, so the preload loops carry exactly the preload; buckling and modes use the locked
/// stiffness.
fn static_displacement(
    model: &FeModel,
    red: &Reduction,
    loads: &[f64],
    use_sparse: bool,
) -> Result<Vec<f64>, crate::Error> {
    let ks = red.reduce(&model.stiffness_prestress());
    let f = red.reduce_vec(loads);
    if use_sparse {
        let kc = sparse::SymCsc::from_triplets(red.n_red, &ks);
        sparse::solve_spd(&kc, &f).map_err(|e| sparse_err(model, red, e, false))
    } else {
        let ksd = to_dense(red.n_red, &ks);
        dense::solve_spd(&ksd, &f).map_err(|e| dense_err(model, red, e, false, "static solve"))
    }
}

/// The buckling factor of (K + λ·K_G)·φ = 0 on the locked stiffness K.
fn buckling(
    model: &FeModel,
    red: &Reduction,
    k0: &Triplets,
    kg: &Triplets,
    use_sparse: bool,
) -> Result<Option<f64>, crate::Error> {
    if use_sparse {
        sparse::buckling_factor(
            &sparse::SymCsc::from_triplets(red.n_red, k0),
            &sparse::SymCsc::from_triplets(red.n_red, kg),
        )
        .map_err(|e| sparse_err(model, red, e, false))
    } else {
        let kd = to_dense(red.n_red, k0);
        let kgd = to_dense(red.n_red, kg);
        dense::buckling_factor(&kd, &kgd)
            .map_err(|_| ModalError::NoConvergence("buckling".into()).into())
    }
}

/// The modes of the band asked for by the sparse solver, with its Sturm proof in the label,
/// checked and flagged as the dense path's are.
fn sparse_modes(
    model: &FeModel,
    red: &Reduction,
    m_full: &Triplets,
    (k, m): (&Triplets, &Triplets),
    opts: &ModalOptions,
    prestress: Option<PrestressSummary>,
) -> Result<ModalResult, crate::Error> {
    let n = red.n_red;
    let kc = sparse::SymCsc::from_triplets(n, k);
    let mc = sparse::SymCsc::from_triplets(n, m);
    let basis = ModeBasis::new(model, red, m_full, m);
    // A band of modes (not the lowest N, which could all lie in one class) of a model with
    // mirror planes is solved class by class.
    let mirrors = (opts.modes.is_none() && opts.fmax_hz.is_some())
        .then(|| mirrors::find_mirrors(model, red, &kc, &mc))
        .flatten();
    let solved = match &mirrors {
        Some(mr) => by_class::solve_by_class(mr, (k, m), (&kc, &mc), &basis, opts),
        None => solve_whole(n, (k, m), (&kc, &mc), &basis, opts),
    };
    let (checked, modes, mut stats) = solved.map_err(|e| sparse_err(model, red, e, true))?;
    let two_pi = 2.0 * std::f64::consts::PI;
    let label = format!(
        "sparse (shift-invert block Lanczos on faer LDLᵀ{}; Sturm count {} below {:.6} Hz)",
        if mirrors.is_some() {
            ", by mirror-symmetry class"
        } else {
            ""
        },
        stats.sturm_count,
        stats.sturm_sigma.max(0.0).sqrt() / two_pi
    );
    let lambdas = modes.iter().map(|md| md.eigenvalue);
    let (rigid, worst) = check_pairs(model, &checked, lambdas, past_buckling(&prestress))?;
    let mut result = basis.result(red, modes, &label, prestress);
    let (max_ratio, at) = flag_solution(model, red, &mut result, rigid, &stats.pivot_ratio, worst);
    stats.max_ratio = max_ratio;
    stats.max_ratio_at = checks::dof_name(model, red, at);
    result.sparse = Some(stats);
    Ok(result)
}

/// The sparse eigen-solve of the whole model. Each band's modes are checked, polished and
/// measured on the band's thread as soon as it is solved: repeated modes never straddle a
/// band cut (cuts sit in gaps of the spectrum), and no more than the bands in flight hold
/// their eigenvectors when the shapes are dropped.
fn solve_whole(
    n: usize,
    (k, m): (&Triplets, &Triplets),
    (kc, mc): (&sparse::SymCsc, &sparse::SymCsc),
    basis: &ModeBasis,
    opts: &ModalOptions,
) -> Result<(Vec<checks::PairCheck>, Vec<Mode>, sparse::SparseStats), sparse::SparseError> {
    let checker = checks::PairChecker::new(n, (k, m));
    let finish = |band: sparse::FinishedBand, st: &mut sparse::SparseStats| {
        let sparse::FinishedBand { offset, mut pairs } = band;
        // The sparse eigenvalues are Rayleigh quotients: no shift enters their rounding.
        let mut checked = checker.check(&pairs, 0.0);
        polish_unconverged(&checker, (kc, mc), &mut pairs, &mut checked, st)?;
        set_zero_modes(&checked, &mut pairs);
        Ok((checked, basis.modes(pairs, offset, opts.shapes)))
    };
    let (bands, stats) = sparse::eigen_by_band(kc, mc, opts.fmax_hz, opts.modes, &finish)?;
    let (checked, modes): (Vec<_>, Vec<_>) = bands.into_iter().unzip();
    Ok((
        checked.into_iter().flatten().collect(),
        modes.into_iter().flatten().collect(),
        stats,
    ))
}

/// A round-off zero becomes exactly 0, before the modes are aligned: the rigid-body modes
/// then form one cluster and get aligned with the axes.
fn set_zero_modes(checked: &[checks::PairCheck], pairs: &mut [(f64, Vec<f64>)]) {
    for ((lambda, _), c) in pairs.iter_mut().zip(checked) {
        if c.zero {
            *lambda = 0.0;
        }
    }
}

/// Whether the preload is past buckling (a caller that opted out of stopping): the negative
/// modes are then the result, not an error.
fn past_buckling(prestress: &Option<PrestressSummary>) -> bool {
    prestress
        .as_ref()
        .and_then(|p| p.buckling_factor)
        .is_some_and(|f| f < 1.0)
}

/// Every mode by the dense solver, then the ones asked for (`modes`, `fmax_hz`) kept, each
/// checked against its residual; rigid-body modes set to 0 Hz and counted.
fn dense_modes(
    model: &FeModel,
    red: &Reduction,
    m_full: &Triplets,
    (k, m): (&Triplets, &Triplets),
    opts: &ModalOptions,
    prestress: Option<PrestressSummary>,
) -> Result<ModalResult, crate::Error> {
    let kd = to_dense(red.n_red, k);
    let md = to_dense(red.n_red, m);
    let g = dense::generalized(&kd, &md)
        .map_err(|e| dense_err(model, red, e, false, "dense eigen-solve"))?;
    let keep = dense_kept(&g.lambda, opts);
    let mut shapes: Vec<(f64, Vec<f64>)> = (0..keep)
        .map(|c| (g.lambda[c], (0..red.n_red).map(|r| g.phi[(r, c)]).collect()))
        .collect();
    m_orthonormalize(m, &mut shapes);
    let checked = checks::PairChecker::new(red.n_red, (k, m)).check(&shapes, g.shift.abs());
    set_zero_modes(&checked, &mut shapes);
    let lambdas = shapes.iter().map(|p| p.0);
    let (rigid, worst) = check_pairs(model, &checked, lambdas, past_buckling(&prestress))?;
    let basis = ModeBasis::new(model, red, m_full, m);
    let modes = basis.modes(shapes, 0, opts.shapes);
    let solver = "dense (faer self-adjoint eigen, shift-invert)";
    let mut result = basis.result(red, modes, solver, prestress);
    let (max_ratio, at) = flag_solution(model, red, &mut result, rigid, &g.pivot_ratio, worst);
    result.dense = Some(checks::DenseStats {
        shift: g.shift,
        max_ratio,
        max_ratio_at: checks::dof_name(model, red, at),
        max_backward_error: worst.0,
    });
    Ok(result)
}

/// What either solver's checked pairs say about the result: the `rigid` zero modes marked,
/// and warnings for a poorly conditioned stiffness (MAXRATIO over the pivot ratios of K − σM
/// below the spectrum) and for pairs not solved to working precision (`worst` backward error
/// and its mode). Returns MAXRATIO and its reduced DOF.
fn flag_solution(
    model: &FeModel,
    red: &Reduction,
    result: &mut ModalResult,
    rigid: usize,
    pivot_ratio: &[f64],
    worst: (f64, usize),
) -> (f64, usize) {
    mark_rigid_body(result, rigid);
    let free = model.free_rigid_motions(red);
    result.free_rigid_motions = free;
    if rigid > free {
        result
            .warnings
            .push(not_rigid_warning(model, result, rigid, free));
    }
    let (max_ratio, at) = checks::max_ratio(pivot_ratio, rigid);
    if max_ratio > checks::MAX_PIVOT_RATIO {
        let w = checks::conditioning_warning(model, red, max_ratio, at);
        result.warnings.push(w);
    }
    // A pivot that kept fewer digits than the zero test allows means the "rigid-body" modes
    // may be flexible modes drowned by a stiffness beyond double precision: say so.
    let (raw_ratio, raw_at) = checks::max_ratio(pivot_ratio, 0);
    if rigid > 0 && raw_ratio > checks::LOST_PIVOT_RATIO {
        let w = checks::conditioning_warning(model, red, raw_ratio, raw_at);
        result.warnings.push(format!(
            "the {rigid} zero-frequency modes may be an artefact: {w}"
        ));
    }
    if worst.0 > checks::MAX_BACKWARD_ERROR {
        result.warnings.push(format!(
            "modes not solved to working precision: backward error up to {:.2e} (> {:.0e}), worst at mode {} ({:.6e} Hz)",
            worst.0,
            checks::MAX_BACKWARD_ERROR,
            worst.1 + 1,
            result.modes[worst.1].frequency_hz
        ));
    }
    (max_ratio, at)
}

/// How many of the ascending eigenvalues the options keep.
fn dense_kept(lambda: &[f64], opts: &ModalOptions) -> usize {
    let mut keep = lambda.len();
    if let Some(n) = opts.modes {
        keep = keep.min(n);
    }
    if let Some(fmax) = opts.fmax_hz {
        let lmax = (2.0 * std::f64::consts::PI * fmax).powi(2);
        keep = keep.min(lambda.iter().take_while(|&&l| l <= lmax).count());
    }
    keep
}

/// Relative spread of the eigenvalues of one cluster of repeated modes.
const CLUSTER_SPREAD: f64 = 1e-6;

/// The modes above the backward-error threshold, each with the cluster of repeated modes it
/// belongs to, polished whole (inverse iteration and Rayleigh–Ritz, `sparse::polish`): the
/// Lanczos runs accept vectors on a residual estimate that can miss by the conditioning of the
/// shift far from it. The cluster is the pairs within [`CLUSTER_SPREAD`] of the flagged one;
/// a pair whose λ is itself that far off is taken with the pairs within the wider
/// [`POLISH_WINDOWS`] in turn, until a polished block is kept ([`Block::polish`]); `checked`
/// follows the pairs.
fn polish_unconverged(
    checker: &checks::PairChecker,
    (kc, mc): (&sparse::SymCsc, &sparse::SymCsc),
    pairs: &mut [(f64, Vec<f64>)],
    checked: &mut [checks::PairCheck],
    stats: &mut sparse::SparseStats,
) -> Result<(), sparse::SparseError> {
    let flagged = |c: &checks::PairCheck, lambda: f64| {
        lambda > 0.0 && !c.zero && c.backward_error > checks::MAX_BACKWARD_ERROR
    };
    if !(checked.iter().zip(pairs.iter())).any(|(c, p)| flagged(c, p.0)) {
        return Ok(());
    }
    let pencil = sparse::Pencil::new(kc, Some(mc))?;
    let block = Block {
        pencil: &pencil,
        csc: (kc, mc),
        checker,
    };
    let mut i = 0;
    while i < pairs.len() {
        if !flagged(&checked[i], pairs[i].0) {
            i += 1;
            continue;
        }
        let mut end = i + 1;
        for spread in POLISH_WINDOWS {
            let near = |j: usize| (pairs[j].0 - pairs[i].0).abs() <= spread * pairs[i].0;
            let start = (0..i).rev().take_while(|&j| near(j)).last().unwrap_or(i);
            end = (i..pairs.len())
                .take_while(|&j| near(j))
                .last()
                .unwrap_or(i)
                + 1;
            if block.polish(pairs, checked, start..end, stats) {
                break;
            }
        }
        i = end;
    }
    Ok(())
}

/// Relative widths of the windows a flagged pair's block is taken from, in turn: its cluster
/// of repeated modes ([`CLUSTER_SPREAD`]), then wider, for a pair whose λ is itself off by
/// more than the cluster's spread (seen: 4e-6 at a 60-satellite stack's near-rigid joints).
const POLISH_WINDOWS: [f64; 3] = [CLUSTER_SPREAD, 1e-5, 1e-4];

/// What polishing a block needs: the pencil for its shifts and counts, the solver's matrices,
/// and the triplets the independent check reads.
struct Block<'a> {
    pencil: &'a sparse::Pencil,
    csc: (&'a sparse::SymCsc, &'a sparse::SymCsc),
    checker: &'a checks::PairChecker,
}

impl Block<'_> {
    /// Polishes `pairs[range]`; keeps the result (and its checks) only when its worst check
    /// improves and its eigenvalues either stayed within [`POLISH_MAX_SHIFT`] or are proven
    /// by [`counted_whole`]. Returns whether it was kept; a block that cannot be polished (a
    /// shift that stays singular) keeps its pairs, and the check flags them as before.
    fn polish(
        &self,
        pairs: &mut [(f64, Vec<f64>)],
        checked: &mut [checks::PairCheck],
        range: std::ops::Range<usize>,
        stats: &mut sparse::SparseStats,
    ) -> bool {
        let worst =
            |c: &[checks::PairCheck]| c.iter().map(|c| c.backward_error).fold(0.0, f64::max);
        let (kc, mc) = self.csc;
        let old: Vec<(f64, Vec<f64>)> = pairs[range.clone()].to_vec();
        let polished =
            sparse::polish::polish_cluster(self.pencil, kc, mc, pairs, range.clone(), stats);
        if polished.is_err() {
            pairs[range].clone_from_slice(&old);
            return false;
        }
        let again = self.checker.check(&pairs[range.clone()], 0.0);
        let stayed = (old.iter().zip(&pairs[range.clone()]))
            .all(|(o, p)| (p.0 - o.0).abs() <= POLISH_MAX_SHIFT * o.0);
        let kept = worst(&again) < worst(&checked[range.clone()])
            && (stayed || counted_whole(self.pencil, &old, &pairs[range.clone()], stats));
        if kept {
            for (c, a) in checked[range].iter_mut().zip(again) {
                *c = a;
            }
        } else {
            pairs[range].clone_from_slice(&old);
        }
        kept
    }
}

/// Largest relative move of an eigenvalue by polishing taken without further proof: its
/// vector's improvement changes λ at second order. A larger move (a cluster whose Lanczos
/// values were off, as on a stack with near-rigid joints) is kept only when
/// [`counted_whole`] proves the block is still the same eigenvalues.
const POLISH_MAX_SHIFT: f64 = 1e-8;

/// Whether Sturm counts put exactly as many eigenvalues in the span of the block's old and
/// polished values (widened by [`CLUSTER_SPREAD`]) as the block holds: then the polished
/// pairs, each with a residual at round-off, are those eigenvalues and no neighbour's.
fn counted_whole(
    pencil: &sparse::Pencil,
    old: &[(f64, Vec<f64>)],
    polished: &[(f64, Vec<f64>)],
    stats: &mut sparse::SparseStats,
) -> bool {
    let values = || old.iter().chain(polished).map(|p| p.0);
    let lo = values().fold(f64::INFINITY, f64::min) * (1.0 - CLUSTER_SPREAD);
    let hi = values().fold(f64::NEG_INFINITY, f64::max) * (1.0 + CLUSTER_SPREAD);
    stats.factorizations += 2;
    match (pencil.factor(lo), pencil.factor(hi)) {
        (Ok(a), Ok(b)) => b.negative.checked_sub(a.negative) == Some(old.len()),
        _ => false,
    }
}

/// Checks every kept pair (its zeros already set by [`set_zero_modes`]): a negative λ beyond
/// round-off is an error. Returns the number of zeros and the largest backward error with
/// its mode index.
fn check_pairs(
    model: &FeModel,
    checked: &[checks::PairCheck],
    lambdas: impl Iterator<Item = f64>,
    unstable: bool,
) -> Result<(usize, (f64, usize)), crate::Error> {
    let mut rigid = 0;
    let mut worst = (0.0f64, 0);
    for (i, (lambda, c)) in lambdas.zip(checked).enumerate() {
        if c.backward_error > worst.0 {
            worst = (c.backward_error, i);
        }
        if c.zero {
            rigid += 1;
        } else if lambda < 0.0 && !unstable {
            let f = (-lambda).sqrt() / (2.0 * std::f64::consts::PI);
            return Err(ModalError::Invalid(format!(
                "mode {} has a negative eigenvalue ({:.6e} rad²/s², an imaginary frequency of {f:.4} Hz) beyond round-off: the stiffness of {} is not positive semi-definite",
                i + 1,
                lambda,
                model_name(model)
            ))
            .into());
        }
    }
    Ok((rigid, worst))
}

/// Modified Gram–Schmidt (twice) of the kept shapes in the M inner product, lowest first: the
/// shift-invert shapes are M-orthonormal only to ε·cond(K − σM) (3.8e-10 on NAFEMS FV4's
/// rigid arm), the modal superposition downstream assumes ΦᵀMΦ = I to round-off. Within one
/// eigenvalue this is a rotation of the eigenspace; across eigenvalues it moves each shape by
/// that loss of orthogonality.
fn m_orthonormalize(m: &Triplets, shapes: &mut [(f64, Vec<f64>)]) {
    let n = shapes.first().map_or(0, |s| s.1.len());
    let mul = |v: &[f64]| {
        let mut y = vec![0.0; n];
        for &(i, j, a) in m {
            y[i] += a * v[j];
        }
        y
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut mphi: Vec<Vec<f64>> = Vec::with_capacity(shapes.len());
    for j in 0..shapes.len() {
        let mut v = std::mem::take(&mut shapes[j].1);
        for _ in 0..2 {
            for (i, w) in mphi.iter().enumerate() {
                let c = dot(w, &v);
                v.iter_mut()
                    .zip(&shapes[i].1)
                    .for_each(|(x, p)| *x -= c * p);
            }
        }
        let mut w = mul(&v);
        // A shape projected to nothing would be a repeated vector; left as it is rather than
        // divided by zero.
        let norm = dot(&v, &w).sqrt();
        let norm = if norm > 0.0 { norm } else { 1.0 };
        v.iter_mut().for_each(|x| *x /= norm);
        w.iter_mut().for_each(|x| *x /= norm);
        shapes[j].1 = v;
        mphi.push(w);
    }
}

fn model_name(model: &FeModel) -> String {
    format!("the model ({} nodes)", model.nodes.len())
}

/// The warning for zero-frequency modes beyond the rigid-body motions the supports leave
/// free: a part or DOF nothing stiffens, or flexible modes whose stiffness is below the
/// round-off of K (a mesh so fine that φᵀKφ cancels to noise).
fn not_rigid_warning(model: &FeModel, result: &ModalResult, rigid: usize, free: usize) -> String {
    format!(
        "{} of the {rigid} zero-frequency modes are not rigid-body motions of {} (its supports leave {free} free): either a mechanism (a node or part that nothing stiffens in some direction) or flexible modes whose stiffness is lost to round-off in K, as on a mesh far finer than its section (elements much shorter than the section depth); check the supports and connections, or use fewer elements",
        rigid - free,
        model_name(model),
    ) + &result
        .modes
        .get(rigid)
        .map(|m| format!(" (first non-zero mode {:.4} Hz)", m.frequency_hz))
        .unwrap_or_default()
}

/// Flags the first `rigid` modes (λ = 0 sorts first) and names their directions.
fn mark_rigid_body(result: &mut ModalResult, rigid: usize) {
    result.rigid_body_modes = rigid;
    for mode in result.modes.iter_mut().take(rigid) {
        mode.rigid_body = true;
        mode.frequency_hz = 0.0;
        let name = mode.dominant_direction().unwrap_or("none");
        result.rigid_body_directions.push(name.to_string());
    }
}

/// Axial force of every beam element from a full displacement vector (tension positive).
pub fn element_axial_forces(model: &FeModel, u: &[f64]) -> Vec<f64> {
    model
        .beams
        .iter()
        .map(|b| {
            let (a, c) = (6 * b.nodes[0], 6 * b.nodes[1]);
            let du = [u[c] - u[a], u[c + 1] - u[a + 1], u[c + 2] - u[a + 2]];
            let ex = b.rot[0];
            b.props.e * b.props.sec.area / b.length
                * (ex[0] * du[0] + ex[1] * du[1] + ex[2] * du[2])
        })
        .collect()
}

/// Whether the modes keep their shapes (the response analyses read them) or only what they
/// sum up (frequencies, participations): an n × modes block is 1.3 GB on the 200-satellite
/// stack, which `satqual modal` never reads.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Shapes {
    #[default]
    Keep,
    Drop,
}

/// The rigid-body quantities every mode is measured against (mass properties, M·D over the
/// reduced DOFs, the rigid-body masses the effective masses sum to), and from them the
/// modes' frequencies, sign convention and effective masses.
struct ModeBasis {
    total_mass: f64,
    cm: [f64; 3],
    md: Vec<[f64; 6]>,
    rb: [f64; 6],
    rb_total: [f64; 6],
}

impl ModeBasis {
    fn new(model: &FeModel, red: &Reduction, m_full: &Triplets, m_red: &Triplets) -> Self {
        let (total_mass, cm) = model.mass_properties(m_full);
        let d_full = model.rigid_body_vectors(cm);
        let (md, rb, rb_total) = rigid_body_masses(red, m_full, m_red, &d_full);
        ModeBasis {
            total_mass,
            cm,
            md,
            rb,
            rb_total,
        }
    }

    /// The modes `offset..` of a run of pairs (λ ascending): repeated ones aligned, then
    /// each signed and measured.
    fn modes(&self, pairs: Vec<(f64, Vec<f64>)>, offset: usize, shapes: Shapes) -> Vec<Mode> {
        let pairs = align_degenerate(pairs, &self.md, &self.rb_total);
        use rayon::prelude::*;
        // Per mode and independent, so in parallel (2772 modes of 6200 DOFs on the
        // 60-satellite stack); the collected order is the input order whatever the thread
        // count.
        pairs
            .into_par_iter()
            .enumerate()
            .map(|(idx, (lambda, shape))| {
                let mut mode = mode(offset + idx, lambda, shape, &self.md, &self.rb_total);
                if shapes == Shapes::Drop {
                    mode.shape = Vec::new();
                }
                mode
            })
            .collect()
    }

    fn result(
        &self,
        red: &Reduction,
        modes: Vec<Mode>,
        solver: &str,
        prestress: Option<PrestressSummary>,
    ) -> ModalResult {
        ModalResult {
            total_mass_kg: self.total_mass,
            center_of_mass_m: self.cm,
            rigid_body_mass: Dir6::from_array(self.rb),
            total_rigid_body_mass: Dir6::from_array(self.rb_total),
            dofs: red.n_red,
            solver: solver.to_string(),
            modes,
            rigid_body_modes: 0,
            rigid_body_directions: Vec::new(),
            free_rigid_motions: 6,
            prestress,
            dense: None,
            warnings: Vec::new(),
            sparse: None,
        }
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// M·D over the reduced DOFs (D: the rigid-body vectors about the centre of mass), and the
/// diagonal of Dᵀ·M·D over the free DOFs and over all DOFs.
fn rigid_body_masses(
    red: &Reduction,
    m_full: &Triplets,
    m_red: &Triplets,
    d_full: &[[f64; 6]],
) -> (Vec<[f64; 6]>, [f64; 6], [f64; 6]) {
    let d_red: Vec<[f64; 6]> = red.red_to_full.iter().map(|&f| d_full[f]).collect();
    let mut md = vec![[0.0; 6]; red.n_red];
    for &(i, j, v) in m_red {
        for a in 0..6 {
            md[i][a] += v * d_red[j][a];
        }
    }
    let mut rb = [0.0; 6];
    for i in 0..red.n_red {
        for a in 0..6 {
            rb[a] += d_red[i][a] * md[i][a];
        }
    }
    let mut rb_total = [0.0; 6];
    for &(i, j, v) in m_full {
        for a in 0..6 {
            rb_total[a] += d_full[i][a] * v * d_full[j][a];
        }
    }
    (md, rb, rb_total)
}

/// Relative difference below which two components of a shape are a tie for its sign.
const SIGN_TIE: f64 = 1e-6;

/// Mode `idx` (0-based) of eigenvalue `lambda`: its sign fixed, frequency, participation
/// factors and effective masses.
fn mode(
    idx: usize,
    lambda: f64,
    mut shape: Vec<f64>,
    md: &[[f64; 6]],
    rb_total: &[f64; 6],
) -> Mode {
    let two_pi = 2.0 * std::f64::consts::PI;
    // Sign convention: the largest-magnitude component (first one on ties) is positive. A
    // tie is within SIGN_TIE, far above the solvers' vector accuracy (VECTOR_TOL, 1e-9), so
    // that round-off cannot flip the sign of a symmetric mode whose two largest components
    // mirror each other.
    let mut imax = 0;
    for (i, v) in shape.iter().enumerate() {
        if v.abs() > shape[imax].abs() * (1.0 + SIGN_TIE) {
            imax = i;
        }
    }
    if shape[imax] < 0.0 {
        shape.iter_mut().for_each(|v| *v = -*v);
    }
    let mut gamma = [0.0; 6];
    for (i, s) in shape.iter().enumerate() {
        for a in 0..6 {
            gamma[a] += s * md[i][a];
        }
    }
    let eff = gamma.map(|g| g * g);
    let frac: [f64; 6] = std::array::from_fn(|a| {
        if rb_total[a] > 0.0 {
            eff[a] / rb_total[a]
        } else {
            0.0
        }
    });
    let f = lambda.signum() * lambda.abs().sqrt() / two_pi;
    Mode {
        index: idx + 1,
        frequency_hz: f,
        participation: Dir6::from_array(gamma),
        effective_mass: Dir6::from_array(eff),
        effective_mass_fraction: Dir6::from_array(frac),
        rigid_body: false,
        shape,
        eigenvalue: lambda,
    }
}

/// Within each cluster of (numerically) repeated eigenvalues the eigenvectors are any
/// orthonormal basis of the eigenspace; the solver's choice mixes, say, the y and z bending of
/// a square bar. Rotate each cluster so that its first mode takes all the participation in x,
/// the next in y, and so on (Gram–Schmidt on the participation columns): the report then reads
/// "mode 1: y, mode 2: z". An orthogonal rotation keeps the shapes M-orthonormal.
///
/// A cluster whose participation is round-off in every direction (effective-mass fraction of
/// the whole cluster ≤ 1e-12 of `rb_total`) has nothing to align: any basis of it reports the
/// same zero effective masses. It is left as the solver returned it; on the 60-satellite
/// stack that skips the 295-fold column-joint cluster (fraction ~1e-20), whose rotation alone
/// took 0.12 s.
fn align_degenerate(
    mut pairs: Vec<(f64, Vec<f64>)>,
    md: &[[f64; 6]],
    rb_total: &[f64; 6],
) -> Vec<(f64, Vec<f64>)> {
    let mut start = 0;
    while start < pairs.len() {
        let l0 = pairs[start].0;
        let mut end = start + 1;
        while end < pairs.len() && (pairs[end].0 - l0).abs() <= 1e-7 * l0.abs().max(1e-6) {
            end += 1;
        }
        if end - start > 1 {
            align_cluster(&mut pairs[start..end], md, rb_total);
        }
        start = end;
    }
    pairs
}

/// Rotates one cluster of repeated eigenvalues so that its participation is sorted by
/// direction (see [`align_degenerate`]); a cluster with no participation is left alone.
fn align_cluster(cluster: &mut [(f64, Vec<f64>)], md: &[[f64; 6]], rb_total: &[f64; 6]) {
    let k = cluster.len();
    // Γ[i][a] for the cluster's modes.
    let gamma: Vec<[f64; 6]> = cluster
        .iter()
        .map(|(_, shape)| {
            let mut g = [0.0; 6];
            for (i, s) in shape.iter().enumerate() {
                for a in 0..6 {
                    g[a] += s * md[i][a];
                }
            }
            g
        })
        .collect();
    let negligible =
        (0..6).all(|a| gamma.iter().map(|g| g[a] * g[a]).sum::<f64>() <= 1e-12 * rb_total[a]);
    if negligible {
        return;
    }
    let q = participation_basis(&gamma);
    // New shapes = old shapes · Qᵀ, as one matrix product (clusters of a few hundred
    // repeated local modes make this k²·n).
    let dofs = cluster[0].1.len();
    let old = faer::Mat::<f64>::from_fn(dofs, k, |r, i| cluster[i].1[r]);
    let qt = faer::Mat::<f64>::from_fn(k, q.len(), |i, j| q[j][i]);
    let mut new = faer::Mat::<f64>::zeros(dofs, q.len());
    faer::linalg::matmul::matmul(
        new.as_mut(),
        faer::Accum::Replace,
        old.as_ref(),
        qt.as_ref(),
        1.0,
        faer::Par::Seq,
    );
    for j in 0..q.len() {
        let col = new.col(j);
        cluster[j].1 = (0..dofs).map(|r| col[r]).collect();
    }
}

/// An orthonormal basis of the cluster's k-space: Gram–Schmidt (twice) on the participation
/// columns x, y, z, rx, ry, rz first, then the unit vectors to complete it.
fn participation_basis(gamma: &[[f64; 6]]) -> Vec<Vec<f64>> {
    let k = gamma.len();
    let gnorm: f64 = gamma
        .iter()
        .flat_map(|g| g.iter())
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt();
    let mut q: Vec<Vec<f64>> = Vec::new();
    let candidates = (0..6)
        .map(|a| (0..k).map(|i| gamma[i][a]).collect::<Vec<f64>>())
        .chain((0..k).map(|i| (0..k).map(|j| if i == j { 1.0 } else { 0.0 }).collect()));
    for mut v in candidates {
        if q.len() == k {
            break;
        }
        for _ in 0..2 {
            for b in &q {
                let d: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= d * y);
            }
        }
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 1e-6 * gnorm.max(1e-300) && n > 1e-8 {
            q.push(v.into_iter().map(|x| x / n).collect());
        }
    }
    q
}

#[cfg(test)]
mod sign_tests {
    use super::mode;

    /// A symmetric mode's two largest components mirror each other; the solver's round-off
    /// (VECTOR_TOL, 1e-9 relative) must not decide its sign. Within SIGN_TIE they tie and the
    /// first one is made positive, whichever of the two came out larger; a component larger
    /// by 1e-3 wins.
    #[test]
    fn round_off_does_not_flip_the_sign_of_a_mirrored_mode() {
        let md = vec![[0.0; 6]; 3];
        let rb = [1.0; 6];
        for tiny in [-1e-9, 0.0, 1e-9] {
            let m = mode(0, 1.0, vec![-0.5, 0.5 * (1.0 + tiny), 0.1], &md, &rb);
            assert!(
                m.shape[0] > 0.0 && m.shape[1] < 0.0,
                "{tiny}: {:?}",
                m.shape
            );
        }
        let m = mode(0, 1.0, vec![-0.5, 0.5 * (1.0 + 1e-3), 0.1], &md, &rb);
        assert!(m.shape[1] > 0.0 && m.shape[0] < 0.0, "{:?}", m.shape);
    }
}
