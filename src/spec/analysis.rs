//! The response-analysis sections of a scene: `[damping]`, `[sine]` with `[[sine.segment]]`,
//! `[random]`, `[[response]]` output points and `[margins]` (the lock-integrity factors).
//! Read by `response` (sine, random, load recovery, margins) and by `gates`/`pipeline`.
//!
//! Every default of the lock-integrity margins lives in [`MarginsSpec::default`], with its
//! source; nowhere else in the code is a factor of safety written down.

use super::Locator;
use super::plausible;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

/// Modal damping. Exactly one of `q`, `zeta` or `table` (the base, for every mode), and
/// optionally `modes`, per-mode values that take precedence over the base for the modes they
/// name (e.g. ratios identified by `satqual ema`); absent section = [`DEFAULT_Q`].
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Amplification Q = 1/(2ζ) of every mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q: Option<f64>,
    /// Critical-damping ratio ζ of every mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zeta: Option<f64>,
    /// `[[f_hz, zeta], ...]`, increasing f; interpolated as `interpolation` says, constant
    /// beyond the ends.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<Vec<[f64; 2]>>,
    /// How `table` is read between its points: `linear` (ζ linear in f, as Nastran's TABDMP1)
    /// or `log` (log ζ linear in log f).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interpolation: Option<String>,
    /// Per-mode ratios, by 1-based mode number.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<Vec<ModeDamping>>,
}

/// The damping ratio of one mode, by its 1-based number in frequency order.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModeDamping {
    pub mode: usize,
    pub zeta: f64,
    /// The direction (x, y, z, rx, ry, rz) of the mode's largest effective-mass fraction, when
    /// the ratio belongs to a mode family (the test's first axial mode, say): a model change
    /// that renumbers the modes is then refused instead of damping another mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<String>,
}

/// The directions a mode's effective mass is measured in, in `Dir6` order.
pub const MODE_DIRECTIONS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// Default amplification when a scene asks for a response but gives no `[damping]`: Q = 10
/// (ζ = 5 %), the customary preliminary value for bolted spacecraft structure (ECSS-E-HB-32-26A
/// §4.2.4; NASA-HDBK-7005 §4.5 quotes Q = 10 as the typical design assumption).
pub const DEFAULT_Q: f64 = 10.0;

impl DampingSpec {
    /// ζ of mode `number` (1-based) at frequency `f_hz`: its `modes` entry when there is one,
    /// the base otherwise.
    pub fn zeta_of_mode(&self, number: usize, f_hz: f64) -> f64 {
        self.modes
            .iter()
            .flatten()
            .find(|m| m.mode == number)
            .map_or_else(|| self.zeta_at(f_hz), |m| m.zeta)
    }

    /// The base ζ at frequency `f_hz` (what a mode without a `modes` entry gets).
    pub fn zeta_at(&self, f_hz: f64) -> f64 {
        if let Some(z) = self.zeta {
            return z;
        }
        if let Some(q) = self.q {
            return 0.5 / q;
        }
        if let Some(t) = &self.table
            && !t.is_empty()
        {
            return table_zeta(t, f_hz, self.interpolation.as_deref() == Some("log"));
        }
        0.5 / DEFAULT_Q
    }
}

/// ζ(f) from the table: constant beyond the ends (TABDMP1 with FLAT = 1: Nastran's default
/// extrapolates linearly, which can drive ζ negative past a falling end); between points
/// linear in f and ζ, or, with `log`, linear in log f and log ζ.
fn table_zeta(t: &[[f64; 2]], f_hz: f64, log: bool) -> f64 {
    if f_hz <= t[0][0] {
        return t[0][1];
    }
    for w in t.windows(2) {
        if f_hz <= w[1][0] {
            let (f0, z0, f1, z1) = (w[0][0], w[0][1], w[1][0], w[1][1]);
            return if log {
                let s = (f_hz / f0).ln() / (f1 / f0).ln();
                z0 * (z1 / z0).powf(s)
            } else {
                z0 + (f_hz - f0) / (f1 - f0) * (z1 - z0)
            };
        }
    }
    t[t.len() - 1][1]
}

