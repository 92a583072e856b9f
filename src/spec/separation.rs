//! The `[separation]` scene section: springs, release schedule, contact and friction, guide-bar
//! flexibility, integrator tolerance and Monte Carlo dispersions of the in-orbit release.
//!
//! The satellite and bar geometry is NOT repeated here: it comes from `[stack]`
//! (`spec::stack`). This file owns only what the release adds to the hardware description.
//! Every default lives in [`defaults`], one function per key, with its source.
//! Semantic validation (signs, ranges, references, the release order) is in [`validate`] and
//! reports the dotted key through the scene's [`Locator`].

use super::Locator;
use super::count_or_word::{self, CountOrWord};
use super::model::{nonneg, positive};
use super::stack::StackSpec;
use crate::error::SpecError;
use serde::{Deserialize, Serialize};

/// Most bending modes per plane of a guide bar (the right-hand side keeps them on the stack).
pub const MAX_BAR_MODES: usize = 8;

/// `[separation]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SeparationSpec {
    /// Time from the unlock command to the release of the preload by the compression device, s.
    #[serde(default = "defaults::unlock_time_s")]
    pub unlock_time_s: f64,
    /// Delay between consecutive electromagnet releases when `release` is empty, s.
    #[serde(default = "defaults::release_interval_s")]
    pub release_interval_s: f64,
    /// Explicit electromagnet schedule. Empty: interface k releases at
    /// `(k - 1) * release_interval_s` after the unlock, top first.
    #[serde(default)]
    pub release: Vec<ReleaseSpec>,
    /// Number of bending modes per plane of each guide bar, or `"rigid"`.
    #[serde(default = "defaults::bar_modes")]
    pub bar_modes: BarModesChoice,
    /// Beam elements of the bar model that gives the modes (separation::bar_modes::cantilever_bar_modes).
    #[serde(default = "defaults::bar_elements")]
    pub bar_elements: usize,
    /// Modal damping ratio of the guide-bar modes.
    #[serde(default = "defaults::bar_damping_ratio")]
    pub bar_damping_ratio: f64,
    /// The four separation springs of every interface (nominal values).
    pub spring: SpringSpec,
    /// Per-interface overrides of the springs.
    #[serde(default)]
    pub interface: Vec<InterfaceOverride>,
    #[serde(default)]
    pub contact: ContactSpec,
    /// Present: the carrier platform is a free body (then the bars must be rigid). Absent: the
    /// carrier is fixed (it is the launcher's upper stage, orders of magnitude heavier).
    #[serde(default)]
    pub carrier: Option<CarrierSpec>,
    /// Integrator tolerance: relative tolerance of Dormand–Prince 5(4); absolute tolerances are
    /// this times a physical scale per state kind (see `separation::integrator`).
    #[serde(default = "defaults::tolerance")]
    pub tolerance: f64,
    /// Largest step, s. Bounds the time a contact could open and close unseen inside one step.
    #[serde(default = "defaults::max_step_s")]
    pub max_step_s: f64,
    /// The run stops here even if satellites are still on the bars, s.
    #[serde(default = "defaults::max_time_s")]
    pub max_time_s: f64,
    #[serde(default = "defaults::max_steps")]
    pub max_steps: usize,
    /// A satellite whose axial speed falls below this while its bores are still on the bars,
    /// after it has moved, has stalled (wedged), m/s.
    #[serde(default = "defaults::stall_speed_m_s")]
    pub stall_speed_m_s: f64,
    /// After the exits, the run goes on until consecutive satellites are this far apart (or
    /// `max_time_s`), so that the clearance between them is tracked in free flight, m.
    #[serde(default = "defaults::track_clearance_to_m")]
    pub track_clearance_to_m: f64,
    /// Sampling interval of the CSV histories (`--out`), s.
    #[serde(default = "defaults::output_interval_s")]
    pub output_interval_s: f64,
    /// Monte Carlo dispersions.
    #[serde(default)]
    pub dispersion: DispersionSpec,
    /// Release shock: acceleration histories of the moving bodies, their shock response
    /// spectra and, with `spec_g`, the gate against a component shock specification.
    #[serde(default)]
    pub shock: Option<ShockSpec>,
}

/// `[separation.shock]`: how the release's acceleration histories are sampled and analysed.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ShockSpec {
    /// Component shock specification, breakpoints `[f_hz, g]` (log-log); none: no gate.
    #[serde(default)]
    pub spec_g: Vec<[f64; 2]>,
    /// Quality factor of the SRS oscillators.
    #[serde(default = "defaults::shock_q")]
    pub q: f64,
    #[serde(default = "defaults::shock_fmin_hz")]
    pub fmin_hz: f64,
    #[serde(default = "defaults::shock_fmax_hz")]
    pub fmax_hz: f64,
    #[serde(default = "defaults::shock_per_octave")]
    pub per_octave: u32,
    /// Uniform sampling rate of the histories. Default: 10 × `fmax_hz`.
    #[serde(default)]
    pub sample_rate_hz: Option<f64>,
    /// Tolerance above the specification, dB, and the share of points allowed above it.
    #[serde(default = "defaults::shock_upper_db")]
    pub upper_db: f64,
    #[serde(default = "defaults::shock_lower_db")]
    pub lower_db: f64,
    #[serde(default)]
    pub allowed_fraction: f64,
}

impl Default for ShockSpec {
    fn default() -> Self {
        ShockSpec {
            spec_g: Vec::new(),
            q: defaults::shock_q(),
            fmin_hz: defaults::shock_fmin_hz(),
            fmax_hz: defaults::shock_fmax_hz(),
            per_octave: defaults::shock_per_octave(),
            sample_rate_hz: None,
            upper_db: defaults::shock_upper_db(),
            lower_db: defaults::shock_lower_db(),
            allowed_fraction: 0.0,
        }
    }
}

