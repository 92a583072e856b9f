//! Scene files: TOML text -> validated [`Scene`]. Owns the scene contract (unit-suffixed keys,
//! `deny_unknown_fields`; every key is listed in `docs/scene-format.md`, which a test keeps in
//! step with these types) and the mapping of every problem to a file, line, column and dotted
//! key. Inputs come from the user's scene file only.
//!
//! Locations: serde reports byte spans for syntax and type errors; semantic checks report a
//! dotted key path (`beam[2].orientation`), which [`Locator`] resolves to a line and column
//! through a span-preserving `toml_edit` parse of the same text.

pub mod analysis;
mod array_lengths;
pub mod calibration;
pub mod correlation;
mod count_or_word;
pub mod damping_edit;
#[cfg(test)]
mod doc_keys;
pub mod environment;
pub mod fixture;
pub mod limits;
pub mod model;
pub mod plausible;
pub mod qualify;
pub mod separation;
pub mod shock;
pub mod stack;
pub mod sweep;
pub mod update;
pub mod update_edit;

pub use model::*;
pub use qualify::{GatesSpec, LogKind, TestLogSpec};
pub use shock::ShockSpec;
pub use stack::{InterfaceSpec, StackSpec};

use crate::error::SpecError;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The top-level scene table. Each analysis section is optional: an analysis the scene does
/// not ask for is not run.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Free text shown in reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub material: Vec<Material>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub section: Vec<Section>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub node: Vec<Node>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub beam: Vec<Beam>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mass: Vec<Mass>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rigid: Vec<Rigid>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spring: Vec<Spring>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub preload: Vec<Preload>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support: Vec<Support>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub static_load: Vec<StaticLoad>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modal: Option<ModalSpec>,
    /// A parametric stack of satellites, expanded into the generic model so that every
    /// analysis sees one kind of model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stack: Option<StackSpec>,
    /// Pass/fail thresholds of `qualify` (defaults documented in `spec::qualify`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gates: Option<GatesSpec>,
    /// Measured logs to post-process and gate.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub test_log: Vec<TestLogSpec>,
    /// Measured channels mapped to model DOFs, for `satqual correlate`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub test_point: Vec<correlation::TestPointSpec>,
    /// Modes identified outside satqual, for `satqual correlate`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub test_modes: Option<correlation::TestModesSpec>,
    /// The correlation's frequency standard and the logs its modes are identified from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation: Option<correlation::CorrelationSpec>,
    /// The shock specification `kind = "shock"` logs are checked against.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shock: Option<ShockSpec>,
    /// The in-orbit release: springs, schedule, contact; the geometry comes from `[stack]` so
    /// that the release and the FE model describe the same hardware.
    #[serde(default)]
    pub separation: Option<separation::SeparationSpec>,
    /// Modal damping of the sine and random analyses; absent, Q = 10 ([`analysis::DEFAULT_Q`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<analysis::DampingSpec>,
    /// Sine-sweep base excitation; present, `qualify` runs the sine analysis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sine: Option<analysis::SineSpec>,
    /// Random base excitation; present, `qualify` runs the random analysis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random: Option<analysis::RandomSpec>,
    /// Named response points, added to the satellite CGs a `[stack]` gets by default.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub response: Vec<analysis::ResponsePoint>,
    /// Lock-integrity margin factors; every default and its source is in
    /// `analysis::MarginsSpec`, so that no factor of safety is written down twice.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margins: Option<analysis::MarginsSpec>,
    /// A parameter study of the release (`satqual separate SCENE --sweep`); other commands
    /// read the scene as written, without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<sweep::SweepSpec>,
    /// Model updating (`satqual update`): the parameters adjusted and the modes fitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub update: Option<update::UpdateSpec>,
    /// Values this scene took from a test scene updated to measurements.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<calibration::CalibrationSpec>,
    /// The largest work the scene may ask for; absent, the defaults of [`limits`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<limits::LimitsSpec>,
}

