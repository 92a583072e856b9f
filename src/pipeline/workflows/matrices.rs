//! Export of the reduced matrices of a modal system for external solvers (and for the modal
//! benchmark, whose peers read exactly the files a user would export).

use crate::error::Error;
use crate::fem::FeModel;
use crate::fem::model::Triplets;
use crate::modal::ModalSystem;
use crate::report::write_atomic;
use std::fmt::Write as _;
use std::path::Path;

/// Writes a modal system's reduced K, M (and with prestress K_G and K + K_G, the stiffness the
/// eigen-solve used) as Matrix Market files, with the DOF map `dofs.csv`, into `dir`: what an
/// external eigen-solver needs to reproduce the modes; and the base-drive vectors
/// `influence.csv` ([`influence_csv`]), with which the files alone reproduce a base-driven
/// response.
pub fn export(dir: &Path, model: &FeModel, sys: &ModalSystem) -> Result<(), Error> {
    let red = &sys.reduction;
    let k = red.reduce(&model.stiffness());
    write_atomic(&dir.join("K.mtx"), matrix_market(red.n_red, &k).as_bytes())?;
    write_atomic(
        &dir.join("M.mtx"),
        matrix_market(red.n_red, &sys.m).as_bytes(),
    )?;
    if let Some(ps) = &sys.result.prestress {
        let kg = red.reduce(&model.geometric_stiffness(&ps.element_axial_n));
        write_atomic(
            &dir.join("KG.mtx"),
            matrix_market(red.n_red, &kg).as_bytes(),
        )?;
        // The stiffness the eigen-solve actually used, K + K_G, for external solvers.
        write_atomic(
            &dir.join("KKG.mtx"),
            matrix_market(red.n_red, &sys.k).as_bytes(),
        )?;
    }
    let mut csv = String::from("index,node,node_id,dof\n");
    for (i, &f) in red.reduction_dofs().iter().enumerate() {
        let (label, dof, _) = model.dof_label(f);
        let id = model.nodes[f / 6]
            .id
            .map(|v| v.to_string())
            .unwrap_or_default();
        let _ = writeln!(csv, "{},\"{}\",{},{}", i, label, id, dof);
    }
    write_atomic(&dir.join("dofs.csv"), csv.as_bytes())?;
    write_atomic(
        &dir.join("influence.csv"),
        influence_csv(model, sys).as_bytes(),
    )
}

/// The base drive per reduced DOF, one row each (`index` as in `dofs.csv`): `p_x, p_y, p_z`,
/// the load of a unit base acceleration (1 m/s²) along x, y, z, p = Tᵀ·M_full·r (kg: the
/// inertia of the whole structure, the mass coupling to the supported DOFs included), and
/// `r_x, r_y, r_z`, the rigid translation of the DOF with the base (1 on the DOF that moves
/// along the axis, else 0). The relative displacement then solves
/// (K − ω²M + iωC)·u = −p·ü_b, and the absolute acceleration is −ω²·u + r·ü_b.
pub fn influence_csv(model: &FeModel, sys: &ModalSystem) -> String {
    let red = &sys.reduction;
    let p: Vec<Vec<f64>> = (0..3)
        .map(|a| crate::response::basis::influence_load(model, sys, a))
        .collect();
    let mut s = String::from("index,p_x,p_y,p_z,r_x,r_y,r_z\n");
    for (i, &f) in red.red_to_full.iter().enumerate() {
        let r = |a: usize| u8::from(f % 6 == a);
        let _ = writeln!(
            s,
            "{i},{:.17e},{:.17e},{:.17e},{},{},{}",
            p[0][i],
            p[1][i],
            p[2][i],
            r(0),
            r(1),
            r(2)
        );
    }
    s
}

/// Matrix Market coordinate format, lower triangle of a symmetric matrix, duplicates summed.
fn matrix_market(n: usize, t: &Triplets) -> String {
    let mut e: Vec<(usize, usize, f64)> = t.iter().filter(|x| x.0 >= x.1).copied().collect();
    e.sort_by_key(|a| (a.1, a.0));
    let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(e.len());
    for (i, j, v) in e {
        match merged.last_mut() {
            Some(l) if l.0 == i && l.1 == j => l.2 += v,
            _ => merged.push((i, j, v)),
        }
    }
    merged.retain(|x| x.2 != 0.0);
    let mut s = String::with_capacity(merged.len() * 40);
    s.push_str("%%MatrixMarket matrix coordinate real symmetric\n% written by satqual: reduced DOFs (see dofs.csv)\n");
    let _ = writeln!(s, "{n} {n} {}", merged.len());
    for (i, j, v) in merged {
        let _ = writeln!(s, "{} {} {:.17e}", i + 1, j + 1, v);
    }
    s
}
