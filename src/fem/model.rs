//! The assembled FE model: nodes (scene nodes plus beam interior nodes), elements, point
//! masses, springs, rigid links and supports, built from a validated generic model; global
//! K, M (and K_G) as triplets; and the reduction to independent DOFs.
//!
//! Rigid links are eliminated exactly (master–slave): a slave's translations follow
//! u_s = u_m + θ_m × (x_s − x_m) and its rotations equal the master's. Fixed DOFs are removed.
//! The reduction is a sparse map T (u_full = T·u_red), applied to triplets, so the dense and
//! the sparse solvers share one assembly.

use super::beam::{self, BeamProps, SectionProps};
use crate::error::FemError;
use crate::spec::{SceneFile, Theory};
use nalgebra::Vector3;
use std::collections::HashMap;

pub const DOF_NAMES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

#[derive(Debug, Clone)]
pub struct FeNode {
    /// Scene node id; `None` for nodes generated inside a subdivided beam.
    pub id: Option<i64>,
    pub label: String,
    pub x: [f64; 3],
}

#[derive(Debug, Clone)]
pub struct BeamElement {
    pub nodes: [usize; 2],
    /// Index of the `[[beam]]` member in the scene.
    pub member: usize,
    pub props: BeamProps,
    pub rot: [[f64; 3]; 3],
    pub length: f64,
}

#[derive(Debug, Clone)]
pub struct SpringElement {
    pub nodes: [usize; 2],
    pub k: [f64; 6],
    pub spec_index: usize,
}

/// A locked preloaded joint (see `spec::Preload`).
#[derive(Debug, Clone)]
pub struct PreloadElement {
    pub nodes: [usize; 2],
    pub k: [f64; 6],
    pub axis: usize,
    pub force: f64,
    pub name: String,
}

#[derive(Debug, Clone)]
pub struct FeModel {
    pub nodes: Vec<FeNode>,
    pub beams: Vec<BeamElement>,
    /// Node index and its 6×6 mass matrix (offset masses already transformed to the node).
    pub masses: Vec<(usize, [[f64; 6]; 6])>,
    pub springs: Vec<SpringElement>,
    pub preloads: Vec<PreloadElement>,
    /// Names of the scene's springs (or `spring[i]`).
    pub spring_names: Vec<String>,
    pub rigid: Vec<(usize, Vec<usize>)>,
    pub fixed: Vec<[bool; 6]>,
    /// Static load vector per node (forces then moments).
    pub loads: Vec<[f64; 6]>,
    /// Member names of the scene's beams (or `beam[i]`).
    pub member_names: Vec<String>,
}

/// Sparse symmetric matrix as (row, col, value) triplets; duplicates add.
pub type Triplets = Vec<(usize, usize, f64)>;

/// Map from the full DOF space (6 per node) to the reduced, independent DOFs.
#[derive(Debug, Clone)]
pub struct Reduction {
    pub n_full: usize,
    pub n_red: usize,
    /// For each full DOF, its expression in reduced DOFs.
    pub map: Vec<Vec<(usize, f64)>>,
    /// For each reduced DOF, the full DOF it stands for.
    pub red_to_full: Vec<usize>,
}