/// One segment of a sine-sweep level: a zero-to-peak base displacement (a = (2πf)²·d) or a
/// base acceleration, from `from_hz` to `to_hz`.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SineSegment {
    pub from_hz: f64,
    pub to_hz: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub acceleration_g: Option<f64>,
}

impl SineSegment {
    /// Base acceleration amplitude at `f_hz`, g.
    pub fn level_g(&self, f_hz: f64) -> f64 {
        match (self.displacement_m, self.acceleration_g) {
            (Some(d), _) => (2.0 * std::f64::consts::PI * f_hz).powi(2) * d / crate::units::G,
            (None, Some(a)) => a,
            (None, None) => 0.0,
        }
    }

    /// The segment with its level multiplied by `factor`.
    pub fn scaled(&self, factor: f64) -> SineSegment {
        SineSegment {
            displacement_m: self.displacement_m.map(|d| d * factor),
            acceleration_g: self.acceleration_g.map(|a| a * factor),
            ..self.clone()
        }
    }
}

/// `[sine]`: the sweep level, contiguous segments, applied along each axis in turn.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SineSpec {
    #[serde(default = "all_axes")]
    pub axes: Vec<String>,
    #[serde(default)]
    pub segment: Vec<SineSegment>,
    /// Where the level comes from (a standard, a launcher's manual, a paper section): shown
    /// with the environment in the report.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// The test level: sets the default sweep rate, and with `basis = "limit"` the factor on
    /// the segments.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<super::environment::TestLevel>,
    /// What the segments are: the test input itself (`test`, default) or the limit level
    /// (maximum expected flight level) that `level` raises to the test input.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub basis: Option<super::environment::SineBasis>,
    /// Logarithmic sweep rate, octaves per minute (reported with the sweep duration; the
    /// steady-state peaks do not depend on it). Default: the level's rate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep_rate_oct_min: Option<f64>,
}

impl SineSpec {
    /// Base acceleration amplitude applied at `f_hz` (g), the level factor included; 0
    /// outside the profile.
    pub fn level_g(&self, f_hz: f64) -> f64 {
        let n = self.segment.len();
        for (i, s) in self.segment.iter().enumerate() {
            // Half-open segments, the last one closed: a shared boundary belongs to the
            // segment that starts there.
            if f_hz >= s.from_hz && (f_hz < s.to_hz || (i + 1 == n && f_hz <= s.to_hz)) {
                return self.level_factor() * s.level_g(f_hz);
            }
        }
        0.0
    }

    /// Factor from the segments to the applied input: the level's for limit-level segments,
    /// 1 for test-level ones.
    pub fn level_factor(&self) -> f64 {
        match (self.basis.unwrap_or_default(), self.level) {
            (super::environment::SineBasis::Limit, Some(l)) => l.sine_factor(),
            _ => 1.0,
        }
    }
    pub fn band(&self) -> (f64, f64) {
        (
            self.segment.first().map(|s| s.from_hz).unwrap_or(0.0),
            self.segment.last().map(|s| s.to_hz).unwrap_or(0.0),
        )
    }
}

/// `[random]`: a base-acceleration PSD, log-log between its points, applied along each axis.
/// Either an explicit `profile` (the test input as given) or a named `environment` at its
/// limit level, raised to the test `level` and optionally reduced for the model's weight; see
/// `spec::environment`.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RandomSpec {
    #[serde(default = "all_axes")]
    pub axes: Vec<String>,
    /// `[[f_hz, g2_hz], ...]`: the input as applied (no level factor, no weight reduction).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub profile: Vec<[f64; 2]>,
    /// Where an explicit `profile` comes from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// A named table of `spec::environment::NAMED` (e.g. `gevs-component`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<String>,
    /// The test level; scales a named `environment` (qualification and protoflight +3 dB) and
    /// sets the default duration. With an explicit `profile` it only labels it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<super::environment::TestLevel>,
    /// `gevs`: the GSFC-STD-7000A weight-based reduction of `gevs-component` for the model's
    /// mass; `none` (default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weight_reduction: Option<super::environment::WeightReduction>,
    /// Test duration per axis, s (reported; the 3σ figures do not depend on it). Default: the
    /// level's duration.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

