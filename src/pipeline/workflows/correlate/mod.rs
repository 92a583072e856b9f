//! The correlation workflow of `satqual correlate`: FE modes at the test points against the
//! test modes, paired (by MAC, or by frequency and effective-mass direction when there is at
//! most one channel per axis), their MAC matrix, the SEREP cross-orthogonality of the pairs,
//! and the gates.

pub mod fe_side;
pub mod test_modes;

use crate::error::Error;
use crate::gates::Verdict;
use crate::gates::correlation::{self as rules, Matrix, PairedMode};
use crate::modal::correlation::{
    PairingMethod, cross_orthogonality, mac_matrix, pairing, serep_mass,
};
use crate::pipeline::plan::{ModalOverrides, modal_options};
use crate::spec::Scene;
use fe_side::FeModeAtTest;
use serde::Serialize;
use test_modes::TestMode;

pub const REDUCTION: &str = "SEREP of the paired FE modes to the test DOFs";

#[derive(Debug, Clone, Serialize)]
pub struct Pair {
    pub test_mode: usize,
    pub fe_mode: usize,
    pub test_hz: f64,
    pub fe_hz: f64,
    pub error_pct: f64,
    pub mac: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Correlation {
    pub channels: Vec<String>,
    pub test_source: String,
    pub pairing: PairingMethod,
    pub frequency_standard: crate::spec::correlation::FrequencyStandard,
    pub test_modes: Vec<TestMode>,
    pub fe_modes: Vec<FeModeAtTest>,
    pub pairs: Vec<Pair>,
    /// MAC of every test mode (rows) with every elastic FE mode (columns, as `fe_modes`).
    pub mac_matrix: Vec<Vec<f64>>,
    pub reduction: &'static str,
    /// Paired test modes (rows) against paired FE modes (columns), in `pairs` order; absent
    /// when the test DOFs cannot carry the paired modes (`notes` says why).
    pub cross_orthogonality: Option<Vec<Vec<f64>>>,
    pub gates: Vec<Verdict>,
    pub notes: Vec<String>,
}

impl Correlation {
    pub fn passed(&self) -> bool {
        self.gates.iter().all(|g| g.pass)
    }
}

pub fn run(scene: &Scene) -> Result<Correlation, Error> {
    if scene.file.test_point.is_empty() {
        let msg = "correlate needs [[test_point]] entries mapping channels to model DOFs";
        return Err(scene.locator().err("test_point", msg).into());
    }
    let (test, test_source) = test_modes::test_modes(scene)?;
    let opts = modal_options(scene, &ModalOverrides::default());
    let (model, sys) = super::modal::run(scene, &opts)?;
    let rows = fe_side::test_dof_rows(scene, &model, &sys)?;
    let held = fe_side::held_points(scene, &rows)?;
    let fe = fe_side::fe_modes(&sys, &rows);
    let (method, mac, found) = pair_modes(scene, &test, &fe);
    let standard = scene
        .file
        .correlation
        .clone()
        .unwrap_or_default()
        .frequency_standard;
    let mut c = Correlation {
        channels: scene
            .file
            .test_point
            .iter()
            .map(|p| p.channel.clone())
            .collect(),
        test_source,
        pairing: method,
        frequency_standard: standard,
        pairs: Vec::new(),
        mac_matrix: mac,
        reduction: REDUCTION,
        cross_orthogonality: None,
        gates: Vec::new(),
        notes: held,
        test_modes: test,
        fe_modes: fe,
    };
    c.pairs = found.iter().map(|p| pair_row(&c, p.test, p.fe)).collect();
    gate(&mut c, &found);
    Ok(c)
}

/// The pairing of `correlate` (also what `update` re-pairs by at every iteration): the
/// method, the MAC matrix (test rows, FE columns) and the pairs.
pub fn pair_modes(
    scene: &Scene,
    test: &[TestMode],
    fe: &[FeModeAtTest],
) -> (PairingMethod, Vec<Vec<f64>>, Vec<pairing::Pair>) {
    let test_shapes: Vec<Vec<f64>> = test.iter().map(|m| m.shape.clone()).collect();
    let fe_shapes: Vec<Vec<f64>> = fe.iter().map(|m| m.shape.clone()).collect();
    let mac = mac_matrix(&test_shapes, &fe_shapes);
    let method = pairing_method(scene);
    let found = match method {
        PairingMethod::Mac => pairing::by_mac(&mac),
        PairingMethod::FrequencyAndDirection => by_frequency(scene, test, fe),
    };
    (method, mac, found)
}

/// Frequency and direction with at most one channel per axis; MAC otherwise.
fn pairing_method(scene: &Scene) -> PairingMethod {
    let mut per_axis = [0usize; 3];
    for tp in &scene.file.test_point {
        if let Some((axis, _)) = tp.axis() {
            per_axis[axis] += 1;
        }
    }
    if per_axis.iter().all(|&n| n <= 1) {
        PairingMethod::FrequencyAndDirection
    } else {
        PairingMethod::Mac
    }
}

/// Each test mode's axis is that of the test point it moves most.
fn by_frequency(scene: &Scene, test: &[TestMode], fe: &[FeModeAtTest]) -> Vec<pairing::Pair> {
    let axes: Vec<usize> = test
        .iter()
        .map(|m| {
            let p = (0..m.shape.len())
                .max_by(|&a, &b| m.shape[a].abs().total_cmp(&m.shape[b].abs()))
                .unwrap_or(0);
            scene.file.test_point[p].axis().map_or(0, |(a, _)| a)
        })
        .collect();
    let test_hz: Vec<f64> = test.iter().map(|m| m.frequency_hz).collect();
    let fe_hz: Vec<f64> = fe.iter().map(|m| m.frequency_hz).collect();
    let fe_axis: Vec<Option<usize>> = fe.iter().map(|m| m.axis).collect();
    pairing::by_frequency_and_direction(&test_hz, &axes, &fe_hz, &fe_axis)
}

fn pair_row(c: &Correlation, test: usize, fe: usize) -> Pair {
    let p = PairedMode {
        test_mode: test + 1,
        fe_mode: c.fe_modes[fe].mode,
        test_hz: c.test_modes[test].frequency_hz,
        fe_hz: c.fe_modes[fe].frequency_hz,
    };
    Pair {
        test_mode: p.test_mode,
        fe_mode: p.fe_mode,
        test_hz: p.test_hz,
        fe_hz: p.fe_hz,
        error_pct: p.error_pct(),
        mac: c.mac_matrix[test][fe],
    }
}

/// Frequency gates for every pair, a failed gate for every unpaired test mode, and the MAC
/// and cross-orthogonality gates where the test DOFs can tell the paired modes apart.
fn gate(c: &mut Correlation, found: &[pairing::Pair]) {
    let paired: Vec<PairedMode> = c
        .pairs
        .iter()
        .map(|p| PairedMode {
            test_mode: p.test_mode,
            fe_mode: p.fe_mode,
            test_hz: p.test_hz,
            fe_hz: p.fe_hz,
        })
        .collect();
    c.gates
        .extend(rules::frequency(&paired, c.frequency_standard));
    for (i, m) in c.test_modes.iter().enumerate() {
        if !found.iter().any(|p| p.test == i) {
            let why = match c.pairing {
                PairingMethod::Mac => "more test modes than FE modes",
                PairingMethod::FrequencyAndDirection => "no FE mode left along its axis",
            };
            c.gates.push(rules::unpaired(i + 1, m.frequency_hz, why));
        }
    }
    let n_dofs = c.channels.len();
    if n_dofs < 2 || n_dofs < found.len() {
        c.notes.push(format!(
            "MAC and cross-orthogonality not gated: {n_dofs} test DOF(s) cannot tell {} paired mode(s) apart (every shape of one DOF has MAC 1 with every other)",
            found.len()
        ));
        return;
    }
    let square = |m: &[Vec<f64>]| -> Vec<Vec<f64>> {
        found
            .iter()
            .map(|a| found.iter().map(|b| m[a.test][b.fe]).collect())
            .collect()
    };
    c.gates
        .extend(rules::matrix(Matrix::Mac, &square(&c.mac_matrix), &paired));
    let fe_paired: Vec<Vec<f64>> = found
        .iter()
        .map(|p| c.fe_modes[p.fe].shape.clone())
        .collect();
    let test_paired: Vec<Vec<f64>> = found
        .iter()
        .map(|p| c.test_modes[p.test].shape.clone())
        .collect();
    match serep_mass(&fe_paired) {
        Ok(ma) => {
            let co = cross_orthogonality(&test_paired, &fe_paired, &ma);
            c.gates
                .extend(rules::matrix(Matrix::CrossOrthogonality, &co, &paired));
            c.cross_orthogonality = Some(co);
        }
        Err(why) => c
            .notes
            .push(format!("cross-orthogonality not gated: {why}")),
    }
}
