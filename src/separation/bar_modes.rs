//! Lateral bending modes of a guide bar, clamped at its root and free at its tip, for the
//! separation model's floating-frame (modal) bar. The modes come from the `fem` beam model
//! (Timoshenko elements with consistent mass) solved by `modal`, so the separation model and
//! the stack model describe the same bar; [`super::bar`] samples the shapes at the element
//! nodes and interpolates between them. This lives beside its only user rather than in `fem`,
//! which sits below `modal` and must not call it.

use crate::error::{Error, SeparationError};
use crate::fem::FeModel;
use crate::modal::{ModalOptions, analyze};
use crate::spec::{Beam, Material, Node, SceneFile, Section, Support, Theory};

/// Mass-normalised lateral modes of one bending plane (a circular bar has the same modes in x
/// and y).
#[derive(Debug, Clone)]
pub struct BarModes {
    /// Stations along the bar from the root, m (first = 0, last = length).
    pub stations_m: Vec<f64>,
    pub frequencies_hz: Vec<f64>,
    /// `shapes[mode][station]`: lateral deflection for a unit modal coordinate (unit modal
    /// mass), m per √kg.
    pub shapes: Vec<Vec<f64>>,
    /// Mass per unit length, kg/m.
    pub mass_per_length_kg_m: f64,
    pub length_m: f64,
}

/// Modes of a solid circular bar of `diameter_m` and `length_m`, clamped at z = 0, from
/// `elements` beam elements. Returns the first `n_modes` bending modes of one plane.
pub fn cantilever_bar_modes(
    length_m: f64,
    diameter_m: f64,
    material: &Material,
    elements: usize,
    n_modes: usize,
) -> Result<BarModes, Error> {
    if !(length_m > 0.0 && diameter_m > 0.0) || elements == 0 {
        return Err(SeparationError::Invalid(
            "guide-bar modes: bar length, diameter and elements must be positive".into(),
        )
        .into());
    }
    // The bar along global x; bending in the x–y plane gives the lateral modes.
    let scene = SceneFile {
        material: vec![material.clone()],
        section: vec![Section {
            name: "bar".into(),
            shape: "circle".into(),
            diameter_m: Some(diameter_m),
            ..Default::default()
        }],
        node: vec![
            Node {
                id: 1,
                position_m: [0.0; 3],
            },
            Node {
                id: 2,
                position_m: [length_m, 0.0, 0.0],
            },
        ],
        beam: vec![Beam {
            name: Some("guide bar".into()),
            nodes: [1, 2],
            section: "bar".into(),
            material: material.name.clone(),
            elements,
            orientation: Some([0.0, 0.0, 1.0]),
            theory: Theory::Timoshenko,
        }],
        support: vec![Support {
            node: 1,
            dofs: "123456".into(),
        }],
        ..Default::default()
    };
    let mut model = FeModel::from_scene(&scene)?;
    // Only the x–y bending plane: out-of-plane, axial and torsional DOFs are held, which
    // leaves exactly the lateral modes sought.
    for n in 0..model.nodes.len() {
        if n != 0 {
            model.fixed[n] = [true, false, true, true, true, false];
        }
    }
    let opts = ModalOptions {
        modes: Some(n_modes),
        ..Default::default()
    };
    let sys = analyze(&model, &opts)?;
    // Stations in order along the bar: root, interior nodes, tip.
    let mut order: Vec<usize> = (0..model.nodes.len()).collect();
    order.sort_by(|a, b| model.nodes[*a].x[0].total_cmp(&model.nodes[*b].x[0]));
    let stations_m: Vec<f64> = order.iter().map(|&n| model.nodes[n].x[0]).collect();
    let red = &sys.reduction;
    let mut shapes = Vec::new();
    let mut frequencies_hz = Vec::new();
    for m in &sys.result.modes {
        let full = red.expand(&m.shape);
        shapes.push(order.iter().map(|&n| full[6 * n + 1]).collect());
        frequencies_hz.push(m.frequency_hz);
    }
    let area = std::f64::consts::PI * diameter_m * diameter_m / 4.0;
    Ok(BarModes {
        stations_m,
        frequencies_hz,
        shapes,
        mass_per_length_kg_m: material.density_kg_m3 * area,
        length_m,
    })
}
