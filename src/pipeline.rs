//! `qualify`: plans the analyses a scene asks for, runs each once, and reuses results.
//! The only module that knows the whole order spec -> fem -> modal -> response -> gates -> report.
//! It also maps errors of the numerical layers back to the scene: an FE error that names a
//! scene node gets that node's file, line and column.

use crate::error::{Error, FemError, ModalError, SpecError};
use crate::fem::FeModel;
use crate::modal::{ModalOptions, ModalSystem};
use crate::spec::Scene;

/// Builds the FE model of a scene and runs the modal analysis (with prestress when the scene
/// has static loads). Command-line overrides take precedence over `[modal]`.
pub fn modal(
    scene: &Scene,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
) -> Result<(FeModel, ModalSystem), Error> {
    modal_with_solver(scene, fmax_hz, modes, None)
}

/// [`modal`] with a solver override (`--solver`) that takes precedence over `[modal] solver`.
pub fn modal_with_solver(
    scene: &Scene,
    fmax_hz: Option<f64>,
    modes: Option<usize>,
    solver: Option<crate::spec::SolverChoice>,
) -> Result<(FeModel, ModalSystem), Error> {
    let model = FeModel::from_scene(&scene.model).map_err(|e| locate(scene, e))?;
    let mut spec = scene.file.modal.clone().unwrap_or_default();
    if let Some(s) = solver {
        spec.solver = s;
    }
    // A stack's preload above its buckling load is refused as soon as the buckling factor is
    // known, before any mode of the unstable structure is extracted.
    let stop_beyond_buckling = scene.file.stack.is_some();
    let opts = match (fmax_hz, modes) {
        (None, None) => ModalOptions {
            fmax_hz: spec.fmax_hz,
            modes: spec.modes,
            solver: spec.solver,
            stop_beyond_buckling,
        },
        (f, n) => ModalOptions {
            fmax_hz: f,
            modes: n,
            solver: spec.solver,
            stop_beyond_buckling,
        },
    };
    let sys = crate::modal::analyze(&model, &opts).map_err(|e| match (e, &scene.file.stack) {
        (Error::Fem(f), _) => locate(scene, f),
        (Error::Modal(ModalError::BeyondBuckling { factor }), Some(stack)) => scene
            .locator()
            .err(
                "stack.preload_total_n",
                format!(
                    "the preload of {:.0} N is above the stack's buckling load of {:.0} N (buckling factor {:.3}): reduce the preload or stiffen the columns",
                    stack.preload_total_n,
                    factor * stack.preload_total_n,
                    factor
                ),
            )
            .into(),
        (other, _) => other,
    })?;
    Ok((model, sys))
}

/// The FE model of a scene, with FE errors located in the scene.
pub fn fe_model(scene: &Scene) -> Result<FeModel, Error> {
    FeModel::from_scene(&scene.model).map_err(|e| locate(scene, e))
}

/// Attaches the scene location of the node an FE error names, when it is a scene node.
pub fn locate(scene: &Scene, e: FemError) -> Error {
    let node = match &e {
        FemError::MasslessDof { node, .. }
        | FemError::Unconstrained { node, .. }
        | FemError::RigidChain { node } => node.clone(),
        _ => return e.into(),
    };
    let id = node
        .strip_prefix("node ")
        .and_then(|s| s.parse::<i64>().ok());
    let idx = id.and_then(|id| scene.file.node.iter().position(|n| n.id == id));
    match idx {
        Some(i) => {
            let loc = scene.locator();
            let key = format!("node[{i}]");
            let mut se: SpecError = loc.err(&format!("{key}.id"), e.to_string());
            se.key = key;
            se.into()
        }
        None => SpecError {
            file: scene.path.clone(),
            line: 0,
            column: 0,
            key: String::new(),
            message: e.to_string(),
        }
        .into(),
    }
}

use crate::gates::{self, Verdict};
use crate::modal::ModalResult;
use crate::separation;
use serde::Serialize;

