//! Separation gates: every satellite leaves the guide bars fast enough, without too much
//! tip-off, without wedging, with time to spare, and never touches its neighbour again
//! (tracked in free flight until they are far apart); with a Monte Carlo, the same as
//! one-sided tolerance bounds at the demanded probability and confidence, or "not
//! demonstrated" when the runs cannot support them.
//!
//! Margins of maxima follow the margin-of-safety form with a factor of safety of 1,
//! MS = limit/value − 1 (tip-off rate, time on the bars); minima value/limit − 1.

use super::verdict::{MARGIN_CAP, Verdict, above, at_least, design_margin};
use crate::separation::montecarlo::{MonteCarloResult, TailBound, Wedged};
use crate::separation::shock::ReleaseShock;
use crate::separation::{SatelliteResult, SeparationResult, order_stats};
use crate::spec::GatesSpec;

const LIMITS_SOURCE: &str = "[gates] limits; default ASSUMPTION: exit speed ≥ 0.2 m/s and tip-off ≤ 2.5 deg/s, below the paper's measured 0.25–0.35 m/s and its first satellite's accepted 2.47 deg/s (§4, §5.2)";
const NO_RECONTACT: &str =
    "ASSUMPTION: satellites must not touch again after release (collision-free deployment)";
const WEDGING: &str = "a satellite must not stall on the bars ([separation] stall_speed_m_s, \
                       ASSUMPTION)";
const WEDGING_MC: &str = "a satellite must not stall on the bars ([separation] stall_speed_m_s, \
                          ASSUMPTION) with the probability and confidence of \
                          [separation.dispersion]; per-run probability bounded by \
                          Clopper–Pearson";
/// In the name of a Monte Carlo gate whose runs are too few for the demanded bound: the gate
/// fails on the run count, whatever its value (the report's cause sentence reads it).
pub const NOT_DEMONSTRATED: &str = "not demonstrated";
const TIME_ON_BARS: &str = "ASSUMPTION: every satellite must leave the bars within the simulated time ([separation] max_time_s)";

/// What the run-level gates need besides the results.
#[derive(Debug, Clone, Copy)]
pub struct RunLimits {
    /// The simulated span, from the unlock command, s.
    pub max_time_s: f64,
    pub stall_speed_m_s: f64,
    pub track_clearance_to_m: f64,
}

/// The nominal run's gates: per satellite speed, tip-off, time on the bars and wedging, then
/// the clearance.
pub fn nominal(result: &SeparationResult, run: &RunLimits, limits: &GatesSpec) -> Vec<Verdict> {
    let mut out = Vec::new();
    for s in &result.satellites {
        out.extend(satellite(s, run, limits));
    }
    out.extend(clearance(result, run));
    if let Some(shock) = &result.shock {
        out.extend(release_shock(shock));
    }
    out.into_iter().map(unit_from_name).collect()
}

const SHOCK_SOURCE: &str = "the scene's component shock specification ([separation.shock] spec_g); SRS by the Smallwood filter, maximax, tolerance and share of points above it as in NASA-STD-7003A";

/// Per moving body with a specification check: the SRS point that decides the check (see
/// `separation::shock::BodySpecCheck`) against spec × 10^(upper_db/20), MS = limit/value − 1.
pub fn release_shock(shock: &ReleaseShock) -> Vec<Verdict> {
    shock
        .bodies
        .iter()
        .filter_map(|b| b.spec.as_ref().map(|c| (b, c)))
        .map(|(b, c)| match &c.governing {
            Some(g) => {
                let ms = if g.measured_g > 0.0 {
                    (g.limit_g / g.measured_g - 1.0).min(MARGIN_CAP)
                } else {
                    MARGIN_CAP
                };
                Verdict::gate(
                    format!(
                        "{} release shock SRS ({} axis, {:.1} Hz) against the component spec + {} dB [g]",
                        b.body, g.axis, g.frequency_hz, shock.tolerance.upper_db
                    ),
                    g.measured_g,
                    g.limit_g,
                    ms,
                    c.pass,
                    SHOCK_SOURCE,
                )
            }
            None => Verdict::gate(
                format!(
                    "{} release shock SRS: no natural frequency within the component spec's range [g]",
                    b.body
                ),
                0.0,
                0.0,
                -1.0,
                false,
                SHOCK_SOURCE,
            ),
        })
        .collect()
}