impl FeModel {
    pub fn from_scene(f: &SceneFile) -> Result<FeModel, FemError> {
        let mut nodes = Vec::new();
        let mut index: HashMap<i64, usize> = HashMap::new();
        for n in &f.node {
            index.insert(n.id, nodes.len());
            nodes.push(FeNode {
                id: Some(n.id),
                label: format!("node {}", n.id),
                x: n.position_m,
            });
        }
        let get = |id: i64| {
            index
                .get(&id)
                .copied()
                .ok_or_else(|| FemError::Invalid(format!("node {id} is not defined")))
        };
        let mut beams = Vec::new();
        let mut member_names = Vec::new();
        for (bi, b) in f.beam.iter().enumerate() {
            member_names.push(b.name.clone().unwrap_or_else(|| format!("beam[{bi}]")));
            let mat = f
                .material
                .iter()
                .find(|m| m.name == b.material)
                .ok_or_else(|| {
                    FemError::Invalid(format!("material `{}` is not defined", b.material))
                })?;
            let sec = f
                .section
                .iter()
                .find(|s| s.name == b.section)
                .ok_or_else(|| {
                    FemError::Invalid(format!("section `{}` is not defined", b.section))
                })?;
            let props = BeamProps {
                e: mat.youngs_modulus_pa,
                g: mat.shear_modulus_pa(),
                rho: mat.density_kg_m3,
                sec: SectionProps::from_spec(sec, mat.poisson_ratio),
                theory: b.theory,
            };
            let (a, c) = (get(b.nodes[0])?, get(b.nodes[1])?);
            let (xa, xc) = (nodes[a].x, nodes[c].x);
            let orient = b
                .orientation
                .unwrap_or_else(|| beam::default_orientation(xa, xc));
            let rot = beam::rotation(xa, xc, orient);
            let ne = b.elements;
            let mut chain = vec![a];
            for k in 1..ne {
                let t = k as f64 / ne as f64;
                let x = [
                    xa[0] + t * (xc[0] - xa[0]),
                    xa[1] + t * (xc[1] - xa[1]),
                    xa[2] + t * (xc[2] - xa[2]),
                ];
                chain.push(nodes.len());
                nodes.push(FeNode {
                    id: None,
                    label: format!("{} interior node {k}", member_names[bi]),
                    x,
                });
            }
            chain.push(c);
            let length = (Vector3::from(xc) - Vector3::from(xa)).norm() / ne as f64;
            for w in chain.windows(2) {
                beams.push(BeamElement {
                    nodes: [w[0], w[1]],
                    member: bi,
                    props,
                    rot,
                    length,
                });
            }
        }
        let mut masses = Vec::new();
        for m in &f.mass {
            masses.push((
                get(m.node)?,
                point_mass(m.mass_kg, m.inertia_kg_m2, m.offset_m),
            ));
        }
        let mut springs = Vec::new();
        let mut spring_names = Vec::new();
        for (i, s) in f.spring.iter().enumerate() {
            springs.push(SpringElement {
                nodes: [get(s.nodes[0])?, get(s.nodes[1])?],
                k: s.stiffness,
                spec_index: i,
            });
            spring_names.push(s.name.clone().unwrap_or_else(|| format!("spring[{i}]")));
        }
        let mut preloads = Vec::new();
        for (i, p) in f.preload.iter().enumerate() {
            let axis = p
                .axis_index()
                .ok_or_else(|| FemError::Invalid(format!("preload[{i}]: bad axis `{}`", p.axis)))?;
            preloads.push(PreloadElement {
                nodes: [get(p.nodes[0])?, get(p.nodes[1])?],
                k: p.stiffness,
                axis,
                force: p.force_n,
                name: p.name.clone().unwrap_or_else(|| format!("preload[{i}]")),
            });
        }
        let mut rigid = Vec::new();
        for r in &f.rigid {
            let slaves = r
                .slaves
                .iter()
                .map(|&s| get(s))
                .collect::<Result<Vec<_>, _>>()?;
            rigid.push((get(r.master)?, slaves));
        }
        let mut fixed = vec![[false; 6]; nodes.len()];
        for s in &f.support {
            let n = get(s.node)?;
            for d in s.dof_indices() {
                fixed[n][d] = true;
            }
        }
        let mut loads = vec![[0.0; 6]; nodes.len()];
        for p in &preloads {
            loads[p.nodes[0]][p.axis] += p.force;
            loads[p.nodes[1]][p.axis] -= p.force;
        }
        for l in &f.static_load {
            let n = get(l.node)?;
            for d in 0..3 {
                loads[n][d] += l.force_n[d];
                loads[n][3 + d] += l.moment_n_m[d];
            }
        }
        Ok(FeModel {
            nodes,
            beams,
            masses,
            springs,
            preloads,
            spring_names,
            rigid,
            fixed,
            loads,
            member_names,
        })
    }

    pub fn n_full(&self) -> usize {
        6 * self.nodes.len()
    }

    /// Human label of a full DOF: node label and DOF name.
    pub fn dof_label(&self, full: usize) -> (String, usize, &'static str) {
        (
            self.nodes[full / 6].label.clone(),
            full % 6 + 1,
            DOF_NAMES[full % 6],
        )
    }

