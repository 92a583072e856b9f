//! One plot per output and swept key: the output against the key, one line per combination of
//! the other keys' values (a grid), or the bare points (a Latin hypercube); a point that fails
//! any gate gets a red cross, and a gated output shows its limit.

use super::outputs::{OUTPUTS, Output};
use crate::error::Error;
use crate::report::document::Figure;
use crate::report::plot::{Limit, Series, sweep_svg};
use crate::results::SweepTable;

pub fn figures(t: &SweepTable) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    for (j, key) in t.keys.iter().enumerate() {
        for (k, out) in OUTPUTS.iter().enumerate() {
            if t.points.iter().all(|p| (out.get)(p).is_none()) {
                continue;
            }
            figs.push(figure(t, j, key, k, out)?);
        }
    }
    Ok(figs)
}

/// Output `out` against key `j`.
fn figure(t: &SweepTable, j: usize, key: &str, k: usize, out: &Output) -> Result<Figure, Error> {
    let groups = groups(t, j, out);
    let series: Vec<Series> = groups
        .iter()
        .map(|(label, pts)| Series {
            label: label.clone(),
            points: pts,
        })
        .collect();
    let failed: Vec<(f64, f64)> = t
        .points
        .iter()
        .filter(|p| !p.pass)
        .filter_map(|p| (out.get)(p).map(|y| (p.values[j], y)))
        .collect();
    let limit = out
        .gate
        .and_then(|g| t.points.first().and_then(|p| p.gates.get(g)))
        .map(|g| Limit {
            y: g.limit,
            label: format!("gate limit {}", g.limit),
        });
    let title = format!("{} against {}", out.name, short(key));
    Ok(Figure {
        stem: format!("sweep_{}_{}_{}", j + 1, k + 1, short(key)),
        caption: format!(
            "{} of each point's Monte Carlo ({} runs) against `{key}`; a red cross marks a point \
             that fails a gate",
            out.heading(),
            t.runs
        ),
        svg: sweep_svg(
            &title,
            key,
            &out.heading(),
            &series,
            &failed,
            limit.as_ref(),
        )?,
    })
}

/// One plotted line: the points that share the other keys' values (bit patterns).
struct Line {
    others: Vec<u64>,
    label: String,
    points: Vec<(f64, f64)>,
}

/// The points as lines: those sharing every other key's value form one line, sorted along
/// key `j`, in the order the lines first appear. When no two points share them (a Latin
/// hypercube), one series holds every point.
fn groups(t: &SweepTable, j: usize, out: &Output) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut lines: Vec<Line> = Vec::new();
    for p in &t.points {
        let Some(y) = (out.get)(p) else { continue };
        let others: Vec<u64> = (0..p.values.len())
            .filter(|&i| i != j)
            .map(|i| p.values[i].to_bits())
            .collect();
        match lines.iter_mut().find(|l| l.others == others) {
            Some(l) => l.points.push((p.values[j], y)),
            None => {
                let label = (0..p.values.len())
                    .filter(|&i| i != j)
                    .map(|i| format!("{} = {}", short(&t.keys[i]), p.values[i]))
                    .collect::<Vec<_>>()
                    .join(", ");
                lines.push(Line {
                    others,
                    label,
                    points: vec![(p.values[j], y)],
                });
            }
        }
    }
    if lines.len() > 1 && lines.iter().all(|l| l.points.len() == 1) {
        let points = lines.into_iter().flat_map(|l| l.points).collect();
        lines = vec![Line {
            others: Vec::new(),
            label: String::new(),
            points,
        }];
    }
    lines
        .into_iter()
        .map(|mut l| {
            l.points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let label = if l.label.is_empty() {
                "points".into()
            } else {
                l.label
            };
            (label, l.points)
        })
        .collect()
}

/// The last segment of a dotted key, for titles and file names.
fn short(key: &str) -> String {
    key.rsplit('.')
        .next()
        .unwrap_or(key)
        .replace(['[', ']'], "_")
}
