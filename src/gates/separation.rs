//! Separation gates: every satellite leaves the guide bars fast enough, without too much
//! tip-off, within the simulated time, and never touches its neighbour again; with a Monte
//! Carlo, the same at the 3σ (99.73%) bounds.

use super::verdict::{Verdict, above, at_least, at_most};
use crate::separation::{MonteCarloResult, SeparationResult};
use crate::spec::GatesSpec;

const LIMITS_SOURCE: &str = "[gates] limits; default ASSUMPTION: exit speed ≥ 0.2 m/s and tip-off ≤ 2.5 deg/s, below the paper's measured 0.25–0.35 m/s and its first satellite's accepted 2.47 deg/s (§4, §5.2)";
const NO_RECONTACT: &str =
    "ASSUMPTION: satellites must not touch again after release (collision-free deployment)";

/// What the gates need of one satellite's nominal release.
#[derive(Debug, Clone, Copy)]
pub struct Exit {
    pub index: usize,
    pub speed_m_s: f64,
    pub tipoff_rate_deg_s: f64,
    pub time_s: Option<f64>,
}

/// The nominal run's gates: per satellite speed, tip-off and exit, then the clearance.
pub fn nominal(result: &SeparationResult, max_time_s: f64, limits: &GatesSpec) -> Vec<Verdict> {
    let mut out = Vec::new();
    for s in &result.satellites {
        let exit = Exit {
            index: s.index,
            speed_m_s: s.final_speed_m_s,
            tipoff_rate_deg_s: s.final_rate_deg_s,
            time_s: s.exit_time_s,
        };
        out.extend(satellite(&exit, max_time_s, limits));
    }
    out.extend(result.min_clearance_m.map(clearance));
    out
}

/// Exit speed (margin v/v_min − 1), tip-off rate (1 − ω/ω_max) and clearing the bars (a
/// yes/no criterion: margin +1 or −1, value the exit time or NaN when it never exits).
pub fn satellite(exit: &Exit, max_time_s: f64, limits: &GatesSpec) -> [Verdict; 3] {
    let i = exit.index;
    let cleared = exit.time_s.is_some();
    [
        at_least(
            format!("satellite {i} exit speed [m/s]"),
            exit.speed_m_s,
            limits.min_separation_speed_m_s,
            LIMITS_SOURCE,
        )
        .with_unit("m/s"),
        at_most(
            format!("satellite {i} tip-off rate at bar exit [deg/s]"),
            exit.tipoff_rate_deg_s,
            limits.max_tipoff_rate_deg_s,
            LIMITS_SOURCE,
        )
        .with_unit("deg/s"),
        Verdict::gate(
            format!("satellite {i} clears the guide bars"),
            exit.time_s.unwrap_or(f64::NAN),
            max_time_s,
            if cleared { 1.0 } else { -1.0 },
            cleared,
            "ASSUMPTION: every satellite must leave the bars within the simulated time ([separation] max_time_s)",
        )
        .with_unit("s"),
    ]
}

/// The smallest gap between consecutive satellites must stay above 0 (margin: the gap, m).
pub fn clearance(min_clearance_m: f64) -> Verdict {
    above(
        "minimum clearance between consecutive satellites [m]",
        min_clearance_m,
        0.0,
        NO_RECONTACT,
    )
    .with_unit("m")
}

/// The Monte Carlo's 3σ bounds: P0.27 exit speed, P99.73 tip-off rate, P0.27 clearance.
pub fn monte_carlo(mc: &MonteCarloResult, limits: &GatesSpec) -> [Verdict; 3] {
    [
        at_least(
            "Monte Carlo P0.27 exit speed [m/s] (99.73% bound)",
            mc.final_speed_m_s.p0_27,
            limits.min_separation_speed_m_s,
            LIMITS_SOURCE,
        )
        .with_unit("m/s"),
        at_most(
            "Monte Carlo P99.73 tip-off rate [deg/s]",
            mc.tip_off_rate_deg_s.p99_73,
            limits.max_tipoff_rate_deg_s,
            LIMITS_SOURCE,
        )
        .with_unit("deg/s"),
        above(
            "Monte Carlo P0.27 inter-satellite clearance [m]",
            mc.min_clearance_m.p0_27,
            0.0,
            NO_RECONTACT,
        )
        .with_unit("m"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed against the [gates] defaults (0.2 m/s, 2.5 deg/s):
    /// 0.25/0.2 − 1 = 0.25; 1 − 2.0/2.5 = 0.2.
    #[test]
    fn a_satellite_that_exits_fast_and_steady_passes_with_the_defined_margins() {
        let exit = Exit {
            index: 2,
            speed_m_s: 0.25,
            tipoff_rate_deg_s: 2.0,
            time_s: Some(9.5),
        };
        let [speed, rate, cleared] = satellite(&exit, 20.0, &GatesSpec::default());
        assert!(speed.pass && (speed.margin - 0.25).abs() < 1e-12);
        assert!(rate.pass && (rate.margin - 0.2).abs() < 1e-12);
        assert!(cleared.pass && cleared.margin == 1.0 && cleared.value == 9.5);
    }

    #[test]
    fn a_satellite_left_on_the_bars_fails_with_margin_minus_one() {
        let exit = Exit {
            index: 1,
            speed_m_s: 0.0,
            tipoff_rate_deg_s: 0.0,
            time_s: None,
        };
        let [_, _, cleared] = satellite(&exit, 20.0, &GatesSpec::default());
        assert!(!cleared.pass && cleared.margin == -1.0 && cleared.value.is_nan());
        assert_eq!(cleared.limit, 20.0);
    }

    #[test]
    fn clearance_margin_is_the_gap_itself() {
        let v = clearance(0.012);
        assert!(v.pass && (v.margin - 0.012).abs() < 1e-15);
        assert!(!clearance(-0.001).pass);
    }
}
