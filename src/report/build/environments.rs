//! The input environments as applied: every sine segment, the random profile with its level,
//! weight reduction, Grms and duration, each with its source.

use super::number;
use crate::report::Qualification;
use crate::report::document::{Block, Column, Section, Table, Text};
use crate::spec::environment::{RandomEnvironment, SineBasis, SineEnvironment};

/// The section, when a response analysis ran.
pub fn section(q: &Qualification) -> Option<Section> {
    let env = q.environments.as_ref()?;
    let mut blocks = Vec::new();
    if let Some(s) = &env.sine {
        blocks.extend(sine(s));
    }
    if let Some(r) = &env.random {
        blocks.extend(random(r));
    }
    (!blocks.is_empty()).then(|| Section::new("Input environments", blocks))
}

fn sine(s: &SineEnvironment) -> Vec<Block> {
    let mut t = Table::new(vec![
        Column::left("sine segment"),
        Column::right("from [Hz]"),
        Column::right("to [Hz]"),
        Column::right("displacement 0-pk [mm]"),
        Column::right("acceleration 0-pk [g]"),
    ]);
    for (i, g) in s.segments.iter().enumerate() {
        t.row(vec![
            format!("{}", i + 1),
            number(g.from_hz),
            number(g.to_hz),
            g.displacement_m.map_or("—".into(), |d| number(1e3 * d)),
            match (g.displacement_m, g.acceleration_g) {
                (_, Some(a)) => number(a),
                (Some(_), None) => format!(
                    "{} → {}",
                    number(g.level_g(g.from_hz)),
                    number(g.level_g(g.to_hz))
                ),
                (None, None) => "—".into(),
            },
        ]);
    }
    let mut what = vec![format!("axes {}", s.axes.join(", "))];
    if let Some(l) = s.level {
        what.push(format!("{} level", l.name()));
    }
    what.push(match s.basis {
        SineBasis::Test => "segments applied as given (test level)".into(),
        SineBasis::Limit => format!(
            "limit-level segments × {} (GSFC-STD-7000A Table 2.4-1), shown as applied",
            s.level_factor
        ),
    });
    if let (Some(r), Some(d)) = (s.sweep_rate_oct_min, s.duration_s) {
        what.push(format!("{r} oct/min, {d:.0} s per sweep and axis"));
    }
    vec![
        Block::Paragraph(Text::plain(format!(
            "Sine, {}; source: {}.",
            what.join(", "),
            s.source
        ))),
        Block::Table(t),
    ]
}

fn random(r: &RandomEnvironment) -> Vec<Block> {
    let mut what = Vec::new();
    if let Some(name) = &r.environment {
        what.push(format!("named table `{name}`"));
    }
    if let Some(l) = r.level {
        what.push(format!(
            "{} level (+{:.2} dB over the table)",
            l.name(),
            r.level_gain_db
        ));
    }
    if let Some(w) = &r.weight_reduction {
        what.push(format!(
            "GEVS weight reduction for {:.1} kg (rule applied at {:.1} kg): −{:.2} dB",
            w.mass_kg, w.mass_used_kg, w.reduction_db
        ));
    }
    what.push(format!("{:.2} Grms", r.grms));
    if let Some(d) = r.duration_s {
        what.push(format!("{d:.0} s per axis"));
    }
    let mut t = Table::new(vec![
        Column::right("frequency [Hz]"),
        Column::right("ASD [g²/Hz]"),
    ]);
    for p in &r.profile {
        t.row(vec![number(p[0]), format!("{:.6}", p[1])]);
    }
    vec![
        Block::Paragraph(Text::plain(format!(
            "Random, axes {}: {}; source: {}.",
            r.axes.join(", "),
            what.join(", "),
            r.source
        ))),
        Block::Table(t),
    ]
}
