//! The low-args → high-args step: a scene is resolved once into a [`Plan`], with every
//! default filled in and every scene-level check done, so that each analysis receives typed,
//! complete inputs and nothing downstream reads the scene's optional sections again.

use crate::error::Error;
use crate::modal::ModalOptions;
use crate::results::Skipped;
use crate::separation::order_stats;
use crate::signal::{Detrend, IngestOptions, WelchOptions, Window};
use crate::spec::analysis::{RandomSpec, SineSpec, axis_index};
use crate::spec::separation::RunsWanted;
use crate::spec::{GatesSpec, LogKind, Scene, ShockSpec, SolverChoice, TestLogSpec};
use std::path::PathBuf;

/// Resonances `qualify` takes from a sweep or before-signature log: the modes to watch.
pub const SIGNATURE_MODES: usize = 6;

/// Everything `qualify` will run, with its inputs resolved.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Gate thresholds: `[gates]` or the defaults of `GatesSpec`.
    pub limits: GatesSpec,
    /// The modal analysis (needed by the sine and random responses too), or `None` if skipped.
    pub modal: Option<ModalOptions>,
    /// Only with a modal analysis: the response needs its modes.
    pub sine: Option<AxesPlan<SineSpec>>,
    pub random: Option<AxesPlan<RandomSpec>>,
    pub separation: Option<SeparationPlan>,
    pub test_logs: Vec<TestLogPlan>,
    /// The 2-satellite stack of the paper's shaker test: its results are compared with the
    /// paper's measurements.
    pub paper_shaker_test: bool,
    /// What the scene does not ask for, in report order.
    pub skipped: Vec<Skipped>,
}

/// A response analysis and the axes (0 = x, 1 = y, 2 = z) it runs on.
#[derive(Debug, Clone, PartialEq)]
pub struct AxesPlan<S> {
    pub spec: S,
    pub axes: Vec<usize>,
}

/// The in-orbit release and, with `runs > 0`, its Monte Carlo.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeparationPlan {
    pub monte_carlo: Option<MonteCarloPlan>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonteCarloPlan {
    pub runs: usize,
    pub seed: u64,
}

/// One `[[test_log]]` with its path, Welch settings and reference profile resolved.
#[derive(Debug, Clone)]
pub struct TestLogPlan {
    /// Position in the scene, for errors located at `test_log[index]`.
    pub index: usize,
    pub name: String,
    /// The file as written in the scene, and its path relative to the working directory.
    pub file: String,
    pub path: PathBuf,
    pub kind: LogKind,
    pub control: String,
    pub responses: Vec<String>,
    pub ingest: IngestOptions,
    pub welch: WelchOptions,
    /// Random logs: the profile the control is checked against, if any.
    pub profile: Option<Vec<(f64, f64)>>,
    /// Sweep and signature logs: the most prominent resonances kept.
    pub max_peaks: usize,
    /// Shock logs: the scene's `[shock]` specification.
    pub shock: Option<ShockSpec>,
}

/// Command-line overrides of `[modal]`; they take precedence over the scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct ModalOverrides {
    pub fmax_hz: Option<f64>,
    pub modes: Option<usize>,
    pub solver: Option<SolverChoice>,
}

impl Plan {
    /// Resolves what `qualify` runs on `scene`.
    pub fn resolve(scene: &Scene) -> Result<Plan, Error> {
        let f = &scene.file;
        let has_model = !scene.model.node.is_empty();
        let wants_response = f.sine.is_some() || f.random.is_some();
        let wants_modal = f.modal.is_some() || f.stack.is_some() || wants_response;
        let modal =
            (has_model && wants_modal).then(|| modal_options(scene, &ModalOverrides::default()));
        let (sine, random) = match modal {
            Some(_) => (
                f.sine.as_ref().map(|s| axes_plan(s, &s.axes)).transpose()?,
                f.random
                    .as_ref()
                    .map(|r| axes_plan(r, &r.axes))
                    .transpose()?,
            ),
            None => (None, None),
        };
        Ok(Plan {
            limits: f.gates.clone().unwrap_or_default(),
            modal,
            sine,
            random,
            separation: separation_plan(scene)?.map(|(plan, _)| plan),
            test_logs: test_logs(scene)?,
            paper_shaker_test: f.stack.as_ref().is_some_and(|s| s.satellites == 2),
            skipped: skipped(scene)?,
        })
    }
}