impl SceneFile {
    /// The scene's `[limits]`, or the defaults.
    pub fn limits(&self) -> limits::LimitsSpec {
        self.limits.clone().unwrap_or_default()
    }

    /// Mass of the model that is not the test article (a stack's shaker fixture plate), kg:
    /// an environment reduced for the article's weight leaves it out.
    pub fn fixture_mass_kg(&self) -> f64 {
        let fixture = self.stack.as_ref().and_then(|s| s.fixture.as_ref());
        fixture.map_or(0.0, |f| f.mass_kg)
    }
}

/// A loaded and validated scene, with its source kept for error locations and provenance.
#[derive(Debug, Clone)]
pub struct Scene {
    pub path: PathBuf,
    pub text: String,
    /// The scene as written.
    pub file: SceneFile,
    /// The generic model: the file itself, or its `[stack]` expanded.
    pub model: SceneFile,
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, crate::Error> {
        let text = std::fs::read_to_string(path).map_err(|e| crate::Error::io(path, e))?;
        Ok(Scene::parse(path, &text)?)
    }

    /// Parses and validates scene text; `path` is used in messages and for relative paths.
    pub fn parse(path: &Path, text: &str) -> Result<Scene, SpecError> {
        let loc = Locator::new(path, text)?;
        loc.check_finite()?;
        let file: SceneFile = toml::from_str(text).map_err(|e| loc.toml_error(&e))?;
        array_lengths::check(&loc, text, &file)?;
        let limits = file.limits();
        limits.validate(&loc)?;
        if let Some(stack) = &file.stack {
            stack.validate(&file.material, &limits, &loc)?;
        }
        let mut model = generic_model(&file, file.stack.as_ref());
        model::validate(&model, &loc)?;
        correlation::validate(&file, &model, &loc)?;
        if let Some(u) = &file.update {
            let test_modes = file.test_modes.as_ref().map(|t| t.mode.len());
            update::validate(u, test_modes, &loc)?;
        }
        // The test article carries its sensors: every analysis of this scene sees their mass.
        correlation::add_sensor_masses(&file, &mut model);
        qualify::validate(
            &file.gates.clone().unwrap_or_default(),
            &file.test_log,
            &loc,
        )?;
        if let Some(sh) = &file.shock {
            shock::validate(sh, &loc)?;
        }
        analysis::validate(&file, &model, &loc)?;
        if let Some(s) = &file.sweep {
            sweep::validate(s, &loc)?;
        }
        if let Some(c) = &file.calibration {
            calibration::validate(c, &loc)?;
        }
        Ok(Scene {
            path: path.to_path_buf(),
            text: text.to_string(),
            file,
            model,
        })
    }

    /// The generic model with the stack meshed for its buckling factor, when the scene asks
    /// for a finer column mesh there than for the modes (`StackSpec::buckling_stack`).
    pub fn buckling_model(&self) -> Option<SceneFile> {
        let fine = self.file.stack.as_ref()?.buckling_stack()?;
        let mut m = generic_model(&self.file, Some(&fine));
        correlation::add_sensor_masses(&self.file, &mut m);
        Some(m)
    }

    /// A locator for errors found after loading (e.g. a massless DOF at a node).
    pub fn locator(&self) -> Locator {
        Locator::new(&self.path, &self.text).expect("scene text parsed once already")
    }

    /// A short name for reports: the file stem.
    pub fn name(&self) -> String {
        self.path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into())
    }
}

/// The generic model of `file`: the file itself, or with `stack` expanded. It is one point of
/// the design space: `[sweep]` and `[update]` stay with the file.
fn generic_model(file: &SceneFile, stack: Option<&stack::StackSpec>) -> SceneFile {
    let mut m = file.clone();
    if let Some(stack) = stack {
        m.stack = None;
        stack.expand_into(&mut m);
    }
    m.sweep = None;
    m.update = None;
    m
}

/// Resolves dotted key paths and byte offsets of one scene text to lines and columns.
pub struct Locator {
    path: PathBuf,
    text: String,
    doc: toml_edit::Document<String>,
}

