//! Small SVG line plots for reports (plotters, SVG backend, no system fonts: text goes out as
//! SVG `<text>` elements that the viewer renders). Generic: any module can hand over its
//! series; the signal reports use `loglog_svg` for PSDs and `lines_svg` for |H| and coherence.

use crate::error::Error;
use plotters::prelude::*;

/// One curve: label for the legend and (x, y) points.
pub struct Series<'a> {
    pub label: String,
    pub points: &'a [(f64, f64)],
}

/// Axis scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn plot_err(e: impl std::fmt::Display) -> Error {
    Error::Other(format!("plot: {e}"))
}

/// Range of the points usable on the given scale (positive only on a log scale), padded.
fn range(series: &[Series], pick: impl Fn(&(f64, f64)) -> f64, scale: Scale) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for s in series {
        for p in s.points {
            let v = pick(p);
            if v.is_finite() && (scale == Scale::Linear || v > 0.0) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if !lo.is_finite() {
        return if scale == Scale::Log {
            (1e-3, 1.0)
        } else {
            (0.0, 1.0)
        };
    }
    match scale {
        Scale::Log => {
            let (l, h) = (lo.log10().floor(), hi.log10().ceil());
            let h = if h <= l { l + 1.0 } else { h };
            (10f64.powf(l), 10f64.powf(h))
        }
        Scale::Linear => {
            if hi <= lo {
                (lo - 1.0, hi + 1.0)
            } else {
                let pad = 0.05 * (hi - lo);
                (lo - pad, hi + pad)
            }
        }
    }
}

/// A point to annotate on a plot: a circle and its label.
pub struct Marker {
    pub x: f64,
    pub y: f64,
    pub label: String,
}

/// A line plot with the chosen axis scales; returns the SVG document.
pub fn lines_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    x_scale: Scale,
    y_scale: Scale,
) -> Result<String, Error> {
    lines_markers_svg(title, x_label, y_label, series, &[], x_scale, y_scale)
}

/// A line plot with annotated points (e.g. the peaks of a sine response).
pub fn lines_markers_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: &[Marker],
    x_scale: Scale,
    y_scale: Scale,
) -> Result<String, Error> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (x0, x1) = range(series, |p| p.0, x_scale);
        let (y0, y1) = range(series, |p| p.1, y_scale);
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80);
        let keep = |p: &&(f64, f64)| {
            p.0.is_finite()
                && p.1.is_finite()
                && (x_scale == Scale::Linear || p.0 > 0.0)
                && (y_scale == Scale::Linear || p.1 > 0.0)
        };
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_label)
                    .y_desc(y_label)
                    .y_label_formatter(&|v| format!("{v:.3e}"))
                    .draw()
                    .map_err(plot_err)?;
                for (i, s) in series.iter().enumerate() {
                    let c = COLORS[i % COLORS.len()];
                    chart
                        .draw_series(LineSeries::new(
                            s.points.iter().filter(keep).copied(),
                            c.stroke_width(1),
                        ))
                        .map_err(plot_err)?
                        .label(s.label.clone())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                        });
                }
                chart
                    .draw_series(
                        markers
                            .iter()
                            .filter(|m| m.x.is_finite() && m.y.is_finite())
                            .map(|m| {
                                EmptyElement::at((m.x, m.y))
                                    + Circle::new((0, 0), 4, BLACK.stroke_width(1))
                                    + Text::new(
                                        m.label.clone(),
                                        (6, -12),
                                        ("sans-serif", 12).into_font(),
                                    )
                            }),
                    )
                    .map_err(plot_err)?;
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .position(SeriesLabelPosition::UpperRight)
                    .draw()
                    .map_err(plot_err)?;
            }};
        }
        match (x_scale, y_scale) {
            (Scale::Log, Scale::Log) => {
                draw!(
                    builder
                        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                        .map_err(plot_err)?
                )
            }
            (Scale::Log, Scale::Linear) => {
                draw!(
                    builder
                        .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                        .map_err(plot_err)?
                )
            }
            (Scale::Linear, Scale::Log) => {
                draw!(
                    builder
                        .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                        .map_err(plot_err)?
                )
            }
            (Scale::Linear, Scale::Linear) => draw!(
                builder
                    .build_cartesian_2d(x0..x1, y0..y1)
                    .map_err(plot_err)?
            ),
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// Log-log line plot (PSDs: put the Grms in each series label).
pub fn loglog_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<String, Error> {
    lines_svg(title, x_label, y_label, series, Scale::Log, Scale::Log)
}

/// A horizontal reference line (a gate's limit) with its legend label.
pub struct Limit {
    pub y: f64,
    pub label: String,
}

/// Outputs of a parameter sweep against one parameter: each series is a line through its
/// points (filled circles); the points in `failed` get a red cross over them; `limit` is drawn
/// as a grey line across the plot. Linear axes.
pub fn sweep_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    failed: &[(f64, f64)],
    limit: Option<&Limit>,
) -> Result<String, Error> {
    let limit_pts: Vec<(f64, f64)> = limit.map(|l| vec![(f64::NAN, l.y)]).unwrap_or_default();
    let mut all: Vec<Series> = series
        .iter()
        .map(|s| Series {
            label: String::new(),
            points: s.points,
        })
        .collect();
    all.push(Series {
        label: String::new(),
        points: &limit_pts,
    });
    let (x0, x1) = range(&all, |p| p.0, Scale::Linear);
    let (y0, y1) = range(&all, |p| p.1, Scale::Linear);
    // Room above the points for the legend in the upper right corner.
    let y1 = y1 + 0.35 * (y1 - y0);
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .y_label_formatter(&|v| format!("{v:.3e}"))
            .draw()
            .map_err(plot_err)?;
        if let Some(l) = limit {
            let grey = RGBColor(110, 110, 110);
            chart
                .draw_series(LineSeries::new(
                    [(x0, l.y), (x1, l.y)],
                    grey.stroke_width(2),
                ))
                .map_err(plot_err)?
                .label(l.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], grey.stroke_width(2))
                });
        }
        for (i, s) in series.iter().enumerate() {
            let c = COLORS[i % COLORS.len()];
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().filter(finite).copied(),
                    c.stroke_width(1),
                ))
                .map_err(plot_err)?;
            chart
                .draw_series(
                    s.points
                        .iter()
                        .filter(finite)
                        .map(|p| Circle::new(*p, 4, c.filled())),
                )
                .map_err(plot_err)?
                .label(s.label.clone())
                .legend(move |(x, y)| Circle::new((x + 9, y), 4, c.filled()));
        }
        if !failed.is_empty() {
            chart
                .draw_series(
                    failed
                        .iter()
                        .filter(finite)
                        .map(|p| Cross::new(*p, 7, RED.stroke_width(3))),
                )
                .map_err(plot_err)?
                .label("fails a gate")
                .legend(|(x, y)| Cross::new((x + 9, y), 5, RED.stroke_width(3)));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(plot_err)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}