impl RandomSpec {
    pub fn table(&self) -> Vec<(f64, f64)> {
        self.profile.iter().map(|p| (p[0], p[1])).collect()
    }

    /// The section with its named environment, level and weight reduction applied for a model
    /// of `mass_kg`: an explicit profile, as the analyses read it, and the record of how it
    /// was made.
    pub fn applied(
        &self,
        mass_kg: Option<f64>,
    ) -> Result<(RandomSpec, super::environment::RandomEnvironment), String> {
        let env = super::environment::resolve(self, mass_kg)?;
        let spec = RandomSpec {
            axes: self.axes.clone(),
            profile: env.profile.clone(),
            source: Some(env.source.clone()),
            environment: None,
            level: env.level,
            weight_reduction: None,
            duration_s: env.duration_s,
        };
        Ok((spec, env))
    }
}

/// A named output point: absolute acceleration of a node along the excitation axis.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ResponsePoint {
    pub name: String,
    pub node: i64,
}

fn all_axes() -> Vec<String> {
    vec!["x".into(), "y".into(), "z".into()]
}

/// `[margins]`: factors of the lock-integrity margins. Every default is here, with its source.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct MarginsSpec {
    /// Fitting factor on joint loads. NASA-STD-5020B §4.3 (1.15 for a separation/gapping check
    /// of a joint without a fitting-factor test).
    pub fitting_factor: f64,
    /// Factor of safety against separation (gapping). NASA-STD-5020B Table 1 (1.2 for a
    /// separation-critical joint, tested).
    pub separation_factor: f64,
    /// Friction coefficient of the preloaded column faces. NASA-STD-5020B §4.4.2 (0.2 for
    /// uncoated metal faces when no test data exist).
    pub friction_coefficient: f64,
    /// Factor of safety against slip. NASA-STD-5020B §4.4.2 (1.0: slip is checked at limit
    /// load for joints whose strength does not rely on friction).
    pub slip_factor: f64,
    /// Preload uncertainty, ± fraction of nominal. NASA-STD-5020B §4.2 (a torque-controlled
    /// preload has ±25–35 %; ±10 % for a compression device with a load-measured preload, as
    /// the paper's 45 kN is; ASSUMPTION that it was measured).
    pub preload_uncertainty: f64,
    /// Preload loss allowance (creep, relaxation, embedding), fraction of nominal.
    /// NASA-STD-5020B §4.2 (5 % short-term relaxation allowance when no test data exist).
    pub preload_loss: f64,
    /// Yield factor of safety for the guide bars. GSFC-STD-7000A Table 2.2-1 / NASA-STD-5001B
    /// Table 1 (1.25 for a qualification-tested metallic part).
    pub yield_factor: f64,
    /// Ultimate factor of safety for the guide bars. NASA-STD-5001B Table 1 (1.4).
    pub ultimate_factor: f64,
    /// Add the joint's bending moment to the gapping load as M·A/Z of the column-tube face
    /// (the moment that lifts the face edge as much as that axial tension would). On by
    /// default: in a preloaded column under lateral load the bending moment at the joint
    /// unloads one edge of the face, and that edge opens first; gapping of a column joint
    /// under bending is the governing case of preloaded joints (NASA-STD-5020B §4.4.1 takes
    /// the external load that unloads the joint, whatever its source). The tube face is the
    /// scene's contact face; a wider flange would lift less.
    pub include_face_moment: bool,
}

