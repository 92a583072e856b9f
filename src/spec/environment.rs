//! Random-vibration input environments as the standards apply them: the named tables a scene
//! may call by name (each with its source), the test levels (qualification, protoflight,
//! acceptance) with their factors and durations, and the GEVS weight-based reduction of the
//! component profile. [`resolve`] turns a `[random]` section and the model's mass into the
//! profile that goes on the shaker and the record the report shows.
//!
//! Levels (GSFC-STD-7000A §2.4, test factors and durations for random vibration):
//! acceptance = the limit level (maximum expected flight level), 1 min per axis; protoflight =
//! limit + 3 dB, 1 min per axis; qualification (prototype) = limit + 3 dB, 2 min per axis.
//! GEVS's component table gives both columns and its qualification column is exactly twice
//! the acceptance one, so +3 dB is applied as the factor 2 (3.01 dB).

use super::analysis::RandomSpec;
use serde::{Deserialize, Serialize};

/// `[random] level`.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TestLevel {
    #[default]
    Qualification,
    Protoflight,
    Acceptance,
}

impl TestLevel {
    /// Factor on the limit-level ASD: +3 dB (×2) for qualification and protoflight.
    pub fn asd_factor(self) -> f64 {
        match self {
            TestLevel::Acceptance => 1.0,
            TestLevel::Qualification | TestLevel::Protoflight => 2.0,
        }
    }

    /// Duration per axis, s: 2 min for qualification, 1 min for protoflight and acceptance.
    pub fn duration_s(self) -> f64 {
        match self {
            TestLevel::Qualification => 120.0,
            TestLevel::Protoflight | TestLevel::Acceptance => 60.0,
        }
    }

    /// Sine sweep rate, octaves per minute (GSFC-STD-7000A §2.4 test factors and durations:
    /// 2 oct/min for qualification, 4 oct/min for protoflight and acceptance).
    pub fn sweep_rate_oct_min(self) -> f64 {
        match self {
            TestLevel::Qualification => 2.0,
            TestLevel::Protoflight | TestLevel::Acceptance => 4.0,
        }
    }

    /// Factor on limit-level sine segments: 1.25 for qualification and protoflight, 1 for
    /// acceptance (GSFC-STD-7000A Table 2.4-1, sine vibration: 1.25 × limit level).
    pub fn sine_factor(self) -> f64 {
        match self {
            TestLevel::Acceptance => 1.0,
            TestLevel::Qualification | TestLevel::Protoflight => 1.25,
        }
    }

    /// The level's name as the scene writes it.
    pub fn name(self) -> &'static str {
        match self {
            TestLevel::Qualification => "qualification",
            TestLevel::Protoflight => "protoflight",
            TestLevel::Acceptance => "acceptance",
        }
    }
}

/// `[sine] basis`: what the scene's sine segments are.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum SineBasis {
    /// The test input, applied as given (a test report's or a paper's levels).
    #[default]
    Test,
    /// The limit level (maximum expected flight level, e.g. a launcher's manual), raised to
    /// the test input by the level's factor.
    Limit,
}

/// `[random] weight_reduction`.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum WeightReduction {
    #[default]
    None,
    /// GSFC-STD-7000A, notes to the generalized random vibration table for components.
    Gevs,
}

/// A launcher's or a standard's random environment at its limit level.
pub struct NamedEnvironment {
    pub name: &'static str,
    pub source: &'static str,
    /// `[f_hz, g2_hz]` at the limit (acceptance, maximum predicted) level.
    pub profile: &'static [[f64; 2]],
}

/// The GEVS component table, whose shape the weight reduction is written for.
pub const GEVS_COMPONENT: &str = "gevs-component";

