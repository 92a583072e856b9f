//! The measured test logs: channel levels, tolerance against the reference profile,
//! resonances, and the before/after signature comparison.

use super::or_dash;
use crate::report::document::{Block, Column, ListItem, Section, Table, Text};
use crate::report::{Qualification, TestLogResult};
use crate::signal::SignatureReport;

pub fn section(q: &Qualification) -> Option<Section> {
    let td = q.test_data.as_ref()?;
    let mut blocks = vec![Block::List(td.logs.iter().map(log_item).collect())];
    if let Some(sig) = &td.signature {
        blocks.push(Block::Table(signature(sig)));
    }
    Some(Section::new("Test data", blocks))
}

/// One log: its channels' Grms, then its tolerance and resonances as sub-items.
fn log_item(log: &TestLogResult) -> ListItem {
    let channels: Vec<String> = log
        .channels
        .iter()
        .map(|(n, g)| format!("{n} {g:.4} Grms"))
        .collect();
    let mut item = ListItem::new(
        Text::default()
            .strong(log.name.clone())
            .and(" (")
            .code(log.file.clone())
            .and(format!(", {:?}): {}", log.kind, channels.join(", "))),
    );
    for c in &log.shock {
        let k = &c.check;
        item.details.push(Text::plain(format!(
            "{}: peak {:.1} {} at {:.3} ms; SRS {:.1}% of {} points above +{} dB, {:.1}% below −{} dB of the spec; worst {:+.2} dB at {:.0} Hz",
            c.name,
            c.peak,
            c.unit,
            c.peak_time_s * 1e3,
            k.fraction_above_upper * 100.0,
            k.points.len(),
            k.tolerance.upper_db,
            k.fraction_below_lower * 100.0,
            k.tolerance.lower_db,
            k.worst_db,
            k.worst_hz
        )));
    }
    if let Some(t) = &log.tolerance {
        item.details.push(Text::plain(format!(
            "tolerance: {:.2}% of lines beyond ±{} dB (alarm), {:.2}% beyond ±{} dB (abort); worst {:+.2} dB at {:.0} Hz; Grms {:.4} against {:.4} ({:+.2}%)",
            t.fraction_outside_alarm * 100.0,
            t.spec.alarm_db,
            t.fraction_outside_abort * 100.0,
            t.spec.abort_db,
            t.worst_excursion_db,
            t.worst_frequency_hz,
            t.measured_grms,
            t.reference_grms,
            t.grms_error_pct
        )));
    }
    if !log.resonances.is_empty() {
        let r: Vec<String> = log
            .resonances
            .iter()
            .map(|r| format!("{:.1} Hz", r.frequency_hz))
            .collect();
        item.details
            .push(Text::plain(format!("resonances: {}", r.join(", "))));
    }
    item
}

/// Every mode before and after the test, with its shift and the verdict on it.
fn signature(sig: &SignatureReport) -> Table {
    let mut t = Table::new(
        [
            "mode",
            "before [Hz]",
            "after [Hz]",
            "shift [%]",
            "amplitude change [%]",
        ]
        .map(Column::right)
        .to_vec(),
    );
    t.columns.push(Column::left("verdict"));
    for m in &sig.modes {
        t.row(vec![
            m.mode.to_string(),
            format!("{:.2}", m.before_hz),
            or_dash(m.after_hz.map(|v| format!("{v:.2}"))),
            or_dash(m.shift_pct.map(|v| format!("{v:+.3}"))),
            or_dash(m.amplitude_change_pct.map(|v| format!("{v:+.2}"))),
            if m.pass {
                "pass".to_string()
            } else {
                format!("FAIL: {}", m.reason)
            },
        ]);
    }
    t
}
