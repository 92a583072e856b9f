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
/// external eigen-solver needs to reproduce the modes.
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
    write_atomic(&dir.join("dofs.csv"), csv.as_bytes())
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