impl Default for MarginsSpec {
    fn default() -> Self {
        MarginsSpec {
            fitting_factor: 1.15,
            separation_factor: 1.2,
            friction_coefficient: 0.2,
            slip_factor: 1.0,
            preload_uncertainty: 0.10,
            preload_loss: 0.05,
            yield_factor: 1.25,
            ultimate_factor: 1.4,
            include_face_moment: true,
        }
    }
}

impl MarginsSpec {
    /// Lowest preload the joint may see: nominal·(1 − uncertainty)·(1 − loss).
    pub fn min_preload(&self, nominal: f64) -> f64 {
        nominal * (1.0 - self.preload_uncertainty) * (1.0 - self.preload_loss)
    }
    /// Highest preload (for the strength of the tension members): nominal·(1 + uncertainty).
    pub fn max_preload(&self, nominal: f64) -> f64 {
        nominal * (1.0 + self.preload_uncertainty)
    }
}

/// Axis name -> DOF index (0, 1, 2).
pub fn axis_index(a: &str) -> Option<usize> {
    match a {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

/// The plausible ranges of a sine segment's band and level.
fn check_sine_segment(
    g: &SineSegment,
    k: &dyn Fn(&str) -> String,
    loc: &Locator,
) -> Result<(), SpecError> {
    plausible::check(loc, &k("from_hz"), g.from_hz, plausible::FREQUENCY_HZ)?;
    plausible::check(loc, &k("to_hz"), g.to_hz, plausible::FREQUENCY_HZ)?;
    if let Some(a) = g.acceleration_g {
        plausible::check(loc, &k("acceleration_g"), a, plausible::ACCELERATION_G)?;
    }
    if let Some(d) = g.displacement_m {
        plausible::check(loc, &k("displacement_m"), d, plausible::DISPLACEMENT_M)?;
    }
    Ok(())
}

/// The source of the random input: exactly one of an explicit profile or a named table; a
/// weight reduction only of the table it is written for.
fn validate_random_source(r: &RandomSpec, loc: &Locator) -> Result<(), SpecError> {
    use super::environment::{GEVS_COMPONENT, WeightReduction, named, unknown};
    match (&r.environment, r.profile.is_empty()) {
        (Some(_), false) => {
            return Err(loc.err(
                "random.environment",
                "give either `profile` or `environment`, not both",
            ));
        }
        (None, true) => {
            return Err(loc.err(
                "random",
                "give a `profile` (at least two points) or a named `environment`",
            ));
        }
        (Some(name), true) if named(name).is_none() => {
            return Err(loc.err("random.environment", unknown(name)));
        }
        _ => {}
    }
    if r.weight_reduction == Some(WeightReduction::Gevs)
        && r.environment.as_deref() != Some(GEVS_COMPONENT)
    {
        return Err(loc.err(
            "random.weight_reduction",
            format!(
                "the GEVS weight reduction is written for the GEVS component table: set environment = \"{GEVS_COMPONENT}\""
            ),
        ));
    }
    Ok(())
}

/// `damping.interpolation` and `damping.modes`.
fn validate_mode_damping(d: &DampingSpec, loc: &Locator) -> Result<(), SpecError> {
    if let Some(i) = &d.interpolation {
        if i != "linear" && i != "log" {
            return Err(loc.err(
                "damping.interpolation",
                format!("expected `linear` or `log`, got `{i}`"),
            ));
        }
        let Some(t) = &d.table else {
            return Err(loc.err("damping.interpolation", "applies to `table` only"));
        };
        if i == "log" && t.first().is_some_and(|p| p[0] <= 0.0) {
            return Err(loc.err(
                "damping.table[0]",
                "log interpolation needs frequencies above 0 Hz",
            ));
        }
    }
    for (i, m) in d.modes.iter().flatten().enumerate() {
        let k = format!("damping.modes[{i}]");
        if m.mode == 0 {
            return Err(loc.err(&format!("{k}.mode"), "modes are numbered from 1"));
        }
        if d.modes.iter().flatten().take(i).any(|o| o.mode == m.mode) {
            return Err(loc.err(
                &format!("{k}.mode"),
                format!("mode {} is given twice", m.mode),
            ));
        }
        if !(m.zeta > 0.0 && m.zeta < 1.0) {
            return Err(loc.err(
                &format!("{k}.zeta"),
                format!("the damping ratio must lie in (0, 1), got {}", m.zeta),
            ));
        }
        plausible::check(loc, &format!("{k}.zeta"), m.zeta, plausible::ZETA)?;
        if let Some(d) = m
            .direction
            .as_deref()
            .filter(|d| !MODE_DIRECTIONS.contains(d))
        {
            return Err(loc.err(
                &format!("{k}.direction"),
                format!("expected one of x, y, z, rx, ry, rz, got `{d}`"),
            ));
        }
    }
    Ok(())
}

/// The points `[f_hz, g2_hz]` of a PSD profile at `key`: positive and plausible frequencies and
/// levels (log-log interpolation), frequencies increasing.
pub(super) fn validate_psd_points(
    points: &[[f64; 2]],
    key: &str,
    loc: &Locator,
) -> Result<(), SpecError> {
    for (i, p) in points.iter().enumerate() {
        let k = format!("{key}[{i}]");
        if p[0] <= 0.0 {
            return Err(loc.err(&k, format!("frequencies must be positive, got {} Hz", p[0])));
        }
        if p[1] <= 0.0 {
            return Err(loc.err(
                &k,
                format!(
                    "the PSD level must be positive (log-log interpolation), got {} g²/Hz",
                    p[1]
                ),
            ));
        }
        plausible::check(loc, &k, p[0], plausible::FREQUENCY_HZ)?;
        plausible::check(loc, &k, p[1], plausible::PSD_G2_HZ)?;
        if i > 0 && p[0] <= points[i - 1][0] {
            return Err(loc.err(
                &k,
                format!(
                    "profile frequencies must increase: {} Hz follows {} Hz",
                    p[0],
                    points[i - 1][0]
                ),
            ));
        }
    }
    Ok(())
}

/// Checks `[random]`: its source, then the explicit profile's points and the duration.
fn validate_random(r: &RandomSpec, loc: &Locator) -> Result<(), SpecError> {
    let check_axes = axes_checker(loc);
    check_axes("random.axes", &r.axes)?;
    validate_random_source(r, loc)?;
    if r.environment.is_none() && r.profile.len() < 2 {
        return Err(loc.err("random.profile", "the profile needs at least two points"));
    }
    validate_psd_points(&r.profile, "random.profile", loc)?;
    if let Some(d) = r.duration_s
        && d <= 0.0
    {
        return Err(loc.err("random.duration_s", format!("must be positive, got {d}")));
    }
    if let Some(d) = r.duration_s {
        plausible::check(loc, "random.duration_s", d, plausible::DURATION_S)?;
    }
    Ok(())
}

/// A checker of an `axes` list: at least one, each x, y or z.
fn axes_checker(loc: &Locator) -> impl Fn(&str, &[String]) -> Result<(), SpecError> + '_ {
    move |key: &str, axes: &[String]| -> Result<(), SpecError> {
        if axes.is_empty() {
            return Err(loc.err(key, "name at least one axis (x, y or z)"));
        }
        for (i, a) in axes.iter().enumerate() {
            if axis_index(a).is_none() {
                return Err(loc.err(
                    &format!("{key}[{i}]"),
                    format!("unknown axis `{a}`: use x, y or z"),
                ));
            }
            if axes[..i].iter().any(|b| axis_index(b) == axis_index(a)) {
                return Err(loc.err(
                    &format!("{key}[{i}]"),
                    format!("axis `{a}` is listed twice"),
                ));
            }
        }
        Ok(())
    }
}

/// Checks the response sections. `model` is the expanded generic model (for node references).
pub fn validate(
    file: &super::SceneFile,
    model: &super::SceneFile,
    loc: &Locator,
) -> Result<(), SpecError> {
    if let Some(d) = &file.damping {
        let given = [d.q.is_some(), d.zeta.is_some(), d.table.is_some()]
            .iter()
            .filter(|&&b| b)
            .count();
        if given != 1 {
            return Err(loc.err(
                "damping",
                "give exactly one of `q`, `zeta` or `table` (with `modes`, it is the damping of the modes `modes` does not list)",
            ));
        }
        validate_mode_damping(d, loc)?;
        if let Some(q) = d.q
            && q <= 0.5
        {
            return Err(loc.err(
                "damping.q",
                format!("the amplification Q must be above 0.5 (ζ < 1), got {q}"),
            ));
        }
        if let Some(q) = d.q {
            plausible::check(loc, "damping.q", q, plausible::Q)?;
        }
        if let Some(z) = d.zeta
            && (z <= 0.0 || z >= 1.0)
        {
            return Err(loc.err(
                "damping.zeta",
                format!("the damping ratio must lie in (0, 1), got {z}"),
            ));
        }
        if let Some(z) = d.zeta {
            plausible::check(loc, "damping.zeta", z, plausible::ZETA)?;
        }
        if let Some(t) = &d.table {
            if t.is_empty() {
                return Err(loc.err("damping.table", "the table is empty"));
            }
            for (i, p) in t.iter().enumerate() {
                let k = format!("damping.table[{i}]");
                if p[1] <= 0.0 || p[1] >= 1.0 {
                    return Err(loc.err(
                        &k,
                        format!("the damping ratio must lie in (0, 1), got {}", p[1]),
                    ));
                }
                plausible::check(loc, &k, p[1], plausible::ZETA)?;
                if !p[0].is_finite() || p[0] < 0.0 {
                    return Err(loc.err(&k, format!("negative frequency {} Hz", p[0])));
                }
                if i > 0 && p[0] <= t[i - 1][0] {
                    return Err(loc.err(
                        &k,
                        format!(
                            "frequencies must increase: {} Hz follows {} Hz",
                            p[0],
                            t[i - 1][0]
                        ),
                    ));
                }
            }
        }
    }
    let check_axes = axes_checker(loc);
    if let Some(s) = &file.sine {
        check_axes("sine.axes", &s.axes)?;
        if s.basis == Some(super::environment::SineBasis::Limit) && s.level.is_none() {
            return Err(loc.err(
                "sine.basis",
                "limit-level segments need `level` (qualification, protoflight or acceptance), which sets the factor applied to them",
            ));
        }
        if let Some(r) = s.sweep_rate_oct_min
            && !(r > 0.0 && r.is_finite())
        {
            return Err(loc.err(
                "sine.sweep_rate_oct_min",
                format!("must be a positive rate, got {r}"),
            ));
        }
        if s.segment.is_empty() {
            return Err(loc.err("sine", "the sine level needs at least one [[sine.segment]]"));
        }
        for (i, g) in s.segment.iter().enumerate() {
            let k = |x: &str| format!("sine.segment[{i}].{x}");
            if g.from_hz <= 0.0 {
                return Err(loc.err(
                    &k("from_hz"),
                    format!("must be a positive frequency, got {}", g.from_hz),
                ));
            }
            if g.to_hz <= g.from_hz {
                return Err(loc.err(
                    &k("to_hz"),
                    format!(
                        "the segment must run to a higher frequency: {} Hz to {} Hz",
                        g.from_hz, g.to_hz
                    ),
                ));
            }
            match (g.displacement_m, g.acceleration_g) {
                (Some(_), Some(_)) | (None, None) => {
                    return Err(loc.err(
                        &format!("sine.segment[{i}]"),
                        "give exactly one of `displacement_m` or `acceleration_g`",
                    ));
                }
                (Some(d), None) if d <= 0.0 => {
                    return Err(loc.err(
                        &k("displacement_m"),
                        format!("the level must be positive, got {d}"),
                    ));
                }
                (None, Some(a)) if a <= 0.0 => {
                    return Err(loc.err(
                        &k("acceleration_g"),
                        format!("the level must be positive, got {a}"),
                    ));
                }
                _ => {}
            }
            check_sine_segment(g, &k, loc)?;
            if i > 0 {
                let prev = s.segment[i - 1].to_hz;
                let rel = (g.from_hz - prev).abs() / prev;
                if rel > 1e-9 {
                    let what = if g.from_hz > prev {
                        "a gap"
                    } else {
                        "an overlap"
                    };
                    return Err(loc.err(
                        &k("from_hz"),
                        format!(
                            "{what} between segments: segment {} ends at {prev} Hz but this one starts at {} Hz; segments must be contiguous",
                            i - 1,
                            g.from_hz
                        ),
                    ));
                }
            }
        }
    }
    if let Some(r) = &file.random {
        validate_random(r, loc)?;
    }
    let mut names = std::collections::HashSet::new();
    for (i, p) in file.response.iter().enumerate() {
        if !model.node.iter().any(|n| n.id == p.node) {
            return Err(loc.err(
                &format!("response[{i}].node"),
                format!(
                    "response point `{}` names node {}, which is not defined",
                    p.name, p.node
                ),
            ));
        }
        if !names.insert(p.name.as_str()) {
            return Err(loc.err(
                &format!("response[{i}].name"),
                format!("duplicate response point name `{}`", p.name),
            ));
        }
    }
    if let Some(m) = &file.margins {
        for (key, v) in [
            ("fitting_factor", m.fitting_factor),
            ("separation_factor", m.separation_factor),
            ("slip_factor", m.slip_factor),
            ("yield_factor", m.yield_factor),
            ("ultimate_factor", m.ultimate_factor),
        ] {
            if v < 1.0 {
                return Err(loc.err(
                    &format!("margins.{key}"),
                    format!("a factor of safety must be at least 1, got {v}"),
                ));
            }
            let key = format!("margins.{key}");
            plausible::check(loc, &key, v, plausible::SAFETY_FACTOR)?;
        }
        if m.friction_coefficient <= 0.0 {
            return Err(loc.err(
                "margins.friction_coefficient",
                format!("must be positive, got {}", m.friction_coefficient),
            ));
        }
        let key = "margins.friction_coefficient";
        plausible::check(loc, key, m.friction_coefficient, plausible::FRICTION)?;
        for (key, v) in [
            ("preload_uncertainty", m.preload_uncertainty),
            ("preload_loss", m.preload_loss),
        ] {
            if !(0.0..1.0).contains(&v) {
                return Err(loc.err(
                    &format!("margins.{key}"),
                    format!("a fraction in [0, 1) is expected, got {v}"),
                ));
            }
        }
    }
    Ok(())
}

/// The response points of a scene: for a `[stack]`, one per satellite CG (`sat i`, node
/// 1000·i) and `top` (the top of satellite 1's column 1, node 1013, where the compression
/// device sits), followed by the scene's own `[[response]]` points. A generic scene without
/// `[[response]]` gets none (its interfaces and members are still recovered).
pub fn response_points(scene: &super::Scene) -> Vec<ResponsePoint> {
    let mut out = Vec::new();
    if let Some(st) = &scene.file.stack {
        for i in 1..=st.satellites {
            out.push(ResponsePoint {
                name: format!("sat {i}"),
                node: super::stack::ids::satellite(i),
            });
        }
        out.push(ResponsePoint {
            name: "top".into(),
            node: super::stack::ids::column(1, 1, 3),
        });
    }
    // A scene point with a default's name replaces that default.
    out.retain(|d| !scene.file.response.iter().any(|p| p.name == d.name));
    out.extend(scene.file.response.iter().cloned());
    out
}