/// Progress reporting for long stages; the library never prints, the caller decides.
pub trait Progress {
    fn stage(&self, _name: &str) {}
}

/// A no-op progress sink.
pub struct Silent;
impl Progress for Silent {}

/// An analysis the scene did not ask for, and why it was not run.
#[derive(Debug, Clone, Serialize)]
pub struct Skipped {
    pub analysis: String,
    pub reason: String,
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

#[derive(Debug, Clone, Serialize)]
pub struct SeparationSummary {
    pub result: separation::SeparationResult,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<separation::MonteCarloResult>,
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
    #[serde(skip_serializing_if = "Option::is_none")]
    pub modal: Option<ModalSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub response: Option<crate::response::SceneResponse>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<SeparationSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub test_data: Option<TestDataSummary>,
    pub paper_comparison: Vec<PaperComparison>,
    pub assumptions: Vec<String>,
    pub provenance: Provenance,
}

/// FNV-1a, 64 bit: a stable fingerprint of the scene text for the report's provenance.
pub fn fnv1a(text: &str) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in text.as_bytes() {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    format!("{h:016x}")
}

fn first_mode(r: &ModalResult, dir: usize) -> Option<(usize, f64)> {
    r.modes
        .iter()
        .find(|m| m.frequency_hz > 1e-3 && m.effective_mass_fraction.to_array()[dir] >= 0.1)
        .map(|m| (m.index, m.frequency_hz))
}

/// Plans the analyses the scene asks for, runs each once, and gates the results.
pub fn qualify(scene: &Scene, progress: &dyn Progress) -> Result<Qualification, Error> {
    let f = &scene.file;
    let limits = f.gates.clone().unwrap_or_default();
    let mut ran = Vec::new();
    let mut skipped = Vec::new();
    let mut gates = Vec::new();
    let mut comparison = Vec::new();
    let has_model = !scene.model.node.is_empty();
    let wants_modal = f.modal.is_some() || f.stack.is_some();

    let mut modal_summary = None;
    let mut solver = None;
    let mut response_result = None;
    let wants_response = f.sine.is_some() || f.random.is_some();
    if has_model && (wants_modal || wants_response) {
        progress.stage("modal analysis");
        let (fe, sys) = modal(scene, None, None)?;
        ran.push("modal".to_string());
        if wants_response {
            progress.stage("sine and random response");
            let prep = crate::response::Prepared::new(scene, &fe, &sys)?;
            let resp = crate::response::run_scene(&prep)?;
            if f.sine.is_some() {
                ran.push("sine".to_string());
            }
            if f.random.is_some() {
                ran.push("random".to_string());
            }
            for m in resp.governing_margins() {
                gates.push(Verdict {
                    name: format!("{}: {} ({})", m.kind, m.name, m.load_case),
                    value: m.value,
                    limit: m.limit,
                    margin: m.margin,
                    pass: m.pass,
                    source: m.source.clone(),
                });
            }
            if f.stack.as_ref().is_some_and(|s| s.satellites == 2) {
                for a in &resp.sine {
                    let measured = match a.axis.as_str() {
                        "x" => "29.1 Hz, 4.53 g",
                        "y" => "31.2 Hz, 4.29 g",
                        _ => "77.6 Hz, 0.68 g",
                    };
                    if let Some(p) = a.peaks.iter().find(|p| p.name == "sat 1") {
                        comparison.push(PaperComparison {
                            quantity: format!(
                                "sine peak response along {} (top satellite)",
                                a.axis
                            ),
                            paper: format!("{measured} (measured)"),
                            satqual: format!("{:.2} Hz, {:.2} g", p.frequency_hz, p.acceleration_g),
                            source: "paper §5.1.1, Fig. 17a".into(),
                        });
                    }
                }
            }
            response_result = Some(resp);
        }
        let r = sys.result.clone();
        solver = Some(r.solver.clone());
        let (fx, fy, fz) = (first_mode(&r, 0), first_mode(&r, 1), first_mode(&r, 2));
        let src_lat =
            "launcher lateral minimum (Falcon 9 User's Guide), [gates] min_lateral_frequency_hz";
        let src_ax =
            "launcher axial minimum (Falcon 9 User's Guide), [gates] min_axial_frequency_hz";
        if let Some((i, fr)) = fx {
            gates.push(gates::at_least(
                format!("first lateral frequency x (mode {i}) [Hz]"),
                fr,
                limits.min_lateral_frequency_hz,
                src_lat,
            ));
        }
        if let Some((i, fr)) = fy {
            gates.push(gates::at_least(
                format!("first lateral frequency y (mode {i}) [Hz]"),
                fr,
                limits.min_lateral_frequency_hz,
                src_lat,
            ));
        }
        if let Some((i, fr)) = fz {
            gates.push(gates::at_least(
                format!("first axial frequency z (mode {i}) [Hz]"),
                fr,
                limits.min_axial_frequency_hz,
                src_ax,
            ));
        }
        if let Some(ps) = &r.prestress
            && let Some(l) = ps.buckling_factor
        {
            gates.push(gates::at_least(
                "stack buckling factor under the preload",
                l,
                limits.min_buckling_factor,
                "linear buckling (K + λ·K_G)φ = 0, [gates] min_buckling_factor",
            ));
        }
        if f.stack.as_ref().is_some_and(|s| s.satellites == 2) {
            for (label, dir, measured) in [("x", 0usize, 29.1), ("y", 1, 31.2), ("z", 2, 77.6)] {
                let dom = r.modes.iter().max_by(|a, b| {
                    a.effective_mass_fraction.to_array()[dir]
                        .total_cmp(&b.effective_mass_fraction.to_array()[dir])
                });
                if let Some(m) = dom {
                    comparison.push(PaperComparison {
                        quantity: format!("first {label} resonance (2-satellite shaker test)"),
                        paper: format!("{measured} Hz (measured)"),
                        satqual: format!("{:.2} Hz (mode {})", m.frequency_hz, m.index),
                        source: "paper §5.1.1, Fig. 17a".into(),
                    });
                }
            }
        }
        modal_summary = Some(ModalSummary {
            result: r,
            first_x: fx,
            first_y: fy,
            first_z: fz,
        });
    } else {
        skipped.push(Skipped {
            analysis: "modal".into(),
            reason: if has_model {
                "the scene has no [modal] or [stack] section".into()
            } else {
                "the scene has no FE model".into()
            },
        });
    }

    for (present, name, section) in [
        (f.sine.is_some(), "sine", "[sine]"),
        (f.random.is_some(), "random", "[random]"),
    ] {
        if !present {
            skipped.push(Skipped {
                analysis: name.into(),
                reason: format!("the scene has no {section} section"),
            });
        }
    }

    let mut sep_summary = None;
    let mut sep_tol = None;
    if f.separation.is_some() {
        progress.stage("separation dynamics");
        let model = separation::Model::from_scene(scene)?;
        sep_tol = Some(model.tolerance);
        let result = separation::run(
            &model,
            &separation::RunOptions {
                record_history: true,
            },
        )?;
        ran.push("separation".to_string());
        let src = "[gates]; defaults are assumptions documented in spec::qualify";
        for s in &result.satellites {
            gates.push(gates::at_least(
                format!("satellite {} exit speed [m/s]", s.index),
                s.final_speed_m_s,
                limits.min_separation_speed_m_s,
                src,
            ));
            gates.push(gates::at_most(
                format!("satellite {} tip-off rate at bar exit [deg/s]", s.index),
                s.final_rate_deg_s,
                limits.max_tipoff_rate_deg_s,
                src,
            ));
            gates.push(Verdict {
                name: format!("satellite {} clears the guide bars", s.index),
                value: s.exit_time_s.unwrap_or(f64::NAN),
                limit: model.max_time_s,
                margin: if s.exit_time_s.is_some() { 1.0 } else { -1.0 },
                pass: s.exit_time_s.is_some(),
                source: "every satellite must leave the bars within the simulated time".into(),
            });
        }
        if let Some(c) = result.min_clearance_m {
            gates.push(gates::above(
                "minimum clearance between consecutive satellites [m]",
                c,
                0.0,
                "no re-contact after release",
            ));
        }
        let runs = f
            .separation
            .as_ref()
            .map(|s| s.dispersion.runs)
            .unwrap_or(0);
        let mc = if runs > 0 {
            progress.stage("separation Monte Carlo");
            let seed = f
                .separation
                .as_ref()
                .map(|s| s.dispersion.seed)
                .unwrap_or(0);
            let mc = separation::monte_carlo(&model, runs, seed)?;
            ran.push(format!("separation Monte Carlo ({runs} runs, seed {seed})"));
            gates.push(gates::at_least(
                "Monte Carlo P0.27 exit speed [m/s] (99.73% bound)",
                mc.final_speed_m_s.p0_27,
                limits.min_separation_speed_m_s,
                src,
            ));
            gates.push(gates::at_most(
                "Monte Carlo P99.73 tip-off rate [deg/s]",
                mc.tip_off_rate_deg_s.p99_73,
                limits.max_tipoff_rate_deg_s,
                src,
            ));
            gates.push(gates::above(
                "Monte Carlo P0.27 inter-satellite clearance [m]",
                mc.min_clearance_m.p0_27,
                0.0,
                "no re-contact after release",
            ));
            Some(mc)
        } else {
            skipped.push(Skipped {
                analysis: "separation Monte Carlo".into(),
                reason: "[separation.dispersion] runs = 0".into(),
            });
            None
        };
        let vmax = result
            .satellites
            .iter()
            .map(|s| s.max_speed_m_s)
            .fold(0.0, f64::max);
        comparison.push(PaperComparison {
            quantity: "maximum separation speed".into(),
            paper: "0.347 m/s (simulated)".into(),
            satqual: format!("{vmax:.4} m/s"),
            source: "paper §4, Fig. 15".into(),
        });
        let vmin = result
            .satellites
            .iter()
            .map(|s| s.final_speed_m_s)
            .fold(f64::INFINITY, f64::min);
        let vmx = result
            .satellites
            .iter()
            .map(|s| s.final_speed_m_s)
            .fold(0.0, f64::max);
        comparison.push(PaperComparison {
            quantity: "exit speed with 10% spring error".into(),
            paper: "0.278 m/s simulated, 0.252 m/s test".into(),
            satqual: format!("{vmin:.3}–{vmx:.3} m/s"),
            source: "paper §5.2, Fig. 20b".into(),
        });
        if let Some(s1) = result.satellites.first() {
            comparison.push(PaperComparison {
                quantity: "first satellite angular rate".into(),
                paper: "2.47 deg/s at separation (simulated)".into(),
                satqual: format!(
                    "{:.2} deg/s at exit, {:.2} deg/s peak",
                    s1.final_rate_deg_s, s1.peak_rate_deg_s
                ),
                source: "paper §4".into(),
            });
        }
        if let Some(last) = result.satellites.last()
            && let Some(t) = last.exit_time_s
        {
            comparison.push(PaperComparison {
                quantity: format!("time for satellite {} to clear the bars", last.index),
                paper: "about 9.5 s".into(),
                satqual: format!("{t:.2} s"),
                source: "paper §4, Fig. 12".into(),
            });
        }
        sep_summary = Some(SeparationSummary {
            result,
            monte_carlo: mc,
        });
    } else {
        skipped.push(Skipped {
            analysis: "separation".into(),
            reason: "the scene has no [separation] section".into(),
        });
    }

    let mut test_summary = None;
    if f.test_log.is_empty() {
        skipped.push(Skipped {
            analysis: "test data".into(),
            reason: "the scene lists no [[test_log]]".into(),
        });
    } else {
        progress.stage("test data");
        test_summary = Some(test_data(scene, &limits, &mut gates)?);
        ran.push("test data".to_string());
    }

    let assumptions = assumption_lines(&scene.text);
    let pass = gates.iter().all(|g| g.pass);
    Ok(Qualification {
        scene: scene.name(),
        title: f.title.clone(),
        pass,
        gates,
        ran,
        skipped,
        modal: modal_summary,
        response: response_result,
        separation: sep_summary,
        test_data: test_summary,
        paper_comparison: comparison,
        assumptions,
        provenance: Provenance {
            scene_file: scene.path.display().to_string(),
            scene_hash: fnv1a(&scene.text),
            satqual_version: env!("CARGO_PKG_VERSION").to_string(),
            modal_solver: solver,
            separation_tolerance: sep_tol,
        },
    })
}

/// The scene's labelled assumptions (comment lines that say ASSUMPTION or CALIBRATED), for the
/// report's model summary: the engineer signs off on them.
fn assumption_lines(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        let t = line.trim();
        let comment = t.find('#').map(|i| t[i + 1..].trim());
        match comment {
            Some(c) if c.contains("ASSUMPTION") || c.contains("CALIBRATED") => {
                if let Some(cur) = current.take() {
                    out.push(cur);
                }
                current = Some(c.to_string());
            }
            Some(c) if t.starts_with('#') && current.is_some() && !c.is_empty() => {
                if let Some(cur) = current.as_mut() {
                    cur.push(' ');
                    cur.push_str(c);
                }
            }
            _ => {
                if let Some(cur) = current.take() {
                    out.push(cur);
                }
            }
        }
    }
    if let Some(cur) = current {
        out.push(cur);
    }
    out
}