    /// Global stiffness triplets in the full DOF space, preloaded joints locked.
    pub fn stiffness(&self) -> Triplets {
        self.stiffness_with(false)
    }

    /// Stiffness for the prestress solve: each preloaded joint cut along its axis.
    pub fn stiffness_prestress(&self) -> Triplets {
        self.stiffness_with(true)
    }

    fn stiffness_with(&self, cut: bool) -> Triplets {
        let mut t = Vec::with_capacity(self.beams.len() * 144 + self.springs.len() * 24);
        for b in &self.beams {
            let kg = beam::to_global(&beam::local_k(&b.props, b.length), &b.rot);
            scatter12(&mut t, &kg, b.nodes);
        }
        for s in &self.springs {
            for d in 0..6 {
                let k = s.k[d];
                if k != 0.0 {
                    let (i, j) = (6 * s.nodes[0] + d, 6 * s.nodes[1] + d);
                    t.extend([(i, i, k), (j, j, k), (i, j, -k), (j, i, -k)]);
                }
            }
        }
        for p in &self.preloads {
            for d in 0..6 {
                let k = if cut && d == p.axis { 0.0 } else { p.k[d] };
                if k != 0.0 {
                    let (i, j) = (6 * p.nodes[0] + d, 6 * p.nodes[1] + d);
                    t.extend([(i, i, k), (j, j, k), (i, j, -k), (j, i, -k)]);
                }
            }
        }
        t
    }

    /// Internal forces of the springs for a full displacement vector: k·(u₂ − u₁) per global
    /// component (positive = the second node moves away along +axis: tension for a joint whose
    /// second node lies above the first).
    pub fn spring_forces(&self, u: &[f64]) -> Vec<[f64; 6]> {
        self.springs
            .iter()
            .map(|s| {
                std::array::from_fn(|d| s.k[d] * (u[6 * s.nodes[1] + d] - u[6 * s.nodes[0] + d]))
            })
            .collect()
    }

    /// Global consistent mass triplets in the full DOF space.
    pub fn mass(&self) -> Triplets {
        let mut t = Vec::with_capacity(self.beams.len() * 144 + self.masses.len() * 36);
        for b in &self.beams {
            let mg = beam::to_global(&beam::local_m(&b.props, b.length), &b.rot);
            scatter12(&mut t, &mg, b.nodes);
        }
        for (n, m) in &self.masses {
            for a in 0..6 {
                for c in 0..6 {
                    if m[a][c] != 0.0 {
                        t.push((6 * n + a, 6 * n + c, m[a][c]));
                    }
                }
            }
        }
        t
    }

    /// Geometric stiffness for the given per-element axial forces (tension positive).
    pub fn geometric_stiffness(&self, axial: &[f64]) -> Triplets {
        let mut t = Vec::with_capacity(self.beams.len() * 144);
        for (b, &n) in self.beams.iter().zip(axial) {
            let kg = beam::to_global(&beam::local_kg(&b.props, n, b.length), &b.rot);
            scatter12(&mut t, &kg, b.nodes);
        }
        t
    }

    /// The full load vector.
    pub fn load_vector(&self) -> Vec<f64> {
        self.loads.iter().flatten().copied().collect()
    }