/// Every gate name of this file ends with its unit in brackets, written once there; the
/// `unit` field takes it from the name.
fn unit_from_name(v: Verdict) -> Verdict {
    let unit = v
        .name
        .rsplit_once('[')
        .and_then(|(_, u)| u.strip_suffix(']'))
        .unwrap_or_default()
        .to_string();
    v.with_unit(&unit)
}

/// Exit speed (value/v_min − 1), tip-off rate (ω_max/ω − 1), time on the bars (available
/// time / exit time − 1; −1 when it never leaves) and wedging.
pub fn satellite(s: &SatelliteResult, run: &RunLimits, limits: &GatesSpec) -> [Verdict; 4] {
    let i = s.index;
    let available = run.max_time_s - s.release_time_s.unwrap_or(0.0);
    let on_bars = match s.exit_time_s {
        Some(t) => design_margin(
            format!("satellite {i} time on the guide bars, against the simulated time [s]"),
            t,
            available,
            TIME_ON_BARS,
        ),
        None => Verdict::gate(
            format!("satellite {i} time on the guide bars: never left them [s]"),
            available,
            available,
            -1.0,
            false,
            TIME_ON_BARS,
        ),
    };
    [
        at_least(
            format!("satellite {i} exit speed [m/s]"),
            s.final_speed_m_s,
            limits.min_separation_speed_m_s,
            LIMITS_SOURCE,
        ),
        tip_off(s, limits.max_tipoff_rate_deg_s),
        on_bars,
        wedging(s, run),
    ]
    .map(|v| {
        let kind = per_satellite_kind(&v.name);
        v.folded_as(kind, NOMINAL_RELEASE)
    })
}

/// The tip-off rate at the exit from the bars; a satellite that never left them has no exit
/// rate, so its gate fails whatever the rate at the end of the run.
fn tip_off(s: &SatelliteResult, limit: f64) -> Verdict {
    let i = s.index;
    match s.exit_time_s {
        Some(_) => design_margin(
            format!("satellite {i} tip-off rate at bar exit [deg/s]"),
            s.final_rate_deg_s,
            limit,
            LIMITS_SOURCE,
        ),
        None => Verdict::gate(
            format!("satellite {i} tip-off rate at bar exit: never left the bars [deg/s]"),
            s.final_rate_deg_s,
            limit,
            -1.0,
            false,
            LIMITS_SOURCE,
        ),
    }
}

/// The load case of the nominal run's per-satellite gates.
pub const NOMINAL_RELEASE: &str = "nominal release";

/// The kind a per-satellite gate folds under in the report (one row per kind, the worst
/// satellite): its name without the satellite and the unit.
fn per_satellite_kind(name: &str) -> &'static str {
    if name.contains("exit speed") {
        "exit speed"
    } else if name.contains("tip-off rate") {
        "tip-off rate at bar exit"
    } else if name.contains("time on the guide bars") {
        "time on the guide bars"
    } else {
        "wedging"
    }
}

