//! Load recovery: what a response analysis reports, each as a linear functional of the reduced
//! relative displacement (so the modal path and the direct path recover exactly the same
//! quantities).
//! - response points: the absolute acceleration of a node along the excitation axis;
//! - interfaces: the six internal force components k·(u₂ − u₁) of every spring (joint), and for
//!   a `[stack]` the preload each column joint carries (from the prestress summary);
//! - bar stations: axial force, torque and the two bending moments at each end of every
//!   guide-bar element (every beam element in a generic scene), from the element's elastic
//!   stiffness (the geometric-stiffness share of the end forces is of order N·θ, below 0.1 %
//!   of the bending moments here, and left out).
//!
//! Inputs: the scene (`spec`: stack, sections, materials, response points), the FE model
//! (`fem`) and the reduction and prestress of the modal system (`modal`).

use crate::error::{Error, ResponseError};
use crate::fem::beam;
use crate::fem::model::FeModel;
use crate::modal::ModalSystem;
use crate::spec::Scene;
use crate::spec::analysis::ResponsePoint;

/// A scalar transfer function: y = g·x (x = reduced relative displacement). Acceleration rows
/// report −ω²·g·x + rigid (absolute acceleration, rigid = 1 along the axis).
#[derive(Debug, Clone)]
pub struct Row {
    pub functional: Vec<(usize, f64)>,
    pub acceleration: bool,
}

#[derive(Debug, Clone)]
pub struct PointOut {
    pub name: String,
    pub node: i64,
    /// Row of the acceleration along x, y and z; the excitation axis picks one.
    pub rows: [usize; 3],
}

#[derive(Debug, Clone)]
pub struct InterfaceOut {
    pub name: String,
    /// Rows of Fx, Fy, Fz, Mx, My, Mz (global axes).
    pub rows: [usize; 6],
    /// Nominal preload compression carried by the joint, N (stack joints only).
    pub preload_n: Option<f64>,
    /// Area over section modulus of the joint face (column tube), 1/m: a bending moment M
    /// unloads the face edge as an axial tension M·A/Z would.
    pub face_a_over_z: f64,
    /// What carries the joint's shear beyond friction (stack joints only; empty otherwise).
    pub shear_paths: super::margins::ShearPaths,
}

#[derive(Debug, Clone)]
pub struct BarStation {
    /// Bar (member group) name, e.g. `bar 1`.
    pub bar: String,
    /// Station name, e.g. `bar 1 z=0.350 m`.
    pub name: String,
    pub position_m: [f64; 3],
    /// Rows of N, T, My, Mz (element local axes).
    pub rows: [usize; 4],
    pub area_m2: f64,
    /// Bending section modulus I/c, m³.
    pub section_modulus_m3: f64,
    /// Torsion: T·c/J, so this is J/c, m³.
    pub torsion_modulus_m3: f64,
    /// Static (prestress) axial force, tension positive, N.
    pub preload_axial_n: f64,
    pub yield_pa: Option<f64>,
    pub ultimate_pa: Option<f64>,
}

#[derive(Debug, Clone)]
pub struct OutputSet {
    pub rows: Vec<Row>,
    pub points: Vec<PointOut>,
    pub interfaces: Vec<InterfaceOut>,
    pub stations: Vec<BarStation>,
}

