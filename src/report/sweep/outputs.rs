//! The outputs a sweep tabulates and plots: the Monte Carlo percentiles of each point, with the
//! gate that judges some of them; and the CSV of the table.

use crate::results::{SweepPoint, SweepTable};

/// One tabulated output: its name, unit, CSV column and how to read it from a point.
pub struct Output {
    pub name: &'static str,
    pub unit: &'static str,
    pub column: &'static str,
    pub get: fn(&SweepPoint) -> Option<f64>,
    /// Index in the point's gates of the gate that judges this output.
    pub gate: Option<usize>,
}

impl Output {
    pub fn heading(&self) -> String {
        format!("{} [{}]", self.name, self.unit)
    }
}

/// Exit speed, tip-off rate and clearance at the tails the gates use and at the median.
pub const OUTPUTS: [Output; 7] = [
    Output {
        name: "exit speed P0.27",
        unit: "m/s",
        column: "exit_speed_p0_27_m_s",
        get: |p| Some(p.final_speed_m_s.p0_27.value),
        gate: Some(0),
    },
    Output {
        name: "exit speed P1",
        unit: "m/s",
        column: "exit_speed_p1_m_s",
        get: |p| Some(p.final_speed_m_s.p1.value),
        gate: None,
    },
    Output {
        name: "exit speed P50",
        unit: "m/s",
        column: "exit_speed_p50_m_s",
        get: |p| Some(p.final_speed_m_s.p50.value),
        gate: None,
    },
    Output {
        name: "exit speed P99",
        unit: "m/s",
        column: "exit_speed_p99_m_s",
        get: |p| Some(p.final_speed_m_s.p99.value),
        gate: None,
    },
    Output {
        name: "tip-off rate P50",
        unit: "deg/s",
        column: "tip_off_rate_p50_deg_s",
        get: |p| Some(p.tip_off_rate_deg_s.p50.value),
        gate: None,
    },
    Output {
        name: "tip-off rate P99.73",
        unit: "deg/s",
        column: "tip_off_rate_p99_73_deg_s",
        get: |p| Some(p.tip_off_rate_deg_s.p99_73.value),
        gate: Some(1),
    },
    Output {
        name: "min clearance P0.27",
        unit: "m",
        column: "min_clearance_p0_27_m",
        get: |p| p.min_clearance_m.as_ref().map(|c| c.p0_27.value),
        gate: Some(2),
    },
];

/// `sweep.csv`: point, the keys, runs, every output, then each gate's pass and the point's.
/// Numbers in shortest round-trip form; an absent output is an empty cell.
pub fn csv(t: &SweepTable) -> String {
    let mut head = vec!["point".to_string()];
    head.extend(t.keys.iter().cloned());
    head.push("runs".into());
    head.extend(OUTPUTS.iter().map(|o| o.column.to_string()));
    head.extend(
        [
            "pass_exit_speed",
            "pass_tip_off_rate",
            "pass_clearance",
            "pass",
        ]
        .map(String::from),
    );
    let mut s = head.join(",") + "\n";
    for p in &t.points {
        let mut row = vec![p.point.to_string()];
        row.extend(p.values.iter().map(|v| v.to_string()));
        row.push(p.runs.to_string());
        row.extend(
            OUTPUTS
                .iter()
                .map(|o| (o.get)(p).map_or(String::new(), |v| v.to_string())),
        );
        row.extend((0..3).map(|g| p.gates.get(g).map_or(String::new(), |g| g.pass.to_string())));
        row.push(p.pass.to_string());
        s += &(row.join(",") + "\n");
    }
    s
}
