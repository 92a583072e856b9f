//! The separation: per satellite, speeds, rates and contacts; the energy audit; the Monte
//! Carlo percentiles when dispersions were run.

use super::or_dash;
use crate::report::document::{Block, Column, Section, Table, Text};
use crate::report::{Qualification, SeparationSummary};
use crate::separation::MonteCarloResult;

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
    for (name, p) in [
        ("exit speed [m/s]", &mc.final_speed_m_s),
        ("tip-off rate [deg/s]", &mc.tip_off_rate_deg_s),
        ("min. clearance [m]", &mc.min_clearance_m),
    ] {
        let mut cells = vec![name.to_string()];
        cells.extend([p.p0_27, p.p1, p.p50, p.p99, p.p99_73].map(|v| format!("{:.4}", v.value)));
        t.row(cells);
    }
    t
}