impl OutputSet {
    /// Builds every output of the scene.
    pub fn build(
        scene: &Scene,
        model: &FeModel,
        sys: &ModalSystem,
        points: &[ResponsePoint],
    ) -> Result<OutputSet, Error> {
        let red = &sys.reduction;
        let mut rows: Vec<Row> = Vec::new();
        let mut push = |f: Vec<(usize, f64)>, acc: bool| {
            rows.push(Row {
                functional: f,
                acceleration: acc,
            });
            rows.len() - 1
        };
        // Accumulates c·T[full] into a sparse functional.
        let add = |acc: &mut Vec<(usize, f64)>, full: usize, c: f64| {
            if c != 0.0 {
                for &(r, t) in &red.map[full] {
                    acc.push((r, c * t));
                }
            }
        };
        let node_index = |id: i64| model.nodes.iter().position(|n| n.id == Some(id));

        let mut pts = Vec::new();
        for p in points {
            let n = node_index(p.node).ok_or_else(|| {
                ResponseError::Invalid(format!(
                    "response point `{}` names node {}, which is not defined",
                    p.name, p.node
                ))
            })?;
            let mut r = [0; 3];
            for (a, slot) in r.iter_mut().enumerate() {
                let mut g = Vec::new();
                add(&mut g, 6 * n + a, 1.0);
                *slot = push(merge(g), true);
            }
            pts.push(PointOut {
                name: p.name.clone(),
                node: p.node,
                rows: r,
            });
        }

        let stack = scene.file.stack.as_ref();
        let prestress = sys.result.prestress.as_ref();
        let face_a_over_z = stack
            .map(|s| {
                let (d, di) = (s.column_outer_diameter_m, s.column_inner_diameter_m);
                let area = std::f64::consts::PI / 4.0 * (d * d - di * di);
                let z = std::f64::consts::PI / 32.0 * (d.powi(4) - di.powi(4)) / d;
                area / z
            })
            .unwrap_or(0.0);
        let shear_paths = stack
            .map(|s| super::margins::ShearPaths::of_stack(s, &scene.model.material))
            .unwrap_or_default();
        let mut ifs = Vec::new();
        for (si, s) in model.springs.iter().enumerate() {
            let name = model.spring_names[si].clone();
            if stack.is_some() && !name.starts_with("interface ") {
                continue;
            }
            let mut r = [0; 6];
            for (d, slot) in r.iter_mut().enumerate() {
                let mut g = Vec::new();
                add(&mut g, 6 * s.nodes[1] + d, s.k[d]);
                add(&mut g, 6 * s.nodes[0] + d, -s.k[d]);
                *slot = push(merge(g), false);
            }
            let preload_n = match (stack, prestress) {
                (Some(_), Some(ps)) => ps.springs.get(si).map(|f| -f.force_n[2]),
                (Some(st), None) => Some(st.preload_total_n / 4.0),
                _ => None,
            };
            ifs.push(InterfaceOut {
                name,
                rows: r,
                preload_n,
                face_a_over_z,
                shear_paths: shear_paths.clone(),
            });
        }

        let mut stations = Vec::new();
        let bar_group = |member: usize| -> Option<String> {
            let name = &model.member_names[member];
            if stack.is_some() {
                // "bar c segment j" and "bar c tip" belong to "bar c".
                let rest = name.strip_prefix("bar ")?;
                let c = rest.split(' ').next()?;
                Some(format!("bar {c}"))
            } else {
                Some(name.clone())
            }
        };
        let mut last_end: Option<(String, usize)> = None;
        for (e, b) in model.beams.iter().enumerate() {
            let Some(group) = bar_group(b.member) else {
                continue;
            };
            // Rows of k_local·T: local end forces from global end displacements.
            let kt = local_force_matrix(&b.props, b.length, &b.rot);
            let sb = &scene.model.beam[b.member];
            let sec = scene.model.section.iter().find(|s| s.name == sb.section);
            let mat = scene.model.material.iter().find(|m| m.name == sb.material);
            let c = sec.map(fiber_distance).unwrap_or(0.0);
            let (zb, zt) = if c > 0.0 {
                (b.props.sec.iy.min(b.props.sec.iz) / c, b.props.sec.j / c)
            } else {
                (f64::INFINITY, f64::INFINITY)
            };
            let axial = prestress
                .and_then(|p| p.element_axial_n.get(e).copied())
                .unwrap_or(0.0);
            let station = |end: usize, rows_out: &mut Vec<Row>| {
                // end 0: forces on the element at node a, reported as internal forces with the
                // sign of the b-end convention (N tension positive).
                let base = 6 * end;
                let sign = if end == 0 { -1.0 } else { 1.0 };
                let mut r = [0; 4];
                for (slot, local) in r.iter_mut().zip([0usize, 3, 4, 5]) {
                    let mut g = Vec::new();
                    for col in 0..12 {
                        let full = 6 * b.nodes[col / 6] + col % 6;
                        add(&mut g, full, sign * kt[base + local][col]);
                    }
                    rows_out.push(Row {
                        functional: merge(g),
                        acceleration: false,
                    });
                    *slot = rows_out.len() - 1;
                }
                let node = b.nodes[end];
                let x = model.nodes[node].x;
                BarStation {
                    bar: group.clone(),
                    name: format!("{group} z={:.3} m", x[2]),
                    position_m: x,
                    rows: r,
                    area_m2: b.props.sec.area,
                    section_modulus_m3: zb,
                    torsion_modulus_m3: zt,
                    preload_axial_n: axial,
                    yield_pa: mat.and_then(|m| m.yield_strength_pa),
                    ultimate_pa: mat.and_then(|m| m.ultimate_strength_pa),
                }
            };
            let continues = matches!(&last_end, Some((g, n)) if *g == group && *n == b.nodes[0]);
            if !continues {
                stations.push(station(0, &mut rows));
            }
            stations.push(station(1, &mut rows));
            last_end = Some((group.clone(), b.nodes[1]));
        }
        // Stack stations are named by height; a generic member may repeat a height.
        let mut seen = std::collections::HashMap::<String, usize>::new();
        for s in &mut stations {
            let k = seen.entry(s.name.clone()).or_insert(0);
            *k += 1;
            if *k > 1 {
                s.name = format!("{} #{}", s.name, k);
            }
        }
        Ok(OutputSet {
            rows,
            points: pts,
            interfaces: ifs,
            stations,
        })
    }