    /// Builds the master–slave and support reduction.
    pub fn reduction(&self) -> Result<Reduction, FemError> {
        let nn = self.nodes.len();
        let mut master_of: Vec<Option<usize>> = vec![None; nn];
        for (m, slaves) in &self.rigid {
            for &s in slaves {
                if master_of[s].is_some() {
                    return Err(FemError::RigidChain {
                        node: self.nodes[s].label.clone(),
                    });
                }
                master_of[s] = Some(*m);
            }
        }
        for (m, _) in &self.rigid {
            if master_of[*m].is_some() {
                return Err(FemError::RigidChain {
                    node: self.nodes[*m].label.clone(),
                });
            }
        }
        let n_full = 6 * nn;
        let mut red_index = vec![usize::MAX; n_full];
        let mut red_to_full = Vec::new();
        for n in 0..nn {
            if master_of[n].is_some() {
                continue;
            }
            for d in 0..6 {
                if !self.fixed[n][d] {
                    red_index[6 * n + d] = red_to_full.len();
                    red_to_full.push(6 * n + d);
                }
            }
        }
        let mut map = vec![Vec::new(); n_full];
        for n in 0..nn {
            match master_of[n] {
                None => {
                    for d in 0..6 {
                        let r = red_index[6 * n + d];
                        if r != usize::MAX {
                            map[6 * n + d].push((r, 1.0));
                        }
                    }
                }
                Some(m) => {
                    if self.fixed[n].iter().any(|&f| f) {
                        return Err(FemError::SupportedSlave {
                            node: self.nodes[n].label.clone(),
                            master: self.nodes[m].label.clone(),
                        });
                    }
                    let rv = [
                        self.nodes[n].x[0] - self.nodes[m].x[0],
                        self.nodes[n].x[1] - self.nodes[m].x[1],
                        self.nodes[n].x[2] - self.nodes[m].x[2],
                    ];
                    let mi = |d: usize| red_index[6 * m + d];
                    let mut push = |row: usize, col: usize, v: f64| {
                        if col != usize::MAX && v != 0.0 {
                            map[row].push((col, v));
                        }
                    };
                    let b = 6 * n;
                    // u_s = u_m + θ × r
                    push(b, mi(0), 1.0);
                    push(b, mi(4), rv[2]);
                    push(b, mi(5), -rv[1]);
                    push(b + 1, mi(1), 1.0);
                    push(b + 1, mi(5), rv[0]);
                    push(b + 1, mi(3), -rv[2]);
                    push(b + 2, mi(2), 1.0);
                    push(b + 2, mi(3), rv[1]);
                    push(b + 2, mi(4), -rv[0]);
                    for d in 3..6 {
                        push(b + d, mi(d), 1.0);
                    }
                }
            }
        }
        Ok(Reduction {
            n_full,
            n_red: red_to_full.len(),
            map,
            red_to_full,
        })
    }

    /// Rigid-body motion vectors in the full DOF space (6 columns: x, y, z translations and
    /// rotations about the axes through `about`).
    pub fn rigid_body_vectors(&self, about: [f64; 3]) -> Vec<[f64; 6]> {
        // rows: full dofs; columns: the 6 rigid motions
        let mut d = vec![[0.0; 6]; self.n_full()];
        for (n, node) in self.nodes.iter().enumerate() {
            let r = [
                node.x[0] - about[0],
                node.x[1] - about[1],
                node.x[2] - about[2],
            ];
            let b = 6 * n;
            for k in 0..3 {
                d[b + k][k] = 1.0;
                d[b + 3 + k][3 + k] = 1.0;
            }
            // u = θ × r for unit θ about x, y, z
            d[b + 1][3] = -r[2];
            d[b + 2][3] = r[1];
            d[b][4] = r[2];
            d[b + 2][4] = -r[0];
            d[b][5] = -r[1];
            d[b + 1][5] = r[0];
        }
        d
    }

    /// How many independent rigid-body motions the supports and constraints leave free: the
    /// motions that the reduction reproduces exactly (zero on supported DOFs, consistent with
    /// every `[[rigid]]` link). A model has no more rigid-body modes than this; more zero
    /// modes are mechanisms or flexible modes lost to round-off.
    pub fn free_rigid_motions(&self, red: &Reduction) -> usize {
        let d = self.rigid_body_vectors([0.0; 3]);
        // Violation of each rigid motion by the reduction: d − expand(d on reduced DOFs).
        let mut gram = nalgebra::Matrix6::<f64>::zeros();
        let mut norms = [0.0f64; 6];
        for (f, expr) in red.map.iter().enumerate() {
            let mut v = d[f];
            for &(r, c) in expr {
                let dr = d[red.red_to_full[r]];
                for a in 0..6 {
                    v[a] -= c * dr[a];
                }
            }
            for a in 0..6 {
                norms[a] += d[f][a] * d[f][a];
                for b in 0..6 {
                    gram[(a, b)] += v[a] * v[b];
                }
            }
        }
        // Scaled to unit motions, so that metres of lever arm and radians weigh alike.
        for a in 0..6 {
            for b in 0..6 {
                gram[(a, b)] /= (norms[a] * norms[b]).sqrt().max(f64::MIN_POSITIVE);
            }
        }
        let eig = nalgebra::SymmetricEigen::new(gram);
        eig.eigenvalues.iter().filter(|&&l| l < 1e-12).count()
    }

