//! What a qualification found, as data: the result types `pipeline::qualify` fills and the
//! report renders. They live apart from the orchestrator so that the renderer depends on the
//! results, not on the planner. Their serde output is the `results.json` of a report.

use crate::gates::Verdict;
use crate::modal::ModalResult;
use crate::response::SceneResponse;
use crate::separation::{MonteCarloResult, Percentiles, SeparationResult};
use crate::signal::srs::SpecCheck;
use crate::signal::{Resonance, SignatureReport, ToleranceReport};
use crate::spec::LogKind;
use crate::spec::sweep::SweepSpec;
use serde::Serialize;

/// An analysis the scene did not ask for, and why it was not run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Skipped {
    pub analysis: String,
    pub reason: String,
}

impl Skipped {
    pub fn new(analysis: impl Into<String>, reason: impl Into<String>) -> Skipped {
        Skipped {
            analysis: analysis.into(),
            reason: reason.into(),
        }
    }
}

/// The modal part of a qualification.
#[derive(Debug, Clone, Serialize)]
pub struct ModalSummary {
    pub result: ModalResult,
    /// The first mode with ≥ 10% effective mass along x, y and z: the resonances the
    /// stiffness gates judge (index, frequency).
    pub first_x: Option<(usize, f64)>,
    pub first_y: Option<(usize, f64)>,
    pub first_z: Option<(usize, f64)>,
}

/// The separation part of a qualification: the nominal run, and the Monte Carlo when asked.
#[derive(Debug, Clone, Serialize)]
pub struct SeparationSummary {
    pub result: SeparationResult,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<MonteCarloResult>,
}

/// One line of the comparison with the paper's measured or simulated values.
#[derive(Debug, Clone, Serialize)]
pub struct PaperComparison {
    pub quantity: String,
    pub paper: String,
    pub satqual: String,
    pub source: String,
}

/// Where the result came from: enough to reproduce it. No timestamps, so two runs give
/// byte-identical JSON.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    pub scene_file: String,
    /// FNV-1a 64-bit hash of the scene text, hex.
    pub scene_hash: String,
    pub satqual_version: String,
    pub modal_solver: Option<String>,
    pub separation_tolerance: Option<f64>,
}

/// Everything `qualify` found.
#[derive(Debug, Clone, Serialize)]
pub struct Qualification {
    pub scene: String,
    pub title: Option<String>,
    pub pass: bool,
    pub gates: Vec<Verdict>,
    pub ran: Vec<String>,
    pub skipped: Vec<Skipped>,
    /// Every input environment as applied (sine segments, random profile with its level,
    /// weight reduction, Grms and duration), when a response analysis ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub environments: Option<crate::spec::environment::Environments>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub modal: Option<ModalSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub response: Option<SceneResponse>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<SeparationSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub test_data: Option<TestDataSummary>,
    pub paper_comparison: Vec<PaperComparison>,
    /// The values taken from a test model (`[calibration]`), when the scene names one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub calibration: Option<CalibrationSummary>,
    pub assumptions: Vec<String>,
    pub provenance: Provenance,
}

impl Qualification {
    /// What the analyses could not stand fully behind, each with the analysis it comes from:
    /// the modal solve's numerical warnings, then the nominal separation run's.
    pub fn warnings(&self) -> Vec<(&'static str, &str)> {
        let modal = self.modal.iter().flat_map(|m| &m.result.warnings);
        let separation = self.separation.iter().flat_map(|s| &s.result.warnings);
        modal
            .map(|w| ("modal solve", w.as_str()))
            .chain(separation.map(|w| ("separation", w.as_str())))
            .collect()
    }
}

/// What one measured log gave.
#[derive(Debug, Clone, Serialize)]
pub struct TestLogResult {
    pub name: String,
    pub file: String,
    pub kind: LogKind,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<ToleranceReport>,
    /// Grms of every channel.
    pub channels: Vec<(String, f64)>,
    /// Resonances of the FRF control -> first response (sweep and signature logs).
    pub resonances: Vec<Resonance>,
    /// Shock logs: each channel's peak and its SRS against the scene's `[shock]`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub shock: Vec<ShockChannel>,
    /// Curves for the report: (label, [(f, value)]).
    #[serde(skip)]
    pub curves: Vec<(String, Vec<(f64, f64)>)>,
    #[serde(skip)]
    pub log_scale_y: bool,
}

/// One channel of a shock log: its peak acceleration and its SRS against the specification.
#[derive(Debug, Clone, Serialize)]
pub struct ShockChannel {
    pub name: String,
    /// Unit of the peak and the SRS ("g" for accelerations).
    pub unit: String,
    pub peak: f64,
    pub peak_time_s: f64,
    pub check: SpecCheck,
}

/// The test-data part of a qualification.
#[derive(Debug, Clone, Serialize)]
pub struct TestDataSummary {
    pub logs: Vec<TestLogResult>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub signature: Option<SignatureReport>,
}

/// One point of a parameter sweep: the swept values, the Monte Carlo percentiles over every
/// satellite and run, and the Monte Carlo gates at that point.
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    pub point: usize,
    /// The swept keys' values, in the order of [`SweepTable::keys`].
    pub values: Vec<f64>,
    pub runs: usize,
    pub final_speed_m_s: Percentiles,
    pub tip_off_rate_deg_s: Percentiles,
    /// Absent with a single satellite (no pair to keep apart).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_clearance_m: Option<Percentiles>,
    /// Integrator steps over the point's runs.
    pub steps: usize,
    pub gates: Vec<Verdict>,
    /// Every gate of the point passes.
    pub pass: bool,
}

/// A parameter sweep: its definition and one row per point. Its serde output is `sweep.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SweepTable {
    pub scene: String,
    /// FNV-1a 64-bit hash of the scene text, hex.
    pub scene_hash: String,
    pub satqual_version: String,
    /// The `[sweep]` section as read.
    pub sweep: SweepSpec,
    pub keys: Vec<String>,
    /// Monte Carlo runs per point and their seed (the same at every point).
    pub runs: usize,
    pub seed: u64,
    pub points: Vec<SweepPoint>,
}

/// A flight scene's values taken from a test model updated to measurements, and the flight
/// prediction across the test fixture's plausible range.
#[derive(Debug, Clone, Serialize)]
pub struct CalibratedValue {
    pub path: String,
    /// As the flight scene has it.
    pub flight: f64,
    /// As the test scene has it (its updated value).
    pub test: f64,
}

/// The flight prediction with the test model calibrated at one fixture estimate.
#[derive(Debug, Clone, Serialize)]
pub struct FixtureCase {
    /// Factor on every fixture stiffness of the test scene (1 = its estimate).
    pub fixture_factor: f64,
    /// The calibrated values, in `parameters` order.
    pub values: Vec<f64>,
    /// First flight modes with ≥ 10 % effective mass along x, y, z, Hz.
    pub first_hz: [Option<f64>; 3],
}

#[derive(Debug, Clone, Serialize)]
pub struct CalibrationSummary {
    pub test_scene: String,
    pub parameters: Vec<CalibratedValue>,
    /// The fixture's source text in the test scene, when it has a fixture.
    pub fixture_source: Option<String>,
    /// Nominal first, then the low and high ends of the fixture's plausible range.
    pub cases: Vec<FixtureCase>,
    pub warnings: Vec<String>,
}