impl Locator {
    pub fn new(path: &Path, text: &str) -> Result<Locator, SpecError> {
        let doc = toml_edit::Document::parse(text.to_string()).map_err(|e| {
            let (line, column) = e.span().map(|s| line_col(text, s.start)).unwrap_or((0, 0));
            SpecError {
                file: path.to_path_buf(),
                line,
                column,
                key: String::new(),
                message: format!("invalid TOML: {}", e.message().trim()),
            }
        })?;
        Ok(Locator {
            path: path.to_path_buf(),
            text: text.to_string(),
            doc,
        })
    }

    /// The scene text's TOML tree, for reading values by key path.
    pub fn doc_item(&self) -> &toml_edit::Item {
        self.doc.as_item()
    }

    /// An error at the key `path` (dotted, with `[i]` indices), located in the file.
    pub fn err(&self, key: &str, message: impl Into<String>) -> SpecError {
        let (line, column) = self.find(key).unwrap_or((0, 0));
        SpecError {
            file: self.path.clone(),
            line,
            column,
            key: key.to_string(),
            message: message.into(),
        }
    }

    fn toml_error(&self, e: &toml::de::Error) -> SpecError {
        let span = e.span();
        let (line, column) = span
            .as_ref()
            .map(|s| line_col(&self.text, s.start))
            .unwrap_or((0, 0));
        let key = span.map(|s| self.path_at(s.start)).unwrap_or_default();
        SpecError {
            file: self.path.clone(),
            line,
            column,
            key,
            message: e.message().trim().replace('\n', " "),
        }
    }

    /// Line and column of the key named by a dotted path, or of the nearest existing parent.
    pub fn find(&self, key: &str) -> Option<(usize, usize)> {
        // Errors are rare: cloning sub-items keeps this simple and borrow-free.
        let mut item: toml_edit::Item = self.doc.as_item().clone();
        let mut best: Option<std::ops::Range<usize>> = None;
        for (name, index) in split_path(key) {
            let next = {
                let Some(table) = item.as_table_like() else {
                    break;
                };
                let Some((k, v)) = table.get_key_value(&name) else {
                    break;
                };
                best = k.span().or_else(|| v.span()).or(best);
                v.clone()
            };
            item = next;
            if let Some(i) = index {
                let next = if let Some(aot) = item.as_array_of_tables() {
                    aot.get(i).map(|t| {
                        best = t.span().or(best.clone());
                        toml_edit::Item::Table(t.clone())
                    })
                } else if let Some(arr) = item.as_array() {
                    arr.get(i).map(|v| {
                        best = v.span().or(best.clone());
                        toml_edit::Item::Value(v.clone())
                    })
                } else {
                    None
                };
                match next {
                    Some(n) => item = n,
                    None => break,
                }
            }
        }
        best.map(|s| line_col(&self.text, s.start))
    }

    /// The dotted path of the deepest key whose key or value span holds `offset`.
    fn path_at(&self, offset: usize) -> String {
        fn walk(item: &toml_edit::Item, offset: usize, prefix: String, out: &mut String) {
            match item {
                toml_edit::Item::Table(t) => {
                    for (k, v) in t.iter() {
                        let key = t.key(k).and_then(|k| k.span());
                        let p = if prefix.is_empty() {
                            k.to_string()
                        } else {
                            format!("{prefix}.{k}")
                        };
                        let inside = key.as_ref().is_some_and(|s| s.contains(&offset))
                            || v.span().is_some_and(|s| s.contains(&offset));
                        if inside {
                            *out = p.clone();
                        }
                        walk(v, offset, p, out);
                    }
                }
                toml_edit::Item::ArrayOfTables(a) => {
                    for (i, t) in a.iter().enumerate() {
                        let p = format!("{prefix}[{i}]");
                        if t.span().is_some_and(|s| s.contains(&offset)) {
                            *out = p.clone();
                        }
                        walk(&toml_edit::Item::Table(t.clone()), offset, p, out);
                    }
                }
                toml_edit::Item::Value(toml_edit::Value::InlineTable(t)) => {
                    for (k, v) in t.iter() {
                        let p = format!("{prefix}.{k}");
                        if v.span().is_some_and(|s| s.contains(&offset)) {
                            *out = p.clone();
                        }
                        walk(&toml_edit::Item::Value(v.clone()), offset, p, out);
                    }
                }
                _ => {}
            }
        }
        let mut out = String::new();
        walk(self.doc.as_item(), offset, String::new(), &mut out);
        // A `[[table]]` span covers only its header; attribute later offsets to the last
        // array-of-tables entry that starts before the offset.
        if out.is_empty() {
            out = self.last_table_before(offset);
        }
        out
    }