    /// Total mass and centre of mass from the full mass matrix (includes offset masses and the
    /// mass on supported DOFs).
    pub fn mass_properties(&self, m_full: &Triplets) -> (f64, [f64; 3]) {
        let d0 = self.rigid_body_vectors([0.0; 3]);
        // total mass = dxᵀ M dx; first moments from rotations: (dxᵀ M d_ry) etc.
        let mut mass = 0.0;
        let mut s = [[0.0; 6]; 6];
        for &(i, j, v) in m_full {
            for a in 0..6 {
                if d0[i][a] == 0.0 {
                    continue;
                }
                for b in 0..6 {
                    s[a][b] += d0[i][a] * v * d0[j][b];
                }
            }
        }
        mass += s[0][0];
        if mass <= 0.0 {
            return (0.0, [0.0; 3]);
        }
        // Translation x couples to rotation about y by m·z and about z by −m·y.
        let z = s[0][4] / mass;
        let y = -s[0][5] / mass;
        let x = s[1][5] / mass;
        (mass, [x, y, z])
    }
}

/// 6×6 rigid mass matrix at a node for a mass at `offset` with principal inertia `inertia`
/// about its own centre: M = Tᵀ·m·T + diag(0, J) with T = [I, −[r]×].
pub fn point_mass(m: f64, inertia: [f64; 3], r: [f64; 3]) -> [[f64; 6]; 6] {
    let rx = [[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]];
    let mut out = [[0.0; 6]; 6];
    for i in 0..3 {
        out[i][i] = m;
        out[3 + i][3 + i] = inertia[i];
        for j in 0..3 {
            // upper-right: −m[r]×; lower-left: m[r]× ... (symmetric: ([r]×)ᵀ = −[r]×)
            out[i][3 + j] = -m * rx[i][j];
            out[3 + j][i] = -m * rx[i][j];
            let mut rr = 0.0;
            for k in 0..3 {
                rr += rx[k][i] * rx[k][j];
            }
            out[3 + i][3 + j] += m * rr;
        }
    }
    out
}

fn scatter12(t: &mut Triplets, k: &beam::M12, nodes: [usize; 2]) {
    for a in 0..12 {
        let ga = 6 * nodes[a / 6] + a % 6;
        for b in 0..12 {
            let v = k[a][b];
            if v != 0.0 {
                t.push((ga, 6 * nodes[b / 6] + b % 6, v));
            }
        }
    }
}

impl Reduction {
    /// Reduces full-space triplets: K_r = Tᵀ·K·T.
    pub fn reduce(&self, full: &Triplets) -> Triplets {
        let mut out = Vec::with_capacity(full.len());
        for &(i, j, v) in full {
            for &(a, ta) in &self.map[i] {
                for &(b, tb) in &self.map[j] {
                    out.push((a, b, ta * v * tb));
                }
            }
        }
        out
    }

    /// Reduces a full-space vector (a load): F_r = Tᵀ·F.
    pub fn reduce_vec(&self, full: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n_red];
        for (i, &v) in full.iter().enumerate() {
            for &(a, ta) in &self.map[i] {
                out[a] += ta * v;
            }
        }
        out
    }

    /// The full DOF behind each reduced DOF.
    pub fn reduction_dofs(&self) -> &[usize] {
        &self.red_to_full
    }

    /// Expands a reduced vector to the full space: u = T·u_r.
    pub fn expand(&self, red: &[f64]) -> Vec<f64> {
        self.map
            .iter()
            .map(|row| row.iter().map(|&(a, t)| t * red[a]).sum())
            .collect()
    }
}

/// Dense matrix from triplets.
pub fn dense(n: usize, t: &Triplets) -> faer::Mat<f64> {
    let mut m = faer::Mat::<f64>::zeros(n, n);
    for &(i, j, v) in t {
        m[(i, j)] += v;
    }
    m
}

/// Theory is part of the model summary; re-exported for callers that label results.
pub fn theory_name(t: Theory) -> &'static str {
    match t {
        Theory::Timoshenko => "timoshenko",
        Theory::EulerBernoulli => "euler-bernoulli",
    }
}