/// The tables a scene may name in `[random] environment`.
pub const NAMED: [NamedEnvironment; 2] = [
    NamedEnvironment {
        name: GEVS_COMPONENT,
        source: "GSFC-STD-7000A (GEVS) §2.4.2.5, generalized random vibration test levels for components of 22.7 kg or less (Table 2.4-3), acceptance column: 20 Hz 0.013 g²/Hz, +6 dB/oct to 50 Hz, 0.08 g²/Hz to 800 Hz, −6 dB/oct to 2000 Hz 0.013 g²/Hz, 10.0 Grms (qualification column twice that, 14.1 Grms)",
        profile: &[[20.0, 0.013], [50.0, 0.08], [800.0, 0.08], [2000.0, 0.013]],
    },
    NamedEnvironment {
        name: "spacex-rideshare-2022",
        source: "SpaceX Rideshare Payload User's Guide (October 2022), Table 3-7: random vibration maximum predicted environment at the payload interface, all axes, 5.57 Grms",
        profile: &[
            [20.0, 0.01],
            [50.0, 0.015],
            [700.0, 0.015],
            [800.0, 0.03],
            [925.0, 0.03],
            [2000.0, 0.00644],
        ],
    },
];

/// The named table `name`, if there is one.
pub fn named(name: &str) -> Option<&'static NamedEnvironment> {
    NAMED.iter().find(|e| e.name == name)
}

/// What the weight reduction did.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct GevsReduction {
    /// Mass of the test item (the whole model, less a shaker fixture), kg.
    pub mass_kg: f64,
    /// The mass the rule uses: GEVS holds the spectrum at its 182 kg level above 182 kg.
    pub mass_used_kg: f64,
    /// 10·log10(W/22.7), dB (0 at or below 22.7 kg).
    pub reduction_db: f64,
}

/// The random input as applied: what results.json and the report show.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RandomEnvironment {
    pub axes: Vec<String>,
    /// The named table, when the scene calls one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub environment: Option<String>,
    pub source: String,
    /// The test level, when the scene states one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level: Option<TestLevel>,
    /// Gain over the named table's limit level, dB (0 for an explicit profile).
    pub level_gain_db: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight_reduction: Option<GevsReduction>,
    /// `[f_hz, g2_hz]` as applied.
    pub profile: Vec<[f64; 2]>,
    pub grms: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

/// Components at or below this mass take the GEVS table in full, kg (50 lb).
const GEVS_BASE_KG: f64 = 22.7;
/// Up to this mass the ±6 dB/oct slopes are kept, kg (130 lb).
const GEVS_SLOPE_KG: f64 = 59.0;
/// Above this mass the spectrum stays at its level for this mass, kg (400 lb).
const GEVS_CAP_KG: f64 = 182.0;
/// ASD held at 20 and 2000 Hz above 59 kg, at the qualification level, g²/Hz.
const GEVS_END_QUAL: f64 = 0.01;

/// The GEVS reduction of the component table (limit level) for a test item of `mass_kg`:
/// the 50–800 Hz plateau scales by 22.7/W; up to 59 kg the ±6 dB/oct slopes are kept (every
/// point scales), above it the 20 and 2000 Hz ends are held at 0.01 g²/Hz at qualification
/// level (0.005 g²/Hz at this limit level); above 182 kg the 182 kg spectrum applies.
pub fn gevs_reduce(profile: &[[f64; 2]], mass_kg: f64) -> (Vec<[f64; 2]>, GevsReduction) {
    let w = mass_kg.min(GEVS_CAP_KG);
    let record = |db: f64| GevsReduction {
        mass_kg,
        mass_used_kg: w,
        reduction_db: db,
    };
    if w <= GEVS_BASE_KG {
        return (profile.to_vec(), record(0.0));
    }
    let scale = GEVS_BASE_KG / w;
    let end_limit = GEVS_END_QUAL / TestLevel::Qualification.asd_factor();
    let last = profile.len() - 1;
    let out = profile
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let at_end = i == 0 || i == last;
            let asd = if at_end && w > GEVS_SLOPE_KG {
                end_limit
            } else {
                p[1] * scale
            };
            [p[0], asd]
        })
        .collect();
    (out, record(10.0 * (w / GEVS_BASE_KG).log10()))
}

