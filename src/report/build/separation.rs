//! The separation: per satellite, speeds, rates and contacts; the energy audit; the Monte
//! Carlo percentiles when dispersions were run.

use super::or_dash;
use crate::report::document::{Block, Column, Section, Table, Text};
use crate::report::{Qualification, SeparationSummary};
use crate::separation::MonteCarloResult;
use crate::separation::montecarlo::Percentile;

pub fn section(q: &Qualification) -> Option<Section> {
    let sep = q.separation.as_ref()?;
    let mut blocks = vec![
        Block::Table(satellites(sep)),
        Block::Paragraph(Text::plain(format!(
            "Energy-audit residual: {:.3e} of the spring work.",
            sep.result.energy.relative_residual
        ))),
    ];
    if let Some(mc) = &sep.monte_carlo {
        blocks.push(Block::Paragraph(Text::plain(format!(
            "Monte Carlo, {} runs, seed {}:",
            mc.runs, mc.seed
        ))));
        blocks.push(Block::Table(percentiles(mc)));
        blocks.push(Block::Paragraph(Text::plain(interval_note(mc))));
    }
    Some(Section::new("Separation", blocks))
}

fn satellites(sep: &SeparationSummary) -> Table {
    let mut t = Table::new(
        [
            "satellite",
            "max speed [m/s]",
            "exit speed [m/s]",
            "exit rate [deg/s]",
            "peak rate [deg/s]",
            "exit time [s]",
            "contacts",
        ]
        .map(Column::right)
        .to_vec(),
    );
    for st in &sep.result.satellites {
        t.row(vec![
            st.index.to_string(),
            format!("{:.4}", st.max_speed_m_s),
            format!("{:.4}", st.final_speed_m_s),
            format!("{:.3}", st.final_rate_deg_s),
            format!("{:.3}", st.peak_rate_deg_s),
            or_dash(st.exit_time_s.map(|t| format!("{t:.3}"))),
            st.contacts.to_string(),
        ]);
    }
    t
}

/// The tails a launcher interface asks for (3σ two-sided, 1%) and the median.
fn percentiles(mc: &MonteCarloResult) -> Table {
    let mut t = Table::new(vec![Column::left("quantity")]);
    t.columns
        .extend(["P0.27", "P1", "P50", "P99", "P99.73"].map(Column::right));
    let rows = [
        ("exit speed [m/s]", Some(&mc.final_speed_m_s)),
        ("tip-off rate [deg/s]", Some(&mc.tip_off_rate_deg_s)),
        ("min. clearance [m]", mc.min_clearance_m.as_ref()),
    ];
    // A single satellite has no pair, hence no clearance row.
    for (name, p) in rows.into_iter().filter_map(|(n, p)| p.map(|p| (n, p))) {
        let mut cells = vec![name.to_string()];
        cells.extend([&p.p0_27, &p.p1, &p.p50, &p.p99, &p.p99_73].map(with_interval));
        t.row(cells);
    }
    t
}

/// "0.3337 [0.3301, 0.3352]": the sample percentile and the interval of the true one; "–"
/// for a side no sample bounds.
fn with_interval(p: &Percentile) -> String {
    let end = |v: Option<f64>| v.map_or("–".to_string(), |x| format!("{x:.4}"));
    format!("{:.4} [{}, {}]", p.value, end(p.ci_low), end(p.ci_high))
}

fn interval_note(mc: &MonteCarloResult) -> String {
    format!(
        "In brackets: the {:.0}% interval of the true percentile from order statistics (equal-tailed, distribution-free); \
         \"–\" where no run lies far enough out to bound that side (a 0.27% tail needs about a thousand runs). \
         Exit speed and tip-off rate pool every satellite of a run, whose values share the run's dispersions: their intervals are indicative; \
         the gates use one value per run.",
        100.0 * mc.confidence,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A percentile cell states the interval, with a dash for a side no sample bounds.
    #[test]
    fn a_percentile_cell_carries_its_interval() {
        let p = Percentile {
            p: 0.0027,
            value: 0.30123,
            ci_low: None,
            ci_high: Some(0.31),
            confidence: 0.95,
            runs: 59,
            samples: 354,
        };
        assert_eq!(with_interval(&p), "0.3012 [–, 0.3100]");
    }
}