/// The modal options of a scene: `[modal]` (or its defaults: no frequency cap, no mode count,
/// automatic solver) unless overridden. A frequency cap or a mode count given on the command
/// line replaces both of the scene's. Every scene stops at the buckling solve when its static
/// loads exceed the buckling load: the modes of an unstable structure are not a result.
pub fn modal_options(scene: &Scene, overrides: &ModalOverrides) -> ModalOptions {
    let spec = scene.file.modal.clone().unwrap_or_default();
    let (fmax_hz, modes) = match (overrides.fmax_hz, overrides.modes) {
        (None, None) => (spec.fmax_hz, spec.modes),
        given => given,
    };
    ModalOptions {
        fmax_hz,
        modes,
        solver: overrides.solver.unwrap_or(spec.solver),
        stop_beyond_buckling: true,
        ..Default::default()
    }
}

/// The `[sine]` analysis of `satqual sine`, on `axis` or the scene's axes.
pub fn sine_command(scene: &Scene, axis: Option<&str>) -> Result<AxesPlan<SineSpec>, Error> {
    let spec = scene.file.sine.as_ref().ok_or_else(|| {
        missing_section(scene, "[sine]", "add [sine] with [[sine.segment]] levels")
    })?;
    axes_plan(spec, &command_axes(axis, &spec.axes))
}

/// The `[random]` analysis of `satqual random`, on `axis` or the scene's axes.
pub fn random_command(scene: &Scene, axis: Option<&str>) -> Result<AxesPlan<RandomSpec>, Error> {
    let spec = scene
        .file
        .random
        .as_ref()
        .ok_or_else(|| missing_section(scene, "[random]", "add [random] with a profile"))?;
    axes_plan(spec, &command_axes(axis, &spec.axes))
}

fn missing_section(scene: &Scene, section: &str, hint: &str) -> Error {
    Error::Other(format!(
        "{}: the scene has no {section} section ({hint})",
        scene.path.display()
    ))
}

fn command_axes(axis: Option<&str>, scene_axes: &[String]) -> Vec<String> {
    match axis {
        Some(a) => vec![a.to_string()],
        None => scene_axes.to_vec(),
    }
}

fn axes_plan<S: Clone>(spec: &S, names: &[String]) -> Result<AxesPlan<S>, Error> {
    let axes = names
        .iter()
        .map(|a| {
            axis_index(a)
                .ok_or_else(|| Error::Other(format!("--axis must be x, y or z, got `{a}`")))
        })
        .collect::<Result<_, _>>()?;
    Ok(AxesPlan {
        spec: spec.clone(),
        axes,
    })
}

/// The release and its Monte Carlo, with the reason when the Monte Carlo is not run.
fn separation_plan(scene: &Scene) -> Result<Option<(SeparationPlan, Option<String>)>, Error> {
    let Some(s) = scene.file.separation.as_ref() else {
        return Ok(None);
    };
    let d = &s.dispersion;
    let key = "separation.dispersion.runs";
    let wanted = d.runs_wanted().map_err(|e| scene.locator().err(key, e))?;
    let runs = match wanted {
        RunsWanted::Count(0) => Err("[separation.dispersion] runs = 0".to_string()),
        RunsWanted::Count(n) => Ok(n),
        RunsWanted::Auto if !d.disperses() => {
            Err("[separation.dispersion] declares no dispersion".to_string())
        }
        RunsWanted::Auto => Ok(auto_runs(scene, d.probability, d.confidence)?),
    };
    let monte_carlo = runs
        .as_ref()
        .ok()
        .map(|&runs| MonteCarloPlan { runs, seed: d.seed });
    Ok(Some((SeparationPlan { monte_carlo }, runs.err())))
}

/// The runs and seed of the Monte Carlo a scene's `[separation.dispersion]` asks for, if any.
pub fn dispersion_monte_carlo(scene: &Scene) -> Result<Option<MonteCarloPlan>, Error> {
    Ok(separation_plan(scene)?.and_then(|(plan, _)| plan.monte_carlo))
}

/// The scene's Monte Carlo seed, also when its `runs` ask for no Monte Carlo (0 without a
/// `[separation]`).
pub fn dispersion_seed(scene: &Scene) -> u64 {
    scene
        .file
        .separation
        .as_ref()
        .map_or(0, |s| s.dispersion.seed)
}

/// The fewest runs whose extreme sample bounds `probability` at `confidence` (Wilks).
fn auto_runs(scene: &Scene, probability: f64, confidence: f64) -> Result<usize, Error> {
    let n = order_stats::runs_needed(probability, confidence).unwrap_or(usize::MAX);
    let limit = scene.file.limits().monte_carlo_runs;
    if n > limit {
        let e = scene.locator().err(
            "separation.dispersion.probability",
            format!(
                "{probability} at {confidence} confidence needs {n} runs, above the limit of \
                 {limit}; {}",
                crate::spec::limits::raise_hint("monte_carlo_runs")
            ),
        );
        return Err(e.into());
    }
    Ok(n)
}