/// The slowest axial speed on the bars against the stall speed; the name gives the cause of
/// a stall (where, and which bore edges carried the load).
pub fn wedging(s: &SatelliteResult, run: &RunLimits) -> Verdict {
    let i = s.index;
    let slowest = s.min_engaged_speed_m_s.unwrap_or(s.final_speed_m_s);
    let name = match (&s.stall, s.wedged) {
        (Some(st), _) => format!("satellite {i} wedges in the bars: {}", st.describe()),
        (None, true) if s.cut_short(run.stall_speed_m_s) => format!(
            "satellite {i} has not left the bars when the run ends at {} s, still moving at {:.3} m/s: raise separation.max_time_s",
            run.max_time_s, s.final_speed_m_s
        ),
        (None, true) => format!(
            "satellite {i} wedges in the bars: still on them when the run ends at {} s",
            run.max_time_s
        ),
        (None, false) => format!("satellite {i} does not wedge: slowest speed on the bars"),
    };
    let v = at_least(
        format!("{name} [m/s]"),
        slowest,
        run.stall_speed_m_s,
        WEDGING,
    );
    Verdict {
        pass: !s.wedged,
        margin: if s.wedged {
            v.margin.min(-1e-9)
        } else {
            v.margin
        },
        ..v
    }
}

/// The smallest gap between consecutive satellites, tracked in free flight until they are
/// `track_clearance_to_m` apart. A pair still closer at the end of the run and closing is
/// projected to touch: value 0, failed.
pub fn clearance(result: &SeparationResult, run: &RunLimits) -> Option<Verdict> {
    let min = result.min_clearance_m?;
    let open: Vec<_> = result
        .pair_clearances
        .iter()
        .filter(|p| p.apart_time_s.is_none())
        .collect();
    let closing = open.iter().find(|p| p.closing_speed_m_s > 0.0);
    let span = if result.clearance_tracked_to_distance {
        format!("tracked until {} m apart", run.track_clearance_to_m)
    } else {
        let pairs: Vec<String> = open
            .iter()
            .map(|p| {
                format!(
                    "{}/{} at {:.3} m, {} at {:.4} m/s",
                    p.upper,
                    p.upper + 1,
                    p.final_gap_m,
                    if p.closing_speed_m_s > 0.0 {
                        "closing"
                    } else {
                        "opening"
                    },
                    p.closing_speed_m_s.abs()
                )
            })
            .collect();
        format!(
            "tracked to the end of the run at {:.1} s ({})",
            result.end_time_s,
            pairs.join("; ")
        )
    };
    let value = if closing.is_some() { 0.0 } else { min };
    Some(above(
        format!("minimum clearance between consecutive satellites, {span} [m]"),
        value,
        0.0,
        NO_RECONTACT,
    ))
}

/// The Monte Carlo's tolerance bounds of the per-run worst values: slowest exit speed
/// (lower), highest tip-off rate (upper), smallest clearance (lower); and the runs in which a
/// satellite wedged.
pub fn monte_carlo(mc: &MonteCarloResult, limits: &GatesSpec) -> Vec<Verdict> {
    let b = &mc.bounds;
    let mut out = Vec::new();
    if let Some(t) = &b.slowest_exit_speed_m_s {
        let name = bound_name("slowest exit speed", t, "m/s");
        let v = at_least(
            name,
            t.value,
            limits.min_separation_speed_m_s,
            LIMITS_SOURCE,
        );
        out.push(demonstrated(v, t));
    }
    if let Some(t) = &b.highest_tip_off_rate_deg_s {
        let name = bound_name("highest tip-off rate", t, "deg/s");
        let v = design_margin(name, t.value, limits.max_tipoff_rate_deg_s, LIMITS_SOURCE);
        out.push(demonstrated(v, t));
    }
    if let Some(t) = &b.min_clearance_m {
        let name = bound_name("smallest inter-satellite clearance", t, "m");
        out.push(demonstrated(above(name, t.value, 0.0, NO_RECONTACT), t));
    }
    out.push(wedging_probability(mc));
    out.into_iter().map(unit_from_name).collect()
}