impl ShockSpec {
    /// The sampling rate of the histories: the scene's, or 10 × `fmax_hz` (NASA-STD-7003A
    /// asks for a sample rate of at least ten times the highest SRS frequency).
    pub fn sample_rate_hz(&self) -> f64 {
        self.sample_rate_hz.unwrap_or(10.0 * self.fmax_hz)
    }
}

/// A count of modes per bending plane, or the word `rigid`.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(untagged)]
pub enum BarModesChoice {
    Modes(usize),
    Word(String),
}

impl<'de> Deserialize<'de> for BarModesChoice {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let expecting = "a whole number of modes per bending plane, or `rigid`";
        Ok(match count_or_word::read(d, expecting)? {
            CountOrWord::Count(n) => Self::Modes(n),
            CountOrWord::Word(w) => Self::Word(w),
        })
    }
}

impl BarModesChoice {
    /// `Some(n)` for flexible bars with n modes per plane, `None` for rigid bars.
    pub fn modes(&self) -> Option<usize> {
        match self {
            BarModesChoice::Modes(n) => Some(*n),
            BarModesChoice::Word(_) => None,
        }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ReleaseSpec {
    /// Interface k lies below satellite k (k = N: between satellite N and the carrier).
    pub interface: usize,
    /// Delay after the compression device has unlocked, s.
    pub delay_s: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// Nominal stiffness of one spring, N/m.
    pub stiffness_n_m: f64,
    /// Travel of the spring plunger before its end stop, m.
    pub stroke_m: f64,
    /// Spring length when the interface is latched, m.
    #[serde(default = "defaults::installed_length_m")]
    pub installed_length_m: f64,
    /// Unloaded length, m. Default: installed length + stroke (the spring reaches its free
    /// length exactly at the end stop).
    #[serde(default)]
    pub free_length_m: Option<f64>,
    /// Relative stiffness error of the four springs, columns (+,+), (−,+), (−,−), (+,−):
    /// k = nominal × (1 + error).
    #[serde(default)]
    pub stiffness_error: [f64; 4],
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InterfaceOverride {
    pub interface: usize,
    #[serde(default)]
    pub stiffness_error: Option<[f64; 4]>,
    #[serde(default)]
    pub stroke_m: Option<[f64; 4]>,
    #[serde(default)]
    pub free_length_m: Option<[f64; 4]>,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Lankarani–Nikravesh stiffness K (paper eq. 33), N/m^exponent.
    #[serde(default = "defaults::contact_stiffness_n_m1_5")]
    pub stiffness_n_m1_5: f64,
    /// Hertz exponent n (paper eq. 33).
    #[serde(default = "defaults::contact_exponent")]
    pub exponent: f64,
    /// Coefficient of restitution Ce (paper eq. 34), in (0, 1].
    #[serde(default = "defaults::restitution")]
    pub restitution: f64,
    /// Coulomb coefficient c_f (paper eq. 36).
    #[serde(default = "defaults::friction")]
    pub friction: f64,
    /// Friction thresholds v0 < v1 of the modified coefficient c_d (paper eq. 37), m/s.
    #[serde(default = "defaults::v0_m_s")]
    pub v0_m_s: f64,
    #[serde(default = "defaults::v1_m_s")]
    pub v1_m_s: f64,
    /// Radial clearance bore–bar, m. Default: from `[stack]`, (bore − bar diameter)/2.
    #[serde(default)]
    pub clearance_m: Option<f64>,
    /// Length of the bore that guides a satellite on its bar (between its two contact
    /// edges, centred on the column), m. Default: the column height, `stack.satellite_pitch_m`.
    #[serde(default)]
    pub bore_length_m: Option<f64>,
    /// Floor of the latched impact speed δ̇⁻, m/s: a grazing contact would otherwise get an
    /// unbounded damping coefficient (eq. 34 divides by δ̇⁻).
    #[serde(default = "defaults::min_impact_speed_m_s")]
    pub min_impact_speed_m_s: f64,
    /// Where the bore meets the bar: `point` (the two bore edges, paper Fig. 8) or `line` (a
    /// force distributed along the overlap of bore and bar, Fig. 7d).
    #[serde(default)]
    pub model: ContactModel,
    /// Line contact: normal force per unit length per unit penetration, N/m².
    #[serde(default = "defaults::line_stiffness_n_m2")]
    pub line_stiffness_n_m2: f64,
    /// Line contact: Gauss–Legendre points along each edge's share of the overlap.
    #[serde(default = "defaults::line_points")]
    pub line_points: usize,
}

/// How the bore meets the bar (see `ContactSpec::model`).
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ContactModel {
    #[default]
    Point,
    Line,
}

/// The most Gauss–Legendre points a line contact may use (the tabulated rules).
pub const MAX_LINE_POINTS: usize = 6;

impl Default for ContactSpec {
    fn default() -> Self {
        ContactSpec {
            stiffness_n_m1_5: defaults::contact_stiffness_n_m1_5(),
            exponent: defaults::contact_exponent(),
            restitution: defaults::restitution(),
            friction: defaults::friction(),
            v0_m_s: defaults::v0_m_s(),
            v1_m_s: defaults::v1_m_s(),
            clearance_m: None,
            bore_length_m: None,
            min_impact_speed_m_s: defaults::min_impact_speed_m_s(),
            model: ContactModel::default(),
            line_stiffness_n_m2: defaults::line_stiffness_n_m2(),
            line_points: defaults::line_points(),
        }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CarrierSpec {
    pub mass_kg: f64,
    /// Principal moments about the carrier's CG, which sits at the bar-root origin, kg·m².
    pub inertia_kg_m2: [f64; 3],
}

/// A run count, or the word `auto`.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(untagged)]
pub enum RunCount {
    Count(usize),
    Word(String),
}

impl<'de> Deserialize<'de> for RunCount {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(
            match count_or_word::read(d, "a whole number of runs, or `auto`")? {
                CountOrWord::Count(n) => Self::Count(n),
                CountOrWord::Word(w) => Self::Word(w),
            },
        )
    }
}

/// Monte Carlo dispersions (1σ for normal ones, bounds for uniform ones). All zero by default.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DispersionSpec {
    /// 1σ relative stiffness error of each spring, added to the nominal error.
    #[serde(default)]
    pub spring_stiffness_sigma: f64,
    /// 1σ lateral (x and y) CG offset of each satellite, m.
    #[serde(default)]
    pub cg_offset_sigma_m: f64,
    /// Uniform radial clearance range, m.
    #[serde(default)]
    pub clearance_range_m: Option<[f64; 2]>,
    /// Uniform friction coefficient range.
    #[serde(default)]
    pub friction_range: Option<[f64; 2]>,
    /// 1σ skew of each electromagnet release time, s (a negative draw is clamped at the unlock).
    #[serde(default)]
    pub release_skew_sigma_s: f64,
    /// Monte Carlo runs that `qualify` makes: a count (0: none), or `"auto"` (also when
    /// absent): the fewest runs whose extreme sample bounds `probability` at `confidence`
    /// (none when no dispersion is declared). `satqual separate --monte-carlo N` overrides it.
    #[serde(default)]
    pub runs: Option<RunCount>,
    /// Probability of the one-sided bounds the Monte Carlo gates demonstrate (exit speed
    /// below, tip-off rate and clearance loss above).
    #[serde(default = "defaults::probability")]
    pub probability: f64,
    /// Confidence at which those bounds must be demonstrated.
    #[serde(default = "defaults::confidence")]
    pub confidence: f64,
    /// Seed of the Monte Carlo (ChaCha); the same seed gives the same percentiles.
    #[serde(default)]
    pub seed: u64,
}

impl Default for DispersionSpec {
    fn default() -> Self {
        DispersionSpec {
            spring_stiffness_sigma: 0.0,
            cg_offset_sigma_m: 0.0,
            clearance_range_m: None,
            friction_range: None,
            release_skew_sigma_s: 0.0,
            runs: None,
            probability: defaults::probability(),
            confidence: defaults::confidence(),
            seed: 0,
        }
    }
}

/// What `runs` asks for, once checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunsWanted {
    Count(usize),
    Auto,
}

impl DispersionSpec {
    /// `runs` resolved: absent or `"auto"` is [`RunsWanted::Auto`]. Any other word is an
    /// error message for the key.
    pub fn runs_wanted(&self) -> Result<RunsWanted, String> {
        match &self.runs {
            None => Ok(RunsWanted::Auto),
            Some(RunCount::Count(n)) => Ok(RunsWanted::Count(*n)),
            Some(RunCount::Word(w)) if w == "auto" => Ok(RunsWanted::Auto),
            Some(RunCount::Word(w)) => Err(format!("expected a run count or \"auto\", got `{w}`")),
        }
    }

    /// Whether any dispersion is declared: without one every run is the nominal run.
    pub fn disperses(&self) -> bool {
        self.spring_stiffness_sigma > 0.0
            || self.cg_offset_sigma_m > 0.0
            || self.release_skew_sigma_s > 0.0
            || self.clearance_range_m.is_some_and(|[a, b]| b > a)
            || self.friction_range.is_some_and(|[a, b]| b > a)
    }
}

/// Every default of `[separation]`, with its source.
pub mod defaults {
    use super::BarModesChoice;

    /// 0.9973, the two-sided 3σ content of a normal distribution taken one-sided: the level
    /// launcher interface documents quote separation dispersions at (e.g. Ariane 6 User's
    /// Manual, §4.6: separation conditions "at 3σ"; ECSS-E-HB-32-26A on 3σ design values).
    pub fn probability() -> f64 {
        0.9973
    }
    /// 95%: the confidence customary for order-statistics tolerance bounds (Wilks 1941; the
    /// 95/95 criterion of best-estimate safety analysis, USNRC RG 1.203).
    pub fn confidence() -> f64 {
        0.95
    }
    /// Paper §5.1.2: measured mean unlocking time of the compression device, 312 ms.
    pub fn unlock_time_s() -> f64 {
        0.312
    }
    /// Assumption: the paper releases "one by one" without a figure; 2 s lets each satellite
    /// clear its spring stroke and gain ≥ 0.5 m before the next one starts.
    pub fn release_interval_s() -> f64 {
        2.0
    }
    /// Assumption: three bending modes per plane (for the paper's 3.85 m bar ≈ 1, 6 and
    /// 17 Hz). Measured on the first release of the reference scene (docs/separation.md):
    /// exit speed 0.35267 / 0.35143 / 0.34987 / 0.34899 / 0.34941 m/s with 1 … 5 modes, so
    /// three modes sit within 1e-3 m/s of four and five; one mode is 3e-3 m/s off.
    pub fn bar_modes() -> BarModesChoice {
        BarModesChoice::Modes(3)
    }
    /// 40 elements sample the mode shapes finely enough for the cubic spline between stations.
    pub fn bar_elements() -> usize {
        40
    }
    /// Assumption: 1% modal damping, typical of a bolted steel bar (the paper gives none).
    pub fn bar_damping_ratio() -> f64 {
        0.01
    }
    /// Assumption: only the compression (free − installed) matters to the dynamics; 50 mm is a
    /// plausible installed length for an 80 mm stroke.
    pub fn installed_length_m() -> f64 {
        0.05
    }
    /// Assumption: Hertz K = 4/3·E*·√R for a steel bar on an aluminium bore edge of ≈1 mm
    /// radius: E* = 58.6 GPa, √R = 0.0316 → 2.5e9 N/m^1.5.
    pub fn contact_stiffness_n_m1_5() -> f64 {
        2.5e9
    }
    /// Assumption: the linearised line contact of a steel bar in a conformal aluminium bore,
    /// k ≈ π·E*/4 per unit length (Johnson, Contact Mechanics, §5.6, the compliance of two
    /// parallel cylinders without its logarithmic term), E* = 58.6 GPa → 4.6e10 N/m².
    pub fn line_stiffness_n_m2() -> f64 {
        4.6e10
    }
    /// Four Gauss–Legendre points per edge share: exact for the moment of a linearly
    /// varying penetration, and within 1e-6 of a slightly curved one.
    pub fn line_points() -> usize {
        4
    }
    /// Hertz point contact, paper eq. 33 (n = 1.5).
    pub fn contact_exponent() -> f64 {
        1.5
    }
    /// Assumption: 0.8, metal on metal at low speed; the paper says only "large recovery
    /// coefficient" (§3.3).
    pub fn restitution() -> f64 {
        0.8
    }
    /// Assumption: 0.2, steel on anodised aluminium with dry lubricant.
    pub fn friction() -> f64 {
        0.2
    }
    /// Assumption: the MSC ADAMS defaults behind the paper's eq. 37 (stiction transition
    /// 0.1 mm/s, friction transition 10 mm/s).
    pub fn v0_m_s() -> f64 {
        1e-4
    }
    pub fn v1_m_s() -> f64 {
        1e-2
    }
    /// Q = 10 (5% damping), the convention of NASA-STD-7003A and MIL-STD-810H Method 516.
    pub fn shock_q() -> f64 {
        10.0
    }
    /// 10 Hz: the bottom of the usual component shock specifications.
    pub fn shock_fmin_hz() -> f64 {
        10.0
    }
    /// 2 kHz: a bore-edge impact of the reference scene lasts milliseconds (Hertz contact of
    /// K = 2.5e9 N/m^1.5 at mm/s), so its spectrum has rolled off well below it.
    pub fn shock_fmax_hz() -> f64 {
        2000.0
    }
    /// 1/12 octave, the finer grid of the test standards.
    pub fn shock_per_octave() -> u32 {
        12
    }
    /// ±6 dB around the specification (NASA-STD-7003A).
    pub fn shock_upper_db() -> f64 {
        6.0
    }
    pub fn shock_lower_db() -> f64 {
        6.0
    }
    /// 0.1 mm/s: below the v0 friction threshold, i.e. a contact that is not an impact.
    pub fn min_impact_speed_m_s() -> f64 {
        1e-4
    }
    /// The loosest decade that keeps every accuracy criterion of the separation with a wide
    /// margin, measured (`satqual bench separation`, tests/separation_accuracy.rs): at 1e-6 the
    /// energy residual is ~1e-8 of the spring energy (criterion 1e-6), the well-conditioned
    /// exit speeds are within ~1e-6 m/s of a 1e-12 run (criterion: < 1e-4 m/s against
    /// tol/100), and the seeded Monte Carlo's exit-speed distribution agrees with tol/100.
    /// The chaotic scatter of a flexible run's exit speeds is ~1e-3 m/s, a thousand times the
    /// integration error. Mean work over 16 realizations of the reference scene: 1e-8 costs
    /// 1.9× the right-hand sides of 1e-6; 1e-5 breaks the convergence criterion.
    pub fn tolerance() -> f64 {
        1e-6
    }
    /// 20 ms. A contact that opens and closes between two step ends is still felt by the
    /// stages inside the step (the error estimate then rejects and shortens the step); this
    /// bound keeps such a pulse from slipping between the stages of a long free-flight step.
    pub fn max_step_s() -> f64 {
        0.02
    }
    /// Long enough for the bottom satellite to travel 3.85 m at 0.1 m/s after a 10 s schedule.
    pub fn max_time_s() -> f64 {
        60.0
    }
    /// ASSUMPTION: 1 cm/s. A satellite that slow on the bars needs more than five minutes for
    /// the 3.5 m of the reference bars, longer than any release sequence waits: it is stuck for
    /// the mission. Ten times below it the friction of the stuck contacts decides, not the
    /// threshold; the reference Monte Carlo's slowest exits (0.028-0.030 m/s) lie above it.
    pub fn stall_speed_m_s() -> f64 {
        0.01
    }
    /// 1 m: twice the largest satellite's column pitch (0.55 m) plus margin; beyond it a
    /// re-contact needs a closing speed the free flight cannot produce before the first orbit
    /// manoeuvre (ASSUMPTION).
    pub fn track_clearance_to_m() -> f64 {
        1.0
    }
    pub fn max_steps() -> usize {
        5_000_000
    }
    pub fn output_interval_s() -> f64 {
        0.01
    }
}

/// Plausible ranges of the release spring and of the run's length: a stiff spring or a long
/// stroke makes the integrator take steps for minutes, with no result worth having.
fn check_spring_and_budget(
    spec: &SeparationSpec,
    max_runs: usize,
    loc: &Locator,
) -> Result<(), SpecError> {
    use super::plausible::{SEPARATION_SPRING_N_M, SEPARATION_TIME_S, STROKE_M, check};
    let sp = &spec.spring;
    check(
        loc,
        "separation.spring.stiffness_n_m",
        sp.stiffness_n_m,
        SEPARATION_SPRING_N_M,
    )?;
    check(loc, "separation.spring.stroke_m", sp.stroke_m, STROKE_M)?;
    check(
        loc,
        "separation.max_time_s",
        spec.max_time_s,
        SEPARATION_TIME_S,
    )?;
    let d = &spec.dispersion;
    match d.runs_wanted() {
        Err(e) => return Err(loc.err("separation.dispersion.runs", e)),
        Ok(RunsWanted::Count(n)) if n > max_runs => {
            return Err(loc.err(
                "separation.dispersion.runs",
                format!(
                    "{n} runs is above the limit of {max_runs}; {}",
                    super::limits::raise_hint("monte_carlo_runs")
                ),
            ));
        }
        Ok(_) => {}
    }
    for (key, v) in [("probability", d.probability), ("confidence", d.confidence)] {
        if !(v > 0.0 && v < 1.0) {
            return Err(loc.err(
                &format!("separation.dispersion.{key}"),
                format!("must lie strictly between 0 and 1, got {v}"),
            ));
        }
    }
    Ok(())
}

/// A relative spring error above +1000 % describes another spring, not an error of this one;
/// it also multiplies the stiffness past its plausible range (a hang of the integrator).
fn check_stiffness_error(loc: &Locator, key: &str, e: f64) -> Result<(), SpecError> {
    super::plausible::check(loc, key, e.abs(), super::plausible::STIFFNESS_ERROR)
}

/// Checks signs, ranges and references of `[separation]` against `[stack]`, section by
/// section in the order of the scene format. Every error names the key.
pub fn validate(
    spec: &SeparationSpec,
    stack: &StackSpec,
    limits: &super::limits::LimitsSpec,
    loc: &Locator,
) -> Result<(), SpecError> {
    let n = stack.satellites;
    validate_stack_for_release(spec, stack, loc)?;
    validate_run_settings(spec, loc)?;
    check_history_size(spec, n, limits.history_rows, loc)?;
    validate_springs(spec, n, limits.monte_carlo_runs, loc)?;
    validate_releases(spec, n, loc)?;
    validate_contact(&spec.contact, loc)?;
    validate_carrier(spec, loc)?;
    validate_dispersion(&spec.dispersion, loc)?;
    if let Some(sh) = &spec.shock {
        validate_shock(sh, loc)?;
    }
    validate_release_order(spec, n, loc)
}

/// A relative stiffness error must exceed −1 (a spring of zero or negative stiffness) and stay
/// plausible.
fn check_relative_error(loc: &Locator, key: &str, e: f64) -> Result<(), SpecError> {
    if e <= -1.0 {
        return Err(loc.err(key, format!("must exceed -1, got {e}")));
    }
    check_stiffness_error(loc, key, e)
}

/// Interface k lies below satellite k: 1..=n.
fn check_interface(loc: &Locator, key: &str, k: usize, n: usize) -> Result<(), SpecError> {
    if (1..=n).contains(&k) {
        Ok(())
    } else {
        Err(loc.err(
            key,
            format!("interface {k} does not exist: the stack has interfaces 1..={n} (k lies below satellite k)"),
        ))
    }
}

/// The `[stack]` quantities the release depends on: masses, geometry, the stack within the
/// bars, and a bore at least as wide as its bar.
fn validate_stack_for_release(
    spec: &SeparationSpec,
    stack: &StackSpec,
    loc: &Locator,
) -> Result<(), SpecError> {
    let n = stack.satellites;
    if n == 0 {
        return Err(loc.err("stack.satellites", "must be at least 1"));
    }
    positive(loc, "stack.satellite_mass_kg", stack.satellite_mass_kg)?;
    for (j, v) in stack.satellite_inertia_kg_m2.iter().enumerate() {
        positive(loc, &format!("stack.satellite_inertia_kg_m2[{j}]"), *v)?;
    }
    positive(loc, "stack.satellite_pitch_m", stack.satellite_pitch_m)?;
    positive(loc, "stack.bar_length_m", stack.bar_length_m)?;
    positive(loc, "stack.bar_diameter_m", stack.bar_diameter_m)?;
    positive(loc, "stack.column_spacing_m[0]", stack.column_spacing_m[0])?;
    positive(loc, "stack.column_spacing_m[1]", stack.column_spacing_m[1])?;
    nonneg(loc, "stack.base_height_m", stack.base_height_m)?;
    let top = stack.base_height_m + n as f64 * stack.satellite_pitch_m;
    if top > stack.bar_length_m {
        return Err(loc.err(
            "stack.bar_length_m",
            format!(
                "the stack reaches {top} m above the bar root, above the {} m guide bars",
                stack.bar_length_m
            ),
        ));
    }
    let bore_radius = 0.5 * stack.column_inner_diameter_m;
    let clearances = [
        ("separation.contact.clearance_m", spec.contact.clearance_m),
        (
            "separation.dispersion.clearance_range_m",
            spec.dispersion.clearance_range_m.map(|r| r[1]),
        ),
    ];
    for (key, c) in clearances {
        if let Some(c) = c.filter(|&c| c >= bore_radius) {
            return Err(loc.err(
                key,
                format!(
                    "a radial clearance of {c} m does not fit the column bore of {} m diameter (stack.column_inner_diameter_m): the bar would be thinner than nothing; clearances are in metres (0.5 mm = 0.0005)",
                    stack.column_inner_diameter_m
                ),
            ));
        }
    }
    match spec.contact.clearance_m {
        Some(c) => nonneg(loc, "separation.contact.clearance_m", c)?,
        None => {
            if stack.column_inner_diameter_m < stack.bar_diameter_m {
                return Err(loc.err(
                    "stack.column_inner_diameter_m",
                    format!(
                        "the column bore ({} m) is narrower than the guide bar ({} m): negative clearance",
                        stack.column_inner_diameter_m, stack.bar_diameter_m
                    ),
                ));
            }
        }
    }
    if let Some(l) = spec.contact.bore_length_m {
        positive(loc, "separation.contact.bore_length_m", l)?;
        if l > stack.satellite_pitch_m {
            return Err(loc.err(
                "separation.contact.bore_length_m",
                format!(
                    "the bore ({l} m) is longer than its column (stack.satellite_pitch_m = {} m)",
                    stack.satellite_pitch_m
                ),
            ));
        }
    }
    Ok(())
}

/// Timing, integrator and the bars' model.
fn validate_run_settings(spec: &SeparationSpec, loc: &Locator) -> Result<(), SpecError> {
    nonneg(loc, "separation.unlock_time_s", spec.unlock_time_s)?;
    nonneg(
        loc,
        "separation.release_interval_s",
        spec.release_interval_s,
    )?;
    // Below 1e-12 the step falls to the round-off floor before any progress.
    if !(spec.tolerance >= 1e-12 && spec.tolerance <= 1e-2) {
        return Err(loc.err(
            "separation.tolerance",
            format!("must lie in [1e-12, 1e-2], got {}", spec.tolerance),
        ));
    }
    positive(loc, "separation.max_step_s", spec.max_step_s)?;
    positive(loc, "separation.max_time_s", spec.max_time_s)?;
    positive(loc, "separation.output_interval_s", spec.output_interval_s)?;
    nonneg(loc, "separation.stall_speed_m_s", spec.stall_speed_m_s)?;
    nonneg(
        loc,
        "separation.track_clearance_to_m",
        spec.track_clearance_to_m,
    )?;
    if spec.max_steps == 0 {
        return Err(loc.err("separation.max_steps", "must be at least 1"));
    }
    match &spec.bar_modes {
        BarModesChoice::Modes(m) if *m == 0 || *m > MAX_BAR_MODES => {
            return Err(loc.err(
                "separation.bar_modes",
                format!("must lie in 1..={MAX_BAR_MODES}, or be \"rigid\"; got {m}"),
            ));
        }
        BarModesChoice::Word(w) if w != "rigid" => {
            return Err(loc.err(
                "separation.bar_modes",
                format!("`{w}` is neither a mode count nor \"rigid\""),
            ));
        }
        _ => {}
    }
    if spec.bar_elements < 2 {
        return Err(loc.err("separation.bar_elements", "must be at least 2"));
    }
    let key = "separation.bar_damping_ratio";
    nonneg(loc, key, spec.bar_damping_ratio)?;
    super::plausible::check(loc, key, spec.bar_damping_ratio, super::plausible::BAR_ZETA)
}

/// The histories sample every satellite every `output_interval_s` up to `max_time_s`: their
/// size is estimated before the run, as every input-sized allocation is.
fn check_history_size(
    spec: &SeparationSpec,
    n: usize,
    max_rows: usize,
    loc: &Locator,
) -> Result<(), SpecError> {
    let rows = (spec.max_time_s / spec.output_interval_s + 1.0) * n as f64;
    if rows > max_rows as f64 {
        return Err(loc.err(
            "separation.output_interval_s",
            format!(
                "{} s over a run of up to {} s (separation.max_time_s) and {n} satellites makes {rows:.3e} history rows, above the limit of {max_rows}; {}",
                spec.output_interval_s,
                spec.max_time_s,
                super::limits::raise_hint("history_rows")
            ),
        ));
    }
    Ok(())
}

/// `[separation.spring]` and the per-interface overrides of `[[separation.interface]]`.
fn validate_springs(
    spec: &SeparationSpec,
    n: usize,
    max_runs: usize,
    loc: &Locator,
) -> Result<(), SpecError> {
    let sp = &spec.spring;
    positive(loc, "separation.spring.stiffness_n_m", sp.stiffness_n_m)?;
    positive(loc, "separation.spring.stroke_m", sp.stroke_m)?;
    check_spring_and_budget(spec, max_runs, loc)?;
    positive(
        loc,
        "separation.spring.installed_length_m",
        sp.installed_length_m,
    )?;
    if let Some(f) = sp.free_length_m
        && f <= sp.installed_length_m
    {
        return Err(loc.err(
            "separation.spring.free_length_m",
            format!(
                "must exceed the installed length {} m (a spring must be compressed), got {f}",
                sp.installed_length_m
            ),
        ));
    }
    for (j, e) in sp.stiffness_error.iter().enumerate() {
        check_relative_error(loc, &format!("separation.spring.stiffness_error[{j}]"), *e)?;
    }
    for (i, o) in spec.interface.iter().enumerate() {
        let key = |k: &str| format!("separation.interface[{i}].{k}");
        check_interface(loc, &key("interface"), o.interface, n)?;
        if spec.interface[..i]
            .iter()
            .any(|p| p.interface == o.interface)
        {
            return Err(loc.err(
                &key("interface"),
                format!(
                    "interface {} has two [[separation.interface]] entries: give its springs once",
                    o.interface
                ),
            ));
        }
        for (j, v) in o.stroke_m.iter().flatten().enumerate() {
            let key = key(&format!("stroke_m[{j}]"));
            positive(loc, &key, *v)?;
            super::plausible::check(loc, &key, *v, super::plausible::STROKE_M)?;
        }
        for (j, v) in o.stiffness_error.iter().flatten().enumerate() {
            check_relative_error(loc, &key(&format!("stiffness_error[{j}]")), *v)?;
        }
        for (j, v) in o.free_length_m.iter().flatten().enumerate() {
            if *v <= sp.installed_length_m {
                return Err(loc.err(
                    &key(&format!("free_length_m[{j}]")),
                    format!(
                        "must exceed the installed length {} m, got {v}",
                        sp.installed_length_m
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// `[[separation.release]]`: existing interfaces, each released once, non-negative delays.
fn validate_releases(spec: &SeparationSpec, n: usize, loc: &Locator) -> Result<(), SpecError> {
    let mut seen = vec![false; n + 1];
    for (i, r) in spec.release.iter().enumerate() {
        let key = format!("separation.release[{i}].interface");
        check_interface(loc, &key, r.interface, n)?;
        nonneg(loc, &format!("separation.release[{i}].delay_s"), r.delay_s)?;
        if std::mem::replace(&mut seen[r.interface], true) {
            return Err(loc.err(&key, format!("interface {} is released twice", r.interface)));
        }
    }
    Ok(())
}

/// `[separation.contact]`: the Hertz law, restitution, friction and the line contact.
fn validate_contact(c: &ContactSpec, loc: &Locator) -> Result<(), SpecError> {
    positive(
        loc,
        "separation.contact.stiffness_n_m1_5",
        c.stiffness_n_m1_5,
    )?;
    if c.exponent < 1.0 {
        return Err(loc.err(
            "separation.contact.exponent",
            format!("must be at least 1, got {}", c.exponent),
        ));
    }
    if !(c.restitution > 0.0 && c.restitution <= 1.0) {
        return Err(loc.err(
            "separation.contact.restitution",
            format!(
                "the coefficient of restitution Ce must lie in (0, 1], got {}",
                c.restitution
            ),
        ));
    }
    let key = "separation.contact.friction";
    nonneg(loc, key, c.friction)?;
    super::plausible::check(loc, key, c.friction, super::plausible::CONTACT_FRICTION)?;
    nonneg(loc, "separation.contact.v0_m_s", c.v0_m_s)?;
    if c.v1_m_s <= c.v0_m_s {
        return Err(loc.err(
            "separation.contact.v1_m_s",
            format!("must exceed v0_m_s = {}, got {}", c.v0_m_s, c.v1_m_s),
        ));
    }
    let key = "separation.contact.min_impact_speed_m_s";
    positive(loc, key, c.min_impact_speed_m_s)?;
    let key = "separation.contact.line_stiffness_n_m2";
    positive(loc, key, c.line_stiffness_n_m2)?;
    if !(1..=MAX_LINE_POINTS).contains(&c.line_points) {
        return Err(loc.err(
            "separation.contact.line_points",
            format!("must lie in 1..={MAX_LINE_POINTS}, got {}", c.line_points),
        ));
    }
    Ok(())
}

/// `[separation.carrier]`: a free carrier's mass properties, with rigid bars only.
fn validate_carrier(spec: &SeparationSpec, loc: &Locator) -> Result<(), SpecError> {
    let Some(cr) = &spec.carrier else {
        return Ok(());
    };
    positive(loc, "separation.carrier.mass_kg", cr.mass_kg)?;
    for (j, v) in cr.inertia_kg_m2.iter().enumerate() {
        positive(loc, &format!("separation.carrier.inertia_kg_m2[{j}]"), *v)?;
    }
    if spec.bar_modes.modes().is_some() {
        return Err(loc.err(
            "separation.carrier",
            "a free carrier needs `bar_modes = \"rigid\"`: flexible bars on an accelerating base are not modelled",
        ));
    }
    Ok(())
}

/// `[separation.dispersion]`: non-negative sigmas and ordered, plausible ranges.
fn validate_dispersion(d: &DispersionSpec, loc: &Locator) -> Result<(), SpecError> {
    let key = |k: &str| format!("separation.dispersion.{k}");
    nonneg(
        loc,
        &key("spring_stiffness_sigma"),
        d.spring_stiffness_sigma,
    )?;
    nonneg(loc, &key("cg_offset_sigma_m"), d.cg_offset_sigma_m)?;
    nonneg(loc, &key("release_skew_sigma_s"), d.release_skew_sigma_s)?;
    if let Some([a, b]) = d.clearance_range_m
        && (a < 0.0 || b < a)
    {
        return Err(loc.err(
            &key("clearance_range_m"),
            format!("needs 0 <= min <= max, got [{a}, {b}]"),
        ));
    }
    if let Some([a, b]) = d.friction_range {
        if a < 0.0 || b < a {
            return Err(loc.err(
                &key("friction_range"),
                format!("needs 0 <= min <= max, got [{a}, {b}]"),
            ));
        }
        for v in [a, b] {
            let limits = super::plausible::CONTACT_FRICTION;
            super::plausible::check(loc, &key("friction_range"), v, limits)?;
        }
    }
    Ok(())
}

/// `[separation.shock]`: the SRS options, the sampling rate above Nyquist of `fmax_hz`, and
/// the specification's breakpoints positive with increasing frequencies.
fn validate_shock(sh: &ShockSpec, loc: &Locator) -> Result<(), SpecError> {
    let key = |k: &str| format!("separation.shock.{k}");
    let bad = |k: &str, msg: String| Err(loc.err(&key(k), msg));
    if !(sh.q.is_finite() && sh.q > 0.5 && sh.q <= 1e3) {
        return bad("q", format!("must lie in (0.5, 1000], got {}", sh.q));
    }
    if !(sh.fmin_hz.is_finite() && sh.fmin_hz > 0.0) {
        return bad(
            "fmin_hz",
            format!("must be a positive frequency, got {}", sh.fmin_hz),
        );
    }
    if !(sh.fmax_hz.is_finite() && sh.fmax_hz >= sh.fmin_hz && sh.fmax_hz <= 1e6) {
        return bad(
            "fmax_hz",
            format!(
                "must lie in [fmin_hz = {}, 1e6], got {}",
                sh.fmin_hz, sh.fmax_hz
            ),
        );
    }
    if !(1..=96).contains(&sh.per_octave) {
        return bad(
            "per_octave",
            format!("must lie in 1..=96, got {}", sh.per_octave),
        );
    }
    let fs = sh.sample_rate_hz();
    // The filter aliases at and above fs/2; 1e7 Hz bounds the samples of a long run.
    if !(fs.is_finite() && fs > 2.0 * sh.fmax_hz && fs <= 1e7) {
        return bad(
            "sample_rate_hz",
            format!(
                "must exceed 2 × fmax_hz = {} Hz (Nyquist) and be at most 1e7, got {fs}",
                2.0 * sh.fmax_hz
            ),
        );
    }
    for (k, v) in [("upper_db", sh.upper_db), ("lower_db", sh.lower_db)] {
        if !(v.is_finite() && v >= 0.0) {
            return bad(
                k,
                format!("must be a finite, non-negative dB value, got {v}"),
            );
        }
    }
    if !(0.0..=1.0).contains(&sh.allowed_fraction) {
        return bad(
            "allowed_fraction",
            format!("must lie in [0, 1], got {}", sh.allowed_fraction),
        );
    }
    validate_shock_points(&sh.spec_g, loc)
}

fn validate_shock_points(points: &[[f64; 2]], loc: &Locator) -> Result<(), SpecError> {
    if points.len() == 1 {
        return Err(loc.err(
            "separation.shock.spec_g",
            "a specification needs at least two [f_hz, g] breakpoints",
        ));
    }
    for (i, p) in points.iter().enumerate() {
        if !(super::plausible::FREQUENCY_HZ.admits(p[0])
            && super::plausible::ACCELERATION_G.admits(p[1]))
        {
            return Err(loc.err(
                &format!("separation.shock.spec_g[{i}]"),
                format!(
                    "[{}, {}] is outside the plausible ranges {} and {} (see docs/robustness.md)",
                    p[0],
                    p[1],
                    super::plausible::FREQUENCY_HZ.describe(),
                    super::plausible::ACCELERATION_G.describe()
                ),
            ));
        }
        if i > 0 && p[0] <= points[i - 1][0] {
            return Err(loc.err(
                &format!("separation.shock.spec_g[{i}]"),
                format!(
                    "frequencies must increase: {} Hz after {} Hz",
                    p[0],
                    points[i - 1][0]
                ),
            ));
        }
    }
    Ok(())
}

/// The release times of the interfaces (absolute, from the unlock command), `None` = never.
pub fn release_times(spec: &SeparationSpec, n: usize) -> Vec<Option<f64>> {
    let mut t = vec![None; n + 1];
    if spec.release.is_empty() {
        for (k, tk) in t.iter_mut().enumerate().skip(1) {
            *tk = Some(spec.unlock_time_s + (k - 1) as f64 * spec.release_interval_s);
        }
    } else {
        for r in &spec.release {
            t[r.interface] = Some(spec.unlock_time_s + r.delay_s);
        }
    }
    t
}

/// A latched interface joins two bodies rigidly. The model integrates single rigid bodies
/// only, so every release must leave each moving group as one body: satellites latched
/// together but detached from a fixed carrier (or latched to a free one) would form a moving
/// composite body, which is not modelled. Top-down release always satisfies this.
fn validate_release_order(spec: &SeparationSpec, n: usize, loc: &Locator) -> Result<(), SpecError> {
    let times = release_times(spec, n);
    // A release at or after the end of the run leaves its satellite latched: every number
    // of it would describe a satellite that was never let go.
    if let Some((k, t)) = times
        .iter()
        .enumerate()
        .filter_map(|(k, t)| t.map(|t| (k, t)))
        .find(|&(_, t)| t >= spec.max_time_s)
    {
        return Err(loc.err(
            "separation.max_time_s",
            format!(
                "the run ends at {} s, but interface {k} is released at {t} s: raise max_time_s above the last release (and its time on the bars) or release earlier",
                spec.max_time_s
            ),
        ));
    }
    let mut distinct: Vec<f64> = times.iter().flatten().copied().collect();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    let fixed_carrier = spec.carrier.is_none();
    for &t in &distinct {
        // Bodies 1..=n are satellites, n+1 the carrier; interface k joins k and k+1.
        let latched = |k: usize| times[k].is_none_or(|tk| tk > t);
        let mut start = 1;
        while start <= n + 1 {
            let mut end = start;
            while end <= n && latched(end) {
                end += 1;
            }
            // Group start..=end.
            let has_carrier = end == n + 1;
            let size = end - start + 1;
            if size > 1 && !(has_carrier && fixed_carrier) {
                let key = spec
                    .release
                    .iter()
                    .position(|r| times[r.interface] == Some(t))
                    .map(|i| format!("separation.release[{i}].interface"))
                    .unwrap_or_else(|| "separation.release".into());
                let last = if has_carrier { n } else { end };
                return Err(loc.err(
                    &key,
                    format!(
                        "at t = {t} s satellites {start}..={last}{} are latched together but free to move; a moving composite body is not modelled: release the interfaces between them at the same time or earlier",
                        if has_carrier { " and the free carrier" } else { "" }
                    ),
                ));
            }
            start = end + 1;
        }
    }
    Ok(())
}