/// Refuses a Monte Carlo run count given on the command line (`flag`) above the scene's
/// `[limits] monte_carlo_runs`, before any run is made.
pub fn check_runs(scene: &Scene, runs: usize, flag: &str) -> Result<(), Error> {
    let limit = scene.file.limits().monte_carlo_runs;
    if runs > limit {
        return Err(Error::Other(format!(
            "{}: {flag} {runs} is above the limit of {limit} Monte Carlo runs (key `limits.monte_carlo_runs`); {}",
            scene.path.display(),
            crate::spec::limits::raise_hint("monte_carlo_runs")
        )));
    }
    Ok(())
}

/// What is not run and why, in the order the report lists it.
fn skipped(scene: &Scene) -> Result<Vec<Skipped>, Error> {
    let f = &scene.file;
    let has_model = !scene.model.node.is_empty();
    let wants_modal =
        f.modal.is_some() || f.stack.is_some() || f.sine.is_some() || f.random.is_some();
    let mut out = Vec::new();
    if !(has_model && wants_modal) {
        out.push(Skipped::new(
            "modal",
            if has_model {
                "the scene has no [modal] or [stack] section"
            } else {
                "the scene has no FE model"
            },
        ));
    }
    for (present, name) in [(f.sine.is_some(), "sine"), (f.random.is_some(), "random")] {
        if !present {
            out.push(Skipped::new(
                name,
                format!("the scene has no [{name}] section"),
            ));
        }
    }
    match separation_plan(scene)? {
        None => out.push(Skipped::new(
            "separation",
            "the scene has no [separation] section",
        )),
        Some((_, Some(why))) => out.push(Skipped::new("separation Monte Carlo", why)),
        Some(_) => {}
    }
    if let Some(why) = bar_strength_skipped(scene) {
        out.push(Skipped::new("bar strength", why));
    }
    if f.test_log.is_empty() {
        out.push(Skipped::new("test data", "the scene lists no [[test_log]]"));
    }
    Ok(out)
}

/// The guide bars' strength is gated from the responses against their material's yield and
/// ultimate strengths: without either, the gates cannot be made and the report says so.
fn bar_strength_skipped(scene: &Scene) -> Option<String> {
    let f = &scene.file;
    let stack = f.stack.as_ref()?;
    if f.sine.is_none() && f.random.is_none() {
        return None;
    }
    let m = f.material.iter().find(|m| m.name == stack.bar_material)?;
    (m.yield_strength_pa.is_none() && m.ultimate_strength_pa.is_none()).then(|| {
        format!(
            "the guide-bar material `{}` gives no yield_strength_pa or ultimate_strength_pa",
            m.name
        )
    })
}

/// Every `[[test_log]]`, resolved; a signature needs both its before and its after log.
fn test_logs(scene: &Scene) -> Result<Vec<TestLogPlan>, Error> {
    let logs = &scene.file.test_log;
    let plans = logs
        .iter()
        .enumerate()
        .map(|(i, t)| test_log(scene, i, t))
        .collect::<Result<Vec<_>, _>>()?;
    let has = |k: LogKind| logs.iter().any(|t| t.kind == k);
    if has(LogKind::SignatureBefore) != has(LogKind::SignatureAfter) {
        return Err(scene
            .locator()
            .err(
                "test_log",
                "a signature needs one signature-before and one signature-after log",
            )
            .into());
    }
    Ok(plans)
}

pub fn test_log(scene: &Scene, index: usize, t: &TestLogSpec) -> Result<TestLogPlan, Error> {
    let loc = scene.locator();
    let key = |k: &str| format!("test_log[{index}].{k}");
    let dir = scene
        .path
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_default();
    let welch = welch_options(t).map_err(|(k, e)| loc.err(&key(k), e))?;
    let profile = match t.kind {
        LogKind::Random => profile(scene, t).map_err(|msg| loc.err(&key("profile"), msg))?,
        _ => None,
    };
    let shock = match t.kind {
        LogKind::Shock => Some(scene.file.shock.clone().ok_or_else(|| {
            let msg = "a shock log is checked against the scene's [shock] specification; add [shock] with srs_g";
            loc.err(&key("kind"), msg)
        })?),
        _ => None,
    };
    let frf = !matches!(t.kind, LogKind::Random | LogKind::Shock | LogKind::Frf);
    if frf && t.responses.is_empty() {
        let msg = "an FRF needs at least one response channel";
        return Err(loc.err(&key("responses"), msg).into());
    }
    Ok(TestLogPlan {
        index,
        name: t.name.clone(),
        file: t.file.clone(),
        path: dir.join(&t.file),
        kind: t.kind,
        control: t.control.clone(),
        responses: t.responses.clone(),
        ingest: IngestOptions {
            fs: t.fs_hz,
            fs_name: "fs_hz",
            ..Default::default()
        },
        welch,
        profile,
        max_peaks: match t.kind {
            LogKind::SignatureAfter => {
                crate::pipeline::workflows::signature::after_peaks(SIGNATURE_MODES)
            }
            _ => SIGNATURE_MODES,
        },
        shock,
    })
}