/// The per-run wedging probability, bounded from above at the demanded confidence
/// (Clopper–Pearson), against 1 − probability, in percent; MS = limit/value − 1. Without a
/// wedge and with too few runs to bring the bound under the limit, "not demonstrated", with
/// the margin of the tail bounds (the share of the needed runs made, minus one).
fn wedging_probability(mc: &MonteCarloResult) -> Verdict {
    let b = &mc.bounds;
    let (value, limit) = (
        100.0 * b.wedging_probability_bound,
        100.0 * (1.0 - mc.probability),
    );
    let conf = percent(mc.confidence);
    let seen = if b.wedged.is_empty() {
        format!("no wedge in {} runs", mc.runs)
    } else {
        let list: Vec<String> = b.wedged.iter().map(describe_wedged).collect();
        let (k, n) = (b.runs_with_wedging, mc.runs);
        let cure = if b.wedged.iter().any(|w| w.cut_short) {
            "; a run that ends before a satellite's exit counts as wedged: raise separation.max_time_s"
        } else {
            ""
        };
        format!("{k} of {n} runs wedged: {}{cure}", list.join("; "))
    };
    let what = format!("Monte Carlo wedging probability per run, upper bound at {conf} confidence");
    let needed = order_stats::runs_needed(mc.probability, mc.confidence);
    match needed {
        Some(needed) if b.wedged.is_empty() && value > limit => {
            let limit_text = percent(1.0 - mc.probability);
            let name = format!(
                "{what} ({seen}), below {limit_text} {NOT_DEMONSTRATED}: need {needed} runs without a wedge [%]"
            );
            let v = design_margin(name, value, limit, WEDGING_MC);
            short_of_runs(v, mc.runs, needed)
        }
        _ => design_margin(format!("{what} ({seen}) [%]"), value, limit, WEDGING_MC),
    }
}

/// "run 3 satellite 2, final speed 0.004 m/s", or for a satellite the run's end caught
/// sliding "run 3 satellite 2, still sliding at 0.210 m/s when the run ended".
fn describe_wedged(w: &Wedged) -> String {
    let (run, sat, v) = (w.run, w.satellite, w.final_speed_m_s);
    if w.cut_short {
        format!("run {run} satellite {sat}, still sliding at {v:.3} m/s when the run ended")
    } else {
        format!("run {run} satellite {sat}, final speed {v:.3} m/s")
    }
}

/// "Monte Carlo slowest exit speed, lower 99.73% bound at 95% confidence (run 1 of 1109)
/// [m/s]", or with too few runs "…, 99.73% at 95% confidence not demonstrated: 59 runs
/// support at most 95.05%; need 1109 (value: the 95.05% bound) [m/s]".
fn bound_name(what: &str, t: &TailBound, unit: &str) -> String {
    let side = match t.side {
        crate::separation::montecarlo::Side::Lower => "lower",
        crate::separation::montecarlo::Side::Upper => "upper",
    };
    let (p, c) = (percent(t.probability), percent(t.confidence));
    if t.demonstrated {
        format!(
            "Monte Carlo {what}, {side} {p} bound at {c} confidence (extreme run {} of {}) [{unit}]",
            t.rank, t.runs
        )
    } else {
        format!(
            "Monte Carlo {what}, {side} {p} bound at {c} confidence {NOT_DEMONSTRATED}: {} runs \
             support at most {} at {c} confidence; need {} (value: the {} bound) [{unit}]",
            t.runs,
            percent(t.demonstrated_probability),
            t.runs_needed,
            percent(t.demonstrated_probability)
        )
    }
}

/// A bound the runs do not demonstrate fails whatever its value; its margin is the share of
/// the needed runs made, minus one (−0.95 for 59 of 1109).
fn demonstrated(v: Verdict, t: &TailBound) -> Verdict {
    if t.demonstrated {
        return v;
    }
    short_of_runs(v, t.runs, t.runs_needed)
}

/// `v` failed for want of runs: margin runs/needed − 1 (kept below zero).
fn short_of_runs(v: Verdict, runs: usize, needed: usize) -> Verdict {
    let short = runs as f64 / needed.max(1) as f64 - 1.0;
    Verdict {
        pass: false,
        margin: short.min(-1e-9),
        ..v
    }
}

/// 0.9973 → "99.73%", 0.95 → "95%", 0.950492 → "95.05%".
fn percent(x: f64) -> String {
    let s = format!("{:.2}", 100.0 * x);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    format!("{s}%")
}
