//! Mirror planes of the model, proposed from its geometry and proven on its matrices: the
//! sparse solver then solves each symmetry class on its own (`sparse::symmetry`).
//!
//! A plane normal to a coordinate axis through the middle of the nodes' bounding box is a
//! candidate when every node has a node at its mirror point. Nodes that share a position (a
//! bar node and the bore node it is sprung to) are paired in index order; a wrong pairing is
//! no risk, since the proof on K and M then fails and the model is solved whole.

use super::sparse::SymCsc;
use super::sparse::symmetry::{SignedPerm, SymmetryClass, symmetry_classes};
use crate::fem::model::{FeModel, Reduction};
use std::collections::HashMap;

/// Position tolerance of a mirror image, relative to the model's largest extent.
const POSITION_TOL: f64 = 1e-9;
/// The smallest class worth a solve of its own: below `AUTO_DENSE_DOFS` the sparse solver is
/// not the tool (`Auto` never uses it there, and on pencils of a few dozen unknowns asked for
/// nearly all their modes its block Lanczos runs out of room), so a model whose classes would
/// be smaller is solved whole.
const MIN_CLASS_DOFS: usize = super::AUTO_DENSE_DOFS;

/// The proven mirror planes of the model and the classes they split the unknowns into.
pub struct Mirrors {
    /// The planes, e.g. "x = 0 m".
    pub planes: Vec<String>,
    pub classes: Vec<SymmetryClass>,
}

/// The mirror planes normal to x, y and z that K and M (reduced, with the prestress) are
/// proven symmetric about, with their classes; `None` when there is none.
pub fn find_mirrors(model: &FeModel, red: &Reduction, k: &SymCsc, m: &SymCsc) -> Option<Mirrors> {
    let mut planes = Vec::new();
    let mut accepted: Vec<SignedPerm> = Vec::new();
    for axis in 0..3 {
        let Some((g, at)) = reduced_mirror(model, red, axis) else {
            continue;
        };
        let proven = g.is_involution()
            && accepted.iter().all(|h| g.commutes_with(h))
            && g.preserves(k)
            && g.preserves(m);
        if proven {
            planes.push(format!("{} = {at:.6} m", ["x", "y", "z"][axis]));
            accepted.push(g);
        }
    }
    // As many mirrors as keep every class big enough (each mirror halves them).
    while !accepted.is_empty() {
        let classes = symmetry_classes(red.n_red, &accepted)?;
        if classes.iter().all(|c| c.columns.len() >= MIN_CLASS_DOFS) {
            return Some(Mirrors { planes, classes });
        }
        accepted.pop();
        planes.pop();
    }
    None
}

/// The mirror normal to `axis` through the middle of the bounding box, as a signed permutation
/// of the reduced DOFs, and the plane's coordinate; `None` when a node or an independent DOF
/// has no image.
fn reduced_mirror(model: &FeModel, red: &Reduction, axis: usize) -> Option<(SignedPerm, f64)> {
    let (node_image, at) = node_mirror(model, axis)?;
    let mut full_to_red = vec![usize::MAX; red.n_full];
    for (r, &f) in red.red_to_full.iter().enumerate() {
        full_to_red[f] = r;
    }
    let mut perm = Vec::with_capacity(red.n_red);
    let mut sign = Vec::with_capacity(red.n_red);
    for &f in &red.red_to_full {
        let (node, c) = (f / 6, f % 6);
        let image = full_to_red[node_image[node] * 6 + c];
        if image == usize::MAX {
            return None;
        }
        perm.push(image);
        sign.push(mirror_sign(axis, c));
    }
    Some((SignedPerm { perm, sign }, at))
}

/// How DOF component c (x, y, z, rx, ry, rz) changes sign in a mirror normal to `axis`: the
/// translation along the normal flips, the rotations about the other two axes flip (a
/// rotation is a pseudo-vector).
fn mirror_sign(axis: usize, c: usize) -> f64 {
    let flips = if c < 3 { c == axis } else { c - 3 != axis };
    if flips { -1.0 } else { 1.0 }
}

/// Each node's mirror image across the plane normal to `axis` through the middle of the
/// bounding box, and the plane's coordinate.
fn node_mirror(model: &FeModel, axis: usize) -> Option<(Vec<usize>, f64)> {
    let nodes = &model.nodes;
    let (lo, hi) = bounding_box(model);
    let extent = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    if extent.is_nan() || extent <= 0.0 {
        return None;
    }
    let tol = POSITION_TOL * extent;
    // A plane at round-off from the origin is the origin: x ↦ −x is then exact.
    let at = Some(0.5 * (lo[axis] + hi[axis]))
        .filter(|a| a.abs() > tol)
        .unwrap_or(0.0);
    let cell = |x: [f64; 3]| x.map(|v| (v / tol).round() as i64);
    let mut by_cell: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, n) in nodes.iter().enumerate() {
        by_cell.entry(cell(n.x)).or_default().push(i);
    }
    let mut image = vec![usize::MAX; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        let mut p = n.x;
        p[axis] = 2.0 * at - p[axis];
        let here = by_cell.get(&cell(n.x))?;
        let there = by_cell.get(&cell(p))?;
        let rank = here.iter().position(|&j| j == i)?;
        image[i] = *there.get(rank)?;
        if there.len() != here.len() {
            return None;
        }
    }
    Some((image, at))
}

/// The lowest and highest node coordinate along each axis.
fn bounding_box(model: &FeModel) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for n in &model.nodes {
        for a in 0..3 {
            lo[a] = lo[a].min(n.x[a]);
            hi[a] = hi[a].max(n.x[a]);
        }
    }
    (lo, hi)
}