    /// Modal coefficients a[row][j] = g_row·ψ_j, row-major.
    pub fn modal_coefficients(&self, shapes: &[Vec<f64>]) -> Vec<f64> {
        let nb = shapes.len();
        let mut out = vec![0.0; self.rows.len() * nb];
        for (o, row) in self.rows.iter().enumerate() {
            for (j, s) in shapes.iter().enumerate() {
                out[o * nb + j] = row.functional.iter().map(|&(i, c)| c * s[i]).sum();
            }
        }
        out
    }
}

/// Sums duplicate indices of a sparse functional.
fn merge(mut g: Vec<(usize, f64)>) -> Vec<(usize, f64)> {
    g.sort_by_key(|x| x.0);
    let mut out: Vec<(usize, f64)> = Vec::with_capacity(g.len());
    for (i, v) in g {
        match out.last_mut() {
            Some(l) if l.0 == i => l.1 += v,
            _ => out.push((i, v)),
        }
    }
    out.retain(|x| x.1 != 0.0);
    out
}

/// k_local·T (12×12): local end forces of an element from its global end displacements.
fn local_force_matrix(p: &beam::BeamProps, l: f64, r: &[[f64; 3]; 3]) -> beam::M12 {
    let kl = beam::local_k(p, l);
    let mut out = [[0.0; 12]; 12];
    for i in 0..12 {
        for bj in 0..4 {
            for c in 0..3 {
                let mut s = 0.0;
                for k in 0..3 {
                    s += kl[i][3 * bj + k] * r[k][c];
                }
                out[i][3 * bj + c] = s;
            }
        }
    }
    out
}

/// Distance from the neutral axis to the outermost fibre.
fn fiber_distance(s: &crate::spec::Section) -> f64 {
    match s.shape.as_str() {
        "circle" => 0.5 * s.diameter_m.unwrap_or(0.0),
        "tube" => 0.5 * s.outer_diameter_m.unwrap_or(0.0),
        "rectangle" => {
            // Largest of the two planes' extreme fibres (bending about either axis).
            0.5 * s.width_m.unwrap_or(0.0).max(s.height_m.unwrap_or(0.0))
        }
        // A general section gives no fibre distance: that of the equivalent solid circle.
        _ => (s.area_m2.unwrap_or(0.0) / std::f64::consts::PI).sqrt(),
    }
}