/// What one measured log gave.
#[derive(Debug, Clone, Serialize)]
pub struct TestLogResult {
    pub name: String,
    pub file: String,
    pub kind: crate::spec::LogKind,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<crate::signal::ToleranceReport>,
    /// Grms of every channel.
    pub channels: Vec<(String, f64)>,
    /// Resonances of the FRF control -> first response (sweep and signature logs).
    pub resonances: Vec<crate::signal::Resonance>,
    /// Curves for the report: (label, [(f, value)]).
    #[serde(skip)]
    pub curves: Vec<(String, Vec<(f64, f64)>)>,
    #[serde(skip)]
    pub log_scale_y: bool,
}

/// The test-data part of a qualification.
#[derive(Debug, Clone, Serialize)]
pub struct TestDataSummary {
    pub logs: Vec<TestLogResult>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub signature: Option<crate::signal::SignatureReport>,
}

/// Runs every `[[test_log]]` through the signal module and gates the results.
fn test_data(
    scene: &Scene,
    limits: &crate::spec::GatesSpec,
    gates: &mut Vec<Verdict>,
) -> Result<TestDataSummary, Error> {
    use crate::signal::{self as sg, Detrend, IngestOptions, PeakOptions, WelchOptions, Window};
    use crate::spec::LogKind;
    let dir = scene
        .path
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_default();
    let loc = scene.locator();
    let mut logs = Vec::new();
    let mut before: Option<Vec<sg::Resonance>> = None;
    let mut after: Option<Vec<sg::Resonance>> = None;
    for (i, t) in scene.file.test_log.iter().enumerate() {
        let key = |k: &str| format!("test_log[{i}].{k}");
        let path = dir.join(&t.file);
        let mut w = WelchOptions::default();
        if let Some(n) = t.nperseg {
            w.nperseg = n;
        }
        if let Some(o) = t.overlap {
            w.overlap = o;
        }
        if let Some(win) = &t.window {
            w.window = Window::parse(win).map_err(|e| loc.err(&key("window"), e.to_string()))?;
        }
        if let Some(d) = &t.detrend {
            w.detrend = Detrend::parse(d).map_err(|e| loc.err(&key("detrend"), e.to_string()))?;
        }
        w.validate()
            .map_err(|e| loc.err(&key("nperseg"), e.to_string()))?;
        let mut channels: Vec<String> = vec![t.control.clone()];
        channels.extend(t.responses.iter().cloned());
        let ingest = IngestOptions {
            fs: t.fs_hz,
            ..Default::default()
        };
        let mut res = TestLogResult {
            name: t.name.clone(),
            file: t.file.clone(),
            kind: t.kind,
            tolerance: None,
            channels: Vec::new(),
            resonances: Vec::new(),
            curves: Vec::new(),
            log_scale_y: true,
        };
        match t.kind {
            LogKind::Random => {
                // A UFF PSD record has no channel names to select by: take every channel then.
                let uff = sg::uff::looks_like_uff(&path);
                let ing = if uff {
                    ingest.clone()
                } else {
                    IngestOptions {
                        channels: Some(channels.clone()),
                        ..ingest.clone()
                    }
                };
                let psd = sg::psd_of_file(&path, &ing, &w)?;
                for c in &psd.channels {
                    res.channels.push((c.name.clone(), c.grms));
                }
                let control = if uff {
                    psd.channels.first()
                } else {
                    psd.channels.iter().find(|c| c.name == t.control)
                };
                let control = control.ok_or_else(|| {
                    loc.err(
                        &key("control"),
                        format!("channel `{}` is not in {}", t.control, t.file),
                    )
                })?;
                let f = control.psd.frequencies();
                let profile: Option<Vec<(f64, f64)>> = match (&t.profile, &t.profile_table) {
                    (_, Some(tab)) => Some(tab.iter().map(|p| (p[0], p[1])).collect()),
                    (Some(p), None) if p == "random" => {
                        scene.file.random.as_ref().map(|r| r.table())
                    }
                    (Some(p), None) => {
                        return Err(loc.err(&key("profile"), format!("`{p}`: use \"random\" (the scene's [random] profile) or give profile_table")).into());
                    }
                    (None, None) => None,
                };
                for c in &psd.channels {
                    let pts: Vec<(f64, f64)> = c
                        .psd
                        .frequencies()
                        .into_iter()
                        .zip(c.psd.values.iter().copied())
                        .filter(|p| p.0 > 0.0)
                        .collect();
                    res.curves
                        .push((format!("{} (Grms {:.3})", c.name, c.grms), pts));
                }
                if let Some(profile) = profile {
                    let spec = sg::ToleranceSpec {
                        alarm_db: limits.alarm_db,
                        abort_db: limits.abort_db,
                        grms_pct: limits.grms_tolerance_pct,
                    };
                    let rep = sg::tolerance_bands(&f, &control.psd.values, &profile, &spec)?;
                    gates.push(Verdict {
                        name: format!(
                            "{}: control lines beyond ±{} dB abort [%]",
                            t.name, limits.abort_db
                        ),
                        value: rep.fraction_outside_abort * 100.0,
                        limit: 0.0,
                        margin: -rep.fraction_outside_abort,
                        pass: rep.fraction_outside_abort == 0.0,
                        source: "GSFC-STD-7000 random test tolerance, [gates] abort_db".into(),
                    });
                    gates.push(gates::at_most(
                        format!("{}: control Grms departure from the profile [%]", t.name),
                        rep.grms_error_pct.abs(),
                        limits.grms_tolerance_pct,
                        "GSFC-STD-7000 Grms tolerance, [gates] grms_tolerance_pct",
                    ));
                    let (lo, hi) = (profile[0].0, profile[profile.len() - 1].0);
                    let band = |db: f64| -> Vec<(f64, f64)> {
                        crate::response::grid::log_n(lo, hi, 200)
                            .into_iter()
                            .map(|x| {
                                (
                                    x,
                                    crate::units::loglog_interp(&profile, x)
                                        * 10f64.powf(db / 10.0),
                                )
                            })
                            .collect()
                    };
                    res.curves.push(("profile".into(), band(0.0)));
                    res.curves.push((
                        format!("+{} dB alarm", limits.alarm_db),
                        band(limits.alarm_db),
                    ));
                    res.curves.push((
                        format!("−{} dB alarm", limits.alarm_db),
                        band(-limits.alarm_db),
                    ));
                    res.curves.push((
                        format!("+{} dB abort", limits.abort_db),
                        band(limits.abort_db),
                    ));
                    res.curves.push((
                        format!("−{} dB abort", limits.abort_db),
                        band(-limits.abort_db),
                    ));
                    res.tolerance = Some(rep);
                }
            }
            LogKind::SineSweep | LogKind::SignatureBefore | LogKind::SignatureAfter => {
                let output = t.responses.first().ok_or_else(|| {
                    loc.err(
                        &key("responses"),
                        "an FRF needs at least one response channel",
                    )
                })?;
                let h =
                    sg::frf_of_files(std::slice::from_ref(&path), &t.control, output, &ingest, &w)?;
                let f = h.frequencies();
                let h1 = h.h1();
                let coh = h.coherence();
                // The before-signature names the modes to watch (its 6 most prominent); the
                // after-signature is searched twice as wide, so that a mode whose prominence
                // merely changed rank is still matched rather than reported as lost.
                let max_peaks = if t.kind == LogKind::SignatureAfter {
                    12
                } else {
                    6
                };
                res.resonances = sg::resonances(
                    &f,
                    &h1,
                    &coh,
                    &PeakOptions {
                        max_peaks,
                        f_min_hz: f.get(1).copied().unwrap_or(0.0),
                        db_per_decade: 20.0,
                        ..Default::default()
                    },
                );
                res.curves.push((
                    format!("|H1| {output}/{}", t.control),
                    f.iter()
                        .zip(&h1)
                        .skip(1)
                        .map(|(x, v)| (*x, v.norm()))
                        .collect(),
                ));
                res.curves.push((
                    "coherence".into(),
                    f.iter().zip(&coh).skip(1).map(|(x, v)| (*x, *v)).collect(),
                ));
                match t.kind {
                    LogKind::SignatureBefore => before = Some(res.resonances.clone()),
                    LogKind::SignatureAfter => after = Some(res.resonances.clone()),
                    _ => {}
                }
            }
        }
        logs.push(res);
    }
    let signature = match (before, after) {
        (Some(b), Some(a)) => {
            let crit = sg::SignatureCriteria {
                max_shift_pct: limits.max_frequency_shift_pct,
                max_amp_change_pct: limits.max_amplitude_change_pct,
                ..Default::default()
            };
            let rep = sg::compare_signatures(&b, &a, &crit);
            for m in &rep.modes {
                let name = format!("signature mode {} ({:.2} Hz)", m.mode, m.before_hz);
                match (m.shift_pct, m.amplitude_change_pct) {
                    (Some(s), Some(amp)) => {
                        gates.push(gates::at_most(
                            format!("{name}: frequency shift [%]"),
                            s.abs(),
                            limits.max_frequency_shift_pct,
                            "GSFC-STD-7000 practice, [gates] max_frequency_shift_pct",
                        ));
                        gates.push(gates::at_most(
                            format!("{name}: amplitude change [%]"),
                            amp.abs(),
                            limits.max_amplitude_change_pct,
                            "GSFC-STD-7000 practice, [gates] max_amplitude_change_pct",
                        ));
                    }
                    _ => gates.push(Verdict {
                        name: format!("{name}: found after the test"),
                        value: f64::NAN,
                        limit: 0.0,
                        margin: -1.0,
                        pass: false,
                        source: m.reason.clone(),
                    }),
                }
            }
            Some(rep)
        }
        (Some(_), None) | (None, Some(_)) => {
            return Err(loc
                .err(
                    "test_log",
                    "a signature needs one signature-before and one signature-after log",
                )
                .into());
        }
        _ => None,
    };
    Ok(TestDataSummary { logs, signature })
}