    fn last_table_before(&self, offset: usize) -> String {
        let mut best: (usize, String) = (0, String::new());
        for (k, v) in self.doc.iter() {
            if let Some(a) = v.as_array_of_tables() {
                for (i, t) in a.iter().enumerate() {
                    if let Some(s) = t.span()
                        && s.start <= offset
                        && s.start >= best.0
                    {
                        best = (s.start, format!("{k}[{i}]"));
                    }
                }
            } else if let Some(t) = v.as_table()
                && let Some(s) = t.span()
                && s.start <= offset
                && s.start >= best.0
            {
                best = (s.start, k.to_string());
            }
        }
        best.1
    }

    /// TOML accepts `nan` and `inf`; a scene never means them. Reject every non-finite float,
    /// wherever it stands.
    fn check_finite(&self) -> Result<(), SpecError> {
        fn walk(item: &toml_edit::Item, path: String, loc: &Locator) -> Result<(), SpecError> {
            match item {
                toml_edit::Item::Table(t) => {
                    for (k, v) in t.iter() {
                        let p = if path.is_empty() {
                            k.to_string()
                        } else {
                            format!("{path}.{k}")
                        };
                        walk(v, p, loc)?;
                    }
                }
                toml_edit::Item::ArrayOfTables(a) => {
                    for (i, t) in a.iter().enumerate() {
                        walk(
                            &toml_edit::Item::Table(t.clone()),
                            format!("{path}[{i}]"),
                            loc,
                        )?;
                    }
                }
                toml_edit::Item::Value(v) => value(v, path, loc)?,
                toml_edit::Item::None => {}
            }
            Ok(())
        }
        fn value(v: &toml_edit::Value, path: String, loc: &Locator) -> Result<(), SpecError> {
            match v {
                toml_edit::Value::Float(f) if !f.value().is_finite() => {
                    let (line, column) = v
                        .span()
                        .map(|s| line_col(&loc.text, s.start))
                        .unwrap_or((0, 0));
                    return Err(SpecError {
                        file: loc.path.clone(),
                        line,
                        column,
                        key: path,
                        message: format!("the value {} is not a finite number", f.value()),
                    });
                }
                toml_edit::Value::Array(a) => {
                    for (i, x) in a.iter().enumerate() {
                        value(x, format!("{path}[{i}]"), loc)?;
                    }
                }
                toml_edit::Value::InlineTable(t) => {
                    for (k, x) in t.iter() {
                        value(x, format!("{path}.{k}"), loc)?;
                    }
                }
                _ => {}
            }
            Ok(())
        }
        walk(self.doc.as_item(), String::new(), self)
    }
}

/// Splits `a.b[2].c` into `[("a", None), ("b", Some(2)), ("c", None)]`.
pub(crate) fn split_path(key: &str) -> Vec<(String, Option<usize>)> {
    key.split('.')
        .filter(|s| !s.is_empty())
        .map(|part| match part.find('[') {
            Some(i) => {
                let idx = part[i + 1..].trim_end_matches(']').parse().ok();
                (part[..i].to_string(), idx)
            }
            None => (part.to_string(), None),
        })
        .collect()
}

/// 1-based line and column (in characters) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rsplit('\n')
        .next()
        .map(|s| s.chars().count())
        .unwrap_or(0)
        + 1;
    (line, col)
}
