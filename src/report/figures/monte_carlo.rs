//! Monte Carlo separation: a histogram of each dispersed outcome.

use super::{Files, csv};
use crate::error::Error;
use crate::report::document::Figure;
use crate::report::plot::{Scale, Series, lines_svg};
use crate::separation::MonteCarloResult;

/// Bins of each histogram: enough to see the shape of a few hundred runs.
const BINS: usize = 20;

pub fn histograms(mc: &MonteCarloResult, files: &mut Files) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    for (stem, label, samples) in [
        (
            "mc_exit_speed",
            "exit speed [m/s]",
            &mc.samples_final_speed_m_s,
        ),
        (
            "mc_tip_off_rate",
            "tip-off rate [deg/s]",
            &mc.samples_tip_off_rate_deg_s,
        ),
        (
            "mc_min_clearance",
            "minimum inter-satellite clearance [m]",
            &mc.samples_min_clearance_m,
        ),
    ] {
        files.push((
            format!("curves/{stem}.csv"),
            csv("sample", samples.iter().map(|v| vec![*v])),
        ));
        figs.push(Figure {
            stem: stem.into(),
            caption: format!(
                "Monte Carlo ({} runs, seed {}): histogram of the {label}",
                mc.runs, mc.seed
            ),
            svg: lines_svg(
                &format!("Monte Carlo: {label}"),
                label,
                "count",
                &[Series {
                    label: format!("{} samples", samples.len()),
                    points: &histogram_steps(samples, BINS),
                }],
                Scale::Linear,
                Scale::Linear,
            )?,
        });
    }
    Ok(figs)
}

/// A histogram as a step outline: `bins` equal bins between the sample extremes; non-finite
/// samples are left out.
fn histogram_steps(samples: &[f64], bins: usize) -> Vec<(f64, f64)> {
    let finite: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return Vec::new();
    }
    let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let mut hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi <= lo {
        // All samples equal: a bin width of zero would put them nowhere.
        hi = lo + 1e-12_f64.max(lo.abs() * 1e-9);
    }
    let w = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for v in finite {
        let k = (((v - lo) / w) as usize).min(bins - 1);
        counts[k] += 1;
    }
    let mut pts = vec![(lo, 0.0)];
    for (k, c) in counts.iter().enumerate() {
        let (a, b) = (lo + k as f64 * w, lo + (k + 1) as f64 * w);
        pts.push((a, *c as f64));
        pts.push((b, *c as f64));
    }
    pts.push((hi, 0.0));
    pts
}

#[cfg(test)]
mod tests {
    use super::histogram_steps;

    #[test]
    fn histogram_counts_every_finite_sample_once() {
        // Samples 0, 1, 1, 2 in two bins [0, 1) and [1, 2]: the maximum belongs to the last
        // bin, so the counts are 1 and 3 (counted by hand).
        let pts = histogram_steps(&[0.0, 1.0, 1.0, 2.0, f64::NAN], 2);
        assert_eq!(
            pts,
            vec![
                (0.0, 0.0),
                (0.0, 1.0),
                (1.0, 1.0),
                (1.0, 3.0),
                (2.0, 3.0),
                (2.0, 0.0)
            ]
        );
    }
}
