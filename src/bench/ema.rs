//! `satqual bench ema`: the LSCF/LSFD identification of the analytic 3-DOF system
//! ([`crate::catalogue::analytic::three_dof`], 0.25 Hz lines to 200 Hz, three outputs):
//! run time against the worst frequency and damping error, over the highest model order and
//! the noise added to the FRFs (uniform complex, relative to |H| per line, seeded).

use crate::Error;
use crate::catalogue::analytic::three_dof;
use crate::signal::PeakOptions;
use crate::signal::ema::{Criteria, EmaOptions, FrfForm, Method, identify};
use serde::Serialize;
use std::fmt::Write as _;
use std::time::Instant;

#[derive(Serialize)]
struct Row {
    noise_pct: f64,
    order_max: usize,
    modes_found: usize,
    run_ms: f64,
    /// Worst relative errors over the three modes, percent (null when a mode was missed).
    frequency_error_pct: Option<f64>,
    damping_error_pct: Option<f64>,
}

/// The table as (JSON, Markdown).
pub fn run() -> Result<(String, String), Error> {
    let sys = three_dof();
    let mut rows = Vec::new();
    for noise in [0.0, 0.005, 0.02] {
        let set = three_dof().frf_set(noise);
        for order_max in [10usize, 20, 40, 80] {
            let opts = EmaOptions {
                f_lo: 5.0,
                f_hi: 200.0,
                method: Method::Lscf,
                order_max,
                order_max_is_default: false,
                form: FrfForm::Accelerance,
                criteria: Criteria::default(),
                peaks: PeakOptions::default(),
            };
            let t = Instant::now();
            let m = identify(&set, &opts)?;
            let run_ms = t.elapsed().as_secs_f64() * 1e3;
            let found = m.modes.len() == 3;
            let worst = |f: &dyn Fn(usize) -> f64| {
                found.then(|| (0..3).map(f).fold(0.0f64, f64::max) * 100.0)
            };
            rows.push(Row {
                noise_pct: noise * 100.0,
                order_max,
                modes_found: m.modes.len(),
                run_ms,
                frequency_error_pct: worst(&|r| {
                    (m.modes[r].frequency_hz / sys.frequencies_hz[r] - 1.0).abs()
                }),
                damping_error_pct: worst(&|r| {
                    (m.modes[r].damping_ratio / sys.damping[r] - 1.0).abs()
                }),
            });
        }
    }
    let mut md = String::from(
        "# bench ema: LSCF + LSFD on the analytic 3-DOF (3 outputs, 781 lines, 5–200 Hz)\n\n| noise % | order max | modes | run ms | max f error % | max ζ error % |\n|---|---|---|---|---|---|\n",
    );
    let pct = |v: Option<f64>| v.map_or("missed".to_string(), |e| format!("{e:.2e}"));
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.1} | {} | {} |",
            r.noise_pct,
            r.order_max,
            r.modes_found,
            r.run_ms,
            pct(r.frequency_error_pct),
            pct(r.damping_error_pct)
        );
    }
    Ok((super::to_json(&rows)?, md))
}
