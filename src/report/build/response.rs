//! The sine and random response tables, with the joint loads between them.

use super::joint_loads;
use crate::report::Qualification;
use crate::report::document::{Block, Column, Section, Table};
use crate::response::SceneResponse;

/// Sine response, joint loads and random response, each when there is something to show.
pub fn sections(q: &Qualification) -> Vec<Section> {
    let Some(resp) = &q.response else {
        return Vec::new();
    };
    [sine(resp), joint_loads::section(resp), random(resp)]
        .into_iter()
        .flatten()
        .collect()
}

/// The peak acceleration of every response point, per axis.
fn sine(resp: &SceneResponse) -> Option<Section> {
    if resp.sine.is_empty() {
        return None;
    }
    let mut t = Table::new(vec![
        Column::left("axis"),
        Column::left("point"),
        Column::right("peak [g]"),
        Column::right("at [Hz]"),
    ]);
    for a in &resp.sine {
        for p in &a.peaks {
            t.row(vec![
                a.axis.clone(),
                p.name.clone(),
                format!("{:.3}", p.acceleration_g),
                format!("{:.2}", p.frequency_hz),
            ]);
        }
    }
    Some(Section::new("Sine response", vec![Block::Table(t)]))
}

/// The RMS, 3σ and PSD peak of every response point, per axis.
fn random(resp: &SceneResponse) -> Option<Section> {
    if resp.random.is_empty() {
        return None;
    }
    let mut t = Table::new(vec![
        Column::left("axis"),
        Column::right("input Grms"),
        Column::left("point"),
        Column::right("Grms"),
        Column::right("3σ [g]"),
        Column::right("peak PSD [g²/Hz]"),
        Column::right("at [Hz]"),
    ]);
    for a in &resp.random {
        for r in &a.responses {
            t.row(vec![
                a.axis.clone(),
                format!("{:.2}", a.input_grms),
                r.name.clone(),
                format!("{:.3}", r.grms),
                format!("{:.3}", r.three_sigma_g),
                format!("{:.4}", r.peak_psd_g2_hz),
                format!("{:.1}", r.peak_psd_hz),
            ]);
        }
    }
    Some(Section::new("Random response", vec![Block::Table(t)]))
}
