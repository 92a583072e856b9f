//! The measured logs: an FRF log as |H1| and coherence, a shock log as its SRS against the
//! shock specification, any other as its PSDs against the reference profile and tolerance
//! bands.

use super::{Files, csv};
use crate::error::Error;
use crate::report::document::Figure;
use crate::report::plot::{Options, Scale, Series, chart_svg, lines_svg};
use crate::report::{TestDataSummary, TestLogResult};
use crate::spec::LogKind;

/// The curve an FRF log carries beside its |H1|; its presence marks the log as an FRF.
const COHERENCE: &str = "coherence";

pub fn figures(td: &TestDataSummary, files: &mut Files) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    for (k, log) in td.logs.iter().enumerate() {
        let stem = format!("test_{}", k + 1);
        push_curves(&stem, log, files);
        if log.kind == LogKind::Shock {
            figs.push(srs(&stem, log)?);
        } else if log.curves.iter().any(|(l, _)| l == COHERENCE) {
            figs.push(frf(&stem, log)?);
            figs.push(coherence(&stem, log)?);
        } else {
            figs.push(psd(&stem, log)?);
        }
    }
    Ok(figs)
}

/// One CSV per curve, named after the curve with anything but letters and digits as `_`.
fn push_curves(stem: &str, log: &TestLogResult, files: &mut Files) {
    for (label, pts) in &log.curves {
        let safe: String = label
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        files.push((
            format!("curves/{stem}_{safe}.csv"),
            csv("frequency_hz,value", pts.iter().map(|p| vec![p.0, p.1])),
        ));
    }
}

/// The log's curves whose label passes `keep`, as plot series.
fn series(log: &TestLogResult, keep: impl Fn(&str) -> bool) -> Vec<Series<'_>> {
    log.curves
        .iter()
        .filter(|(l, _)| keep(l))
        .map(|(l, p)| Series {
            label: l.clone(),
            points: p,
        })
        .collect()
}

fn frf(stem: &str, log: &TestLogResult) -> Result<Figure, Error> {
    Ok(Figure {
        stem: format!("{stem}_frf"),
        caption: format!("{}: |H1| with its resonances ({})", log.name, log.file),
        svg: lines_svg(
            &format!("{}: FRF", log.name),
            "frequency [Hz]",
            "|H1|",
            &series(log, |l| l != COHERENCE),
            Scale::Log,
            Scale::Log,
        )?,
    })
}

/// Coherence lies in [0, 1] by definition; a fitted axis would magnify the noise of a
/// coherence near 1 into a solid band, so the axis is the whole [0, 1] range.
fn coherence(stem: &str, log: &TestLogResult) -> Result<Figure, Error> {
    let opts = Options {
        y_range: Some((0.0, 1.05)),
        ..Options::lines(Scale::Log, Scale::Linear)
    };
    Ok(Figure {
        stem: format!("{stem}_coherence"),
        caption: format!(
            "{}: coherence γ² (1 = output fully explained by the input)",
            log.name
        ),
        svg: chart_svg(
            &format!("{}: coherence", log.name),
            "frequency [Hz]",
            "γ²",
            &series(log, |l| l == COHERENCE),
            &[],
            opts,
        )?,
    })
}

fn srs(stem: &str, log: &TestLogResult) -> Result<Figure, Error> {
    Ok(Figure {
        stem: format!("{stem}_srs"),
        caption: format!(
            "{}: shock response spectrum against the shock specification and its tolerance ({})",
            log.name, log.file
        ),
        svg: lines_svg(
            &format!("{}: SRS", log.name),
            "natural frequency [Hz]",
            "SRS maximax [g]",
            &series(log, |_| true),
            Scale::Log,
            Scale::Log,
        )?,
    })
}

fn psd(stem: &str, log: &TestLogResult) -> Result<Figure, Error> {
    Ok(Figure {
        stem: format!("{stem}_psd"),
        caption: format!(
            "{}: measured PSD against the reference profile and its tolerance bands ({})",
            log.name, log.file
        ),
        svg: lines_svg(
            &format!("{}: PSD", log.name),
            "frequency [Hz]",
            "PSD [g²/Hz]",
            &series(log, |_| true),
            Scale::Log,
            Scale::Log,
        )?,
    })
}