/// A random log's reference profile: its own table, or "random" for the scene's `[random]`.
fn profile(scene: &Scene, t: &TestLogSpec) -> Result<Option<Vec<(f64, f64)>>, String> {
    match (&t.profile, &t.profile_table) {
        (Some(p), Some(_)) => Err(format!(
            "`{p}` and profile_table both name a reference: give one of them"
        )),
        (None, Some(tab)) => Ok(Some(tab.iter().map(|p| (p[0], p[1])).collect())),
        (Some(p), None) if p == "random" => match &scene.file.random {
            Some(r) => {
                let (applied, _) = r.applied(None).map_err(|e| {
                    format!("`random`: the scene's [random] profile cannot be the reference ({e}); give profile_table")
                })?;
                Ok(Some(applied.table()))
            }
            None => Err(
                "`random`: the scene has no [random] section to take the reference from; add it or give profile_table".into(),
            ),
        },
        (Some(p), None) => Err(format!(
            "`{p}`: use \"random\" (the scene's [random] profile) or give profile_table"
        )),
        (None, None) => Ok(None),
    }
}

/// The log's Welch settings over the defaults; an error names the offending key.
fn welch_options(t: &TestLogSpec) -> Result<WelchOptions, (&'static str, String)> {
    let mut w = WelchOptions::default();
    if let Some(n) = t.nperseg {
        w.nperseg = n;
    }
    if let Some(o) = t.overlap {
        w.overlap = o;
    }
    if let Some(win) = &t.window {
        w.window = Window::parse(win).map_err(|e| ("window", e.to_string()))?;
    }
    if let Some(d) = &t.detrend {
        w.detrend = Detrend::parse(d).map_err(|e| ("detrend", e.to_string()))?;
    }
    w.validate().map_err(|e| ("nperseg", e.to_string()))?;
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::WelchOptions;
    use std::path::Path;

    /// A one-beam cantilever: an FE model with no analysis section.
    const BEAM: &str = r#"
[[material]]
name = "steel"
youngs_modulus_pa = 210e9
poisson_ratio = 0.3
density_kg_m3 = 7850
[[section]]
name = "bar"
shape = "rectangle"
width_m = 0.02
height_m = 0.02
[[node]]
id = 1
position_m = [0.0, 0.0, 0.0]
[[node]]
id = 2
position_m = [1.0, 0.0, 0.0]
[[beam]]
nodes = [1, 2]
section = "bar"
material = "steel"
elements = 4
orientation = [0.0, 0.0, 1.0]
[[support]]
node = 1
dofs = "123456"
"#;

    const SINE: &str = r#"
[sine]
axes = ["z", "x"]
[[sine.segment]]
from_hz = 5.0
to_hz = 100.0
acceleration_g = 0.3
"#;

    fn scene(text: &str) -> Scene {
        Scene::parse(Path::new("specs/plan-test.toml"), text).unwrap_or_else(|e| panic!("{e}"))
    }

    fn analyses(skipped: &[Skipped]) -> Vec<&str> {
        skipped.iter().map(|s| s.analysis.as_str()).collect()
    }

    #[test]
    fn a_scene_without_modal_gets_the_documented_modal_defaults() {
        let s = scene(&format!("{BEAM}{SINE}"));
        let plan = Plan::resolve(&s).unwrap();
        // [modal] absent: no frequency cap, no mode count, automatic solver; beyond buckling
        // refused as in every scene.
        let m = plan.modal.expect("a response needs the modes");
        assert_eq!((m.fmax_hz, m.modes), (None, None));
        assert_eq!(m.solver, SolverChoice::Auto);
        assert!(m.stop_beyond_buckling);
    }

    #[test]
    fn a_scene_without_gates_gets_the_documented_limits() {
        let plan = Plan::resolve(&scene(BEAM)).unwrap();
        assert_eq!(plan.limits, GatesSpec::default());
        assert_eq!(plan.limits.min_lateral_frequency_hz, 10.0);
        assert_eq!(plan.limits.min_axial_frequency_hz, 25.0);
    }

    #[test]
    fn command_line_overrides_replace_both_the_cap_and_the_count() {
        let s = scene(&format!("{BEAM}[modal]\nmodes = 10\nsolver = \"dense\"\n"));
        let from_scene = modal_options(&s, &ModalOverrides::default());
        assert_eq!((from_scene.fmax_hz, from_scene.modes), (None, Some(10)));
        let overrides = ModalOverrides {
            fmax_hz: Some(200.0),
            ..Default::default()
        };
        let given = modal_options(&s, &overrides);
        assert_eq!((given.fmax_hz, given.modes), (Some(200.0), None));
        assert_eq!(given.solver, SolverChoice::Dense);
    }

    #[test]
    fn sine_axes_are_resolved_in_the_scenes_order_or_from_the_command_line() {
        let s = scene(&format!("{BEAM}{SINE}"));
        let plan = Plan::resolve(&s).unwrap();
        assert_eq!(plan.sine.unwrap().axes, vec![2, 0]);
        assert!(plan.random.is_none());
        assert_eq!(sine_command(&s, Some("y")).unwrap().axes, vec![1]);
        let e = sine_command(&s, Some("w")).unwrap_err().to_string();
        assert!(e.contains("--axis must be x, y or z, got `w`"), "{e}");
        let e = random_command(&s, None).unwrap_err().to_string();
        assert!(e.contains("the scene has no [random] section"), "{e}");
    }

    #[test]
    fn a_model_without_analysis_sections_skips_everything_in_report_order() {
        let plan = Plan::resolve(&scene(BEAM)).unwrap();
        assert!(plan.modal.is_none() && plan.separation.is_none());
        let expected = ["modal", "sine", "random", "separation", "test data"];
        assert_eq!(analyses(&plan.skipped), expected);
        assert_eq!(
            plan.skipped[0].reason,
            "the scene has no [modal] or [stack] section"
        );
    }

    /// A stack whose guide-bar material has neither strength gives no bar-strength gates: the
    /// plan lists them as skipped with the material's name instead of dropping them unseen.
    #[test]
    fn bar_strength_without_a_bar_strength_is_listed_as_skipped() {
        let sine = "[sine]\naxes = [\"x\"]\n[[sine.segment]]\nfrom_hz = 5.0\nto_hz = 100.0\nacceleration_g = 0.3\n";
        let text = crate::catalogue::generated::small_stack(1, 1.5, "", sine);
        let plan = Plan::resolve(&scene(&text)).unwrap();
        let s = plan.skipped.iter().find(|s| s.analysis == "bar strength");
        assert!(
            s.is_some_and(|s| s.reason.contains("`steel` gives no yield_strength_pa")),
            "{:?}",
            plan.skipped
        );
        let strong = text.replace(
            "density_kg_m3 = 7850\n",
            "density_kg_m3 = 7850\nyield_strength_pa = 835e6\n",
        );
        let plan = Plan::resolve(&scene(&strong)).unwrap();
        assert!(!analyses(&plan.skipped).contains(&"bar strength"));
    }

    #[test]
    fn test_logs_get_welch_defaults_and_signature_peak_counts() {
        let log = |name: &str, kind: &str| {
            format!(
                "[[test_log]]\nname = \"{name}\"\nfile = \"logs/{name}.csv\"\nkind = \"{kind}\"\ncontrol = \"force\"\nresponses = [\"acc\"]\n"
            )
        };
        let text = format!(
            "{}{}",
            log("pre", "signature-before"),
            log("post", "signature-after")
        );
        let plan = Plan::resolve(&scene(&text)).unwrap();
        let [pre, post] = &plan.test_logs[..] else {
            panic!("two logs planned")
        };
        assert_eq!(pre.path, Path::new("specs/logs/pre.csv"));
        let w = WelchOptions::default();
        assert_eq!(
            (pre.welch.nperseg, pre.welch.overlap),
            (w.nperseg, w.overlap)
        );
        assert_eq!(pre.max_peaks, SIGNATURE_MODES);
        assert_eq!(post.max_peaks, 2 * SIGNATURE_MODES);
        assert!(!analyses(&plan.skipped).contains(&"test data"));
    }

    #[test]
    fn a_signature_without_its_after_log_is_refused() {
        let text = "[[test_log]]\nname = \"pre\"\nfile = \"pre.csv\"\nkind = \"signature-before\"\ncontrol = \"force\"\nresponses = [\"acc\"]\n";
        let e = Plan::resolve(&scene(text)).unwrap_err().to_string();
        assert!(
            e.contains("one signature-before and one signature-after"),
            "{e}"
        );
    }
}