/// Grms of a log-log profile.
pub fn grms(profile: &[[f64; 2]]) -> f64 {
    let t: Vec<(f64, f64)> = profile.iter().map(|p| (p[0], p[1])).collect();
    crate::units::loglog_integral(&t).max(0.0).sqrt()
}

/// The random input of `spec` for a model of `mass_kg` (`None` when the mass is not known:
/// then a weight reduction cannot be applied and is an error). Checked at load time, so the
/// errors here are a message for the caller to place.
pub fn resolve(spec: &RandomSpec, mass_kg: Option<f64>) -> Result<RandomEnvironment, String> {
    let (mut profile, source, gain) = match &spec.environment {
        Some(name) => {
            let env = named(name).ok_or_else(|| unknown(name))?;
            let f = spec.level.unwrap_or_default().asd_factor();
            (env.profile.to_vec(), env.source.to_string(), f)
        }
        None => (
            spec.profile.clone(),
            spec.source
                .clone()
                .unwrap_or_else(|| "the scene's profile".into()),
            1.0,
        ),
    };
    let mut reduction = None;
    if spec.weight_reduction.unwrap_or_default() == WeightReduction::Gevs {
        let m = mass_kg.ok_or("the GEVS weight reduction needs the model's mass")?;
        let (p, r) = gevs_reduce(&profile, m);
        profile = p;
        reduction = Some(r);
    }
    for p in &mut profile {
        p[1] *= gain;
    }
    let level = match &spec.environment {
        Some(_) => Some(spec.level.unwrap_or_default()),
        None => spec.level,
    };
    Ok(RandomEnvironment {
        axes: spec.axes.clone(),
        environment: spec.environment.clone(),
        source,
        level,
        level_gain_db: 10.0 * gain.log10(),
        weight_reduction: reduction,
        grms: grms(&profile),
        profile,
        duration_s: spec.duration_s.or(level.map(TestLevel::duration_s)),
    })
}

/// The message for an environment name that is not in [`NAMED`].
pub fn unknown(name: &str) -> String {
    let names: Vec<&str> = NAMED.iter().map(|e| e.name).collect();
    format!(
        "unknown environment `{name}`: the named tables are {}",
        names.join(", ")
    )
}

/// The sine input as applied.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SineEnvironment {
    pub axes: Vec<String>,
    pub source: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level: Option<TestLevel>,
    pub basis: SineBasis,
    /// Factor from the scene's segments to `segments` (the level's for limit-level ones).
    pub level_factor: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep_rate_oct_min: Option<f64>,
    /// One sweep through the band at that rate, per axis, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// The segments as applied (the factor included).
    pub segments: Vec<super::analysis::SineSegment>,
}

impl SineEnvironment {
    /// The sine input of `spec`: its segments as applied, with the level's sweep rate and
    /// the time of one logarithmic sweep through the band, 60·log2(f_hi/f_lo)/rate.
    pub fn of(spec: &super::analysis::SineSpec) -> SineEnvironment {
        let rate = spec
            .sweep_rate_oct_min
            .or(spec.level.map(TestLevel::sweep_rate_oct_min));
        let (lo, hi) = spec.band();
        let factor = spec.level_factor();
        SineEnvironment {
            axes: spec.axes.clone(),
            source: spec
                .source
                .clone()
                .unwrap_or_else(|| "the scene's [[sine.segment]] levels".into()),
            level: spec.level,
            basis: spec.basis.unwrap_or_default(),
            level_factor: factor,
            sweep_rate_oct_min: rate,
            duration_s: rate
                .filter(|_| lo > 0.0 && hi > lo)
                .map(|r| 60.0 * (hi / lo).log2() / r),
            segments: spec.segment.iter().map(|s| s.scaled(factor)).collect(),
        }
    }
}

