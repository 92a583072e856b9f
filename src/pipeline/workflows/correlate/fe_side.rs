//! The analysis side of the correlation: the scene's elastic FE modes (sensor masses
//! included) read at the test points, with the direction each mode's effective mass lies in.

use crate::error::Error;
use crate::fem::FeModel;
use crate::modal::ModalSystem;
use crate::spec::Scene;
use serde::Serialize;

/// Below this, a mode has no translational effective mass to speak of and no direction.
const MIN_EFFECTIVE_MASS_FRACTION: f64 = 1e-9;

#[derive(Debug, Clone, Serialize)]
pub struct FeModeAtTest {
    /// The mode's number in `satqual modal`.
    pub mode: usize,
    pub frequency_hz: f64,
    /// x, y or z: the translation with the largest effective-mass fraction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<&'static str>,
    /// The mass-normalised shape at the test points, along each point's direction.
    pub shape: Vec<f64>,
    #[serde(skip)]
    pub axis: Option<usize>,
    /// The direction (x … rz) of the mode's largest effective-mass fraction, which names
    /// its family in `[damping] modes` (`Mode::dominant_direction`).
    #[serde(skip)]
    pub family: Option<&'static str>,
}

/// Rows of the reduced-DOF map that give each test point's motion along its direction.
pub fn test_dof_rows(
    scene: &Scene,
    model: &FeModel,
    sys: &ModalSystem,
) -> Result<Vec<Vec<(usize, f64)>>, Error> {
    scene
        .file
        .test_point
        .iter()
        .enumerate()
        .map(|(i, tp)| {
            let node = model.nodes.iter().position(|n| n.id == Some(tp.node));
            let (Some(node), Some((axis, sign))) = (node, tp.axis()) else {
                let msg = format!("node {} is not in the FE model", tp.node);
                return Err(scene
                    .locator()
                    .err(&format!("test_point[{i}].node"), msg)
                    .into());
            };
            let row = &sys.reduction.map[6 * node + axis];
            Ok(row.iter().map(|&(r, t)| (r, sign * t)).collect())
        })
        .collect()
}

/// Test points whose DOF the model holds (a support, or nothing free behind it): every FE
/// shape is 0 there, so the point adds nothing to a MAC. One note per such point; an error
/// when every point is held, since there is then nothing to correlate.
pub fn held_points(scene: &Scene, rows: &[Vec<(usize, f64)>]) -> Result<Vec<String>, Error> {
    let points = &scene.file.test_point;
    let held: Vec<usize> = (0..rows.len()).filter(|&i| rows[i].is_empty()).collect();
    let describe = |i: usize| {
        let p = &points[i];
        format!(
            "test point {} (channel `{}`, node {} {}) is held by the model's supports: every FE shape is 0 there",
            i + 1,
            p.channel,
            p.node,
            p.direction
        )
    };
    if !rows.is_empty() && held.len() == rows.len() {
        let msg = format!(
            "{}; so is every other test point: nothing to correlate (place the points on free DOFs)",
            describe(0)
        );
        return Err(scene.locator().err("test_point[0].node", msg).into());
    }
    Ok(held
        .into_iter()
        .map(|i| format!("{}, so it adds nothing to the MAC", describe(i)))
        .collect())
}

/// Every elastic mode of `sys` at the test DOFs.
pub fn fe_modes(sys: &ModalSystem, rows: &[Vec<(usize, f64)>]) -> Vec<FeModeAtTest> {
    sys.result
        .modes
        .iter()
        .filter(|m| !m.rigid_body)
        .map(|m| {
            let shape = rows
                .iter()
                .map(|row| row.iter().map(|&(r, t)| t * m.shape[r]).sum())
                .collect();
            let f = m.effective_mass_fraction.to_array();
            let axis = (0..3)
                .filter(|&a| f[a] > MIN_EFFECTIVE_MASS_FRACTION)
                .max_by(|&a, &b| f[a].total_cmp(&f[b]));
            FeModeAtTest {
                mode: m.index,
                frequency_hz: m.frequency_hz,
                direction: axis.map(|a| ["x", "y", "z"][a]),
                shape,
                axis,
                family: m.dominant_direction(),
            }
        })
        .collect()
}