/// Every input environment of a scene.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct Environments {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sine: Option<SineEnvironment>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomEnvironment>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(env: &str, level: TestLevel, reduction: WeightReduction) -> RandomSpec {
        RandomSpec {
            axes: vec!["x".into()],
            environment: Some(env.into()),
            level: Some(level),
            weight_reduction: Some(reduction),
            ..Default::default()
        }
    }

    /// GSFC-STD-7000A generalized component table: "Overall 14.1 Grms" (qualification) and
    /// "10.0 Grms" (acceptance), quoted to 0.1 g; the log-log integral of the table's points
    /// gives 14.14 and 10.00.
    #[test]
    fn the_gevs_table_gives_the_standards_overall_levels() {
        let none = WeightReduction::None;
        let q = resolve(&spec(GEVS_COMPONENT, TestLevel::Qualification, none), None).unwrap();
        assert!((q.grms - 14.1).abs() < 0.05, "{}", q.grms);
        assert_eq!(q.profile[1], [50.0, 0.16]);
        assert_eq!(q.duration_s, Some(120.0));
        let a = resolve(&spec(GEVS_COMPONENT, TestLevel::Acceptance, none), None).unwrap();
        assert!((a.grms - 10.0).abs() < 0.05, "{}", a.grms);
        assert_eq!(a.duration_s, Some(60.0));
        // Protoflight: qualification level for the acceptance duration.
        let p = resolve(&spec(GEVS_COMPONENT, TestLevel::Protoflight, none), None).unwrap();
        assert_eq!((p.profile.clone(), p.duration_s), (q.profile, Some(60.0)));
        assert!((p.level_gain_db - 3.0103).abs() < 1e-4);
    }

    /// GEVS weight reduction, from the notes to the component table: dB reduction =
    /// 10·log(W/22.7); ASD(50–800 Hz) = 0.16·(22.7/W) at qualification; slopes kept up to
    /// 59 kg; 0.01 g²/Hz held at 20 and 2000 Hz above it; the 182 kg level above 182 kg.
    #[test]
    fn the_gevs_reduction_follows_the_standards_rule() {
        let q = |mass: f64| {
            let s = spec(
                GEVS_COMPONENT,
                TestLevel::Qualification,
                WeightReduction::Gevs,
            );
            resolve(&s, Some(mass)).unwrap()
        };
        // 40 kg: 10·log(40/22.7) = 2.4603 dB; plateau 0.16·22.7/40 = 0.0908 g²/Hz; the ends
        // scale with it (slopes kept): 0.026·22.7/40 = 0.014755 g²/Hz.
        let e = q(40.0);
        let r = e.weight_reduction.as_ref().unwrap();
        assert!((r.reduction_db - 2.4603).abs() < 1e-4);
        assert!((e.profile[1][1] - 0.0908).abs() < 1e-12);
        assert!((e.profile[0][1] - 0.014755).abs() < 1e-9);
        // 59 kg, where the kept slope lands on the floor: 0.026·22.7/59 = 0.010003 g²/Hz.
        assert!((q(59.0).profile[0][1] - 0.010003).abs() < 1e-6);
        // 100 kg: plateau 0.16·22.7/100 = 0.03632 g²/Hz, ends held at 0.01 g²/Hz.
        let e = q(100.0);
        assert!((e.profile[2][1] - 0.03632).abs() < 1e-12);
        assert!((e.profile[0][1] - 0.01).abs() < 1e-15 && (e.profile[3][1] - 0.01).abs() < 1e-15);
        // 780 kg is held at 182 kg: plateau 0.16·22.7/182 = 0.019956 g²/Hz, 9.0405 dB.
        let e = q(780.0);
        let r = e.weight_reduction.as_ref().unwrap();
        assert_eq!((r.mass_kg, r.mass_used_kg), (780.0, 182.0));
        assert!((r.reduction_db - 9.0405).abs() < 1e-4);
        assert!((e.profile[1][1] - 0.019956).abs() < 1e-6);
        assert_eq!(e.profile, q(182.0).profile);
        // At or below 22.7 kg the table applies in full.
        assert_eq!(q(20.0).profile, q(22.7).profile);
        assert_eq!(q(22.7).profile[1], [50.0, 0.16]);
    }

    /// The launcher table's own figure: "GRMS 5.57" (SpaceX Rideshare Payload User's Guide,
    /// Table 3-7), quoted to 0.01 g.
    #[test]
    fn the_rideshare_table_gives_its_stated_grms() {
        let a = spec(
            "spacex-rideshare-2022",
            TestLevel::Acceptance,
            WeightReduction::None,
        );
        let e = resolve(&a, None).unwrap();
        assert!((e.grms - 5.57).abs() < 0.01, "{}", e.grms);
    }

    /// A sweep of 5–100 Hz (log2(20) = 4.3219 octaves) at the qualification rate of 2 oct/min
    /// takes 60 · 4.3219 / 2 = 129.66 s; at 4 oct/min (acceptance) 64.83 s.
    #[test]
    fn a_sine_sweep_takes_the_levels_rate() {
        let seg = |from_hz, to_hz| super::super::analysis::SineSegment {
            from_hz,
            to_hz,
            acceleration_g: Some(0.3),
            displacement_m: None,
        };
        let mut s = super::super::analysis::SineSpec {
            axes: vec!["x".into()],
            segment: vec![seg(5.0, 8.0), seg(8.0, 100.0)],
            level: Some(TestLevel::Qualification),
            ..Default::default()
        };
        let e = SineEnvironment::of(&s);
        assert_eq!(e.sweep_rate_oct_min, Some(2.0));
        assert!((e.duration_s.unwrap() - 129.658).abs() < 1e-3);
        s.level = Some(TestLevel::Acceptance);
        assert!((SineEnvironment::of(&s).duration_s.unwrap() - 64.829).abs() < 1e-3);
        s.level = None;
        assert_eq!(SineEnvironment::of(&s).duration_s, None);
    }

    /// GSFC-STD-7000A Table 2.4-1, sine vibration: qualification and protoflight at 1.25 ×
    /// the limit level, acceptance at the limit level. Test-level segments (the default
    /// basis) are applied as given whatever the level. Exact.
    #[test]
    fn limit_level_sine_segments_take_the_levels_factor() {
        let seg = super::super::analysis::SineSegment {
            from_hz: 5.0,
            to_hz: 8.0,
            displacement_m: Some(1.0e-3),
            acceleration_g: None,
        };
        let mut s = super::super::analysis::SineSpec {
            axes: vec!["x".into()],
            segment: vec![seg],
            level: Some(TestLevel::Qualification),
            ..Default::default()
        };
        let given = s.segment[0].level_g(6.0);
        assert_eq!(s.level_g(6.0), given);
        s.basis = Some(SineBasis::Limit);
        let cases = [
            (TestLevel::Qualification, 1.25),
            (TestLevel::Protoflight, 1.25),
            (TestLevel::Acceptance, 1.0),
        ];
        for (level, factor) in cases {
            s.level = Some(level);
            assert_eq!(s.level_g(6.0), factor * given, "{level:?}");
            let e = SineEnvironment::of(&s);
            assert_eq!(e.level_factor, factor);
            assert_eq!(e.segments[0].displacement_m, Some(factor * 1.0e-3));
        }
    }

    #[test]
    fn a_reduction_without_a_mass_and_an_unknown_name_are_errors() {
        let s = spec(GEVS_COMPONENT, TestLevel::Acceptance, WeightReduction::Gevs);
        assert!(resolve(&s, None).unwrap_err().contains("mass"));
        let s = spec("atlas", TestLevel::Acceptance, WeightReduction::None);
        let e = resolve(&s, None).unwrap_err();
        assert!(e.contains("gevs-component") && e.contains("atlas"), "{e}");
    }
}
