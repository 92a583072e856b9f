//! Small SVG plots for reports (plotters, SVG backend, no system fonts: text goes out as SVG
//! `<text>` elements that the viewer renders). Generic: any module can hand over its series;
//! the signal reports use `loglog_svg` for PSDs and `chart_svg` for |H| and coherence.
//!
//! Readability rules every plot follows: tick labels are plain decimals (`0.5`, `20`,
//! `0.001`), scientific only beyond 1e6 or below 1e-4; the legend sits below the plot area,
//! never over a curve; every series has its own colour; the axes span the data (a log axis
//! at most [`MAX_DECADES`] decades, so a subnormal or a 1e308 cannot stretch it to nothing); a curve of more points than the plot has pixels is decimated
//! to the minimum and maximum of each bucket, which keeps its envelope.

use crate::error::Error;
use plotters::coord::ranged1d::ValueFormatter;
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

/// How the points of a series are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A polyline through the points.
    Lines,
    /// A vertical stem from 0 to each point, with a dot on top (discrete values such as the
    /// effective mass of each mode); needs a linear y axis.
    Stems,
}

/// The axes and the drawing style of a chart.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    pub x_scale: Scale,
    pub y_scale: Scale,
    /// A fixed y range (e.g. [0, 1] for a coherence); fitted to the data when `None`.
    pub y_range: Option<(f64, f64)>,
    pub style: Style,
}

impl Options {
    pub fn lines(x_scale: Scale, y_scale: Scale) -> Options {
        Options {
            x_scale,
            y_scale,
            y_range: None,
            style: Style::Lines,
        }
    }
}

/// The widest span of a log axis, in decades: deeper tails are clipped at its bottom.
pub const MAX_DECADES: f64 = 10.0;
/// Log axes stay within 1e±300, whatever the data, so that 10^edge is a normal number.
const LOG_EDGE: f64 = 300.0;
/// Points per series beyond which a curve is decimated (about two per horizontal pixel).
const MAX_POINTS: usize = 1600;
const WIDTH: u32 = 900;
const PLOT_HEIGHT: u32 = 520;
const LEGEND_COLUMNS: usize = 2;
const LEGEND_ROW: u32 = 20;

/// Ten distinct colours (the Tableau 10 palette); more series get evenly spaced hues.
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn color(i: usize, n: usize) -> RGBColor {
    if n <= COLORS.len() {
        return COLORS[i];
    }
    let (r, g, b) = HSLColor(i as f64 / n as f64, 0.75, 0.42).rgb();
    RGBColor(r, g, b)
}

fn plot_err(e: impl std::fmt::Display) -> Error {
    Error::Other(format!("plot: {e}"))
}

/// A tick label as a plain decimal with at most four significant digits, trailing zeros
/// dropped; scientific (`1e-6`, `2.5e7`) only outside [1e-4, 1e6).
pub fn decimal(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !v.is_finite() {
        return if v.is_finite() {
            "0".into()
        } else {
            String::new()
        };
    }
    if !(1e-4..1e6).contains(&a) {
        let s = format!("{v:.3e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        return format!("{m}e{e}");
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 8) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Range of the points usable on the given scale (positive only on a log scale). The x axis
/// spans the data exactly; the y axis gets a margin (5% of the span on a linear scale, a
/// factor 1.5 on a log one) so that no curve runs along the border. A log axis spans at
/// most [`MAX_DECADES`] below its top and stays within 1e±300.
fn range(
    series: &[Series],
    pick: impl Fn(&(f64, f64)) -> f64,
    scale: Scale,
    margin: bool,
) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for p in series.iter().flat_map(|s| s.points) {
        let v = pick(p);
        if v.is_finite() && (scale == Scale::Linear || v > 0.0) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if !lo.is_finite() {
        return match scale {
            Scale::Log => (1e-3, 1.0),
            Scale::Linear => (0.0, 1.0),
        };
    }
    match scale {
        Scale::Log => {
            let pad = if margin { 1.5f64.log10() } else { 0.0 };
            let h = (hi.log10() + pad).clamp(-LOG_EDGE + 1.0, LOG_EDGE);
            let l = (lo.log10() - pad).clamp(h - MAX_DECADES, h);
            let l = if h - l < 0.1 { h - 1.0 } else { l };
            (10f64.powf(l), 10f64.powf(h))
        }
        Scale::Linear => {
            let (lo, hi) = (lo.max(-1e300), hi.min(1e300));
            if hi <= lo {
                let pad = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
                (lo - pad, hi + pad)
            } else {
                let pad = if margin { 0.05 * (hi - lo) } else { 0.0 };
                (lo - pad, hi + pad)
            }
        }
    }
}

/// At most [`MAX_POINTS`] of the points: the lowest and highest of each run of consecutive
/// points, in their order, so peaks and notches survive.
fn decimate(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if points.len() <= MAX_POINTS {
        return points.to_vec();
    }
    let chunk = points.len().div_ceil(MAX_POINTS / 2);
    let mut out = Vec::with_capacity(MAX_POINTS + 2);
    for c in points.chunks(chunk) {
        let by_y = |a: &&(f64, f64), b: &&(f64, f64)| a.1.total_cmp(&b.1);
        let (lo, hi) = (c.iter().min_by(by_y), c.iter().max_by(by_y));
        let (Some(&lo), Some(&hi)) = (lo, hi) else {
            continue;
        };
        if lo.0 <= hi.0 {
            out.extend([lo, hi]);
        } else {
            out.extend([hi, lo]);
        }
    }
    out
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
    let opts = Options::lines(x_scale, y_scale);
    chart_svg(title, x_label, y_label, series, &[], opts)
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
    let opts = Options::lines(x_scale, y_scale);
    chart_svg(title, x_label, y_label, series, markers, opts)
}

/// The labels and the series of a chart, as the drawing code needs them.
struct Content<'a> {
    x_label: &'a str,
    y_label: &'a str,
    series: &'a [Series<'a>],
    markers: &'a [Marker],
    opts: Options,
}

/// A chart of `series` (lines or stems) with annotated points and the legend below it.
pub fn chart_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: &[Marker],
    opts: Options,
) -> Result<String, Error> {
    let rows = series.len().div_ceil(LEGEND_COLUMNS) as u32;
    let legend_h = if rows == 0 { 0 } else { 12 + rows * LEGEND_ROW };
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (WIDTH, PLOT_HEIGHT + legend_h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (plot_area, legend_area) = root.split_vertically(PLOT_HEIGHT);
        let c = Content {
            x_label,
            y_label,
            series,
            markers,
            opts,
        };
        draw_chart(&plot_area, title, &c)?;
        draw_legend(&legend_area, series)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

/// The legend: a short line in the series' colour and its label, in columns.
fn draw_legend(area: &Area, series: &[Series]) -> Result<(), Error> {
    let col_w = (WIDTH as i32 - 100) / LEGEND_COLUMNS as i32;
    for (i, s) in series.iter().enumerate() {
        let c = color(i, series.len());
        let x = 80 + (i % LEGEND_COLUMNS) as i32 * col_w;
        let y = 10 + (i / LEGEND_COLUMNS) as i32 * LEGEND_ROW as i32;
        area.draw(&PathElement::new(
            vec![(x, y), (x + 24, y)],
            c.stroke_width(3),
        ))
        .map_err(plot_err)?;
        area.draw(&Text::new(
            s.label.clone(),
            (x + 30, y - 6),
            ("sans-serif", 13).into_font(),
        ))
        .map_err(plot_err)?;
    }
    Ok(())
}

fn draw_chart(area: &Area, title: &str, c: &Content) -> Result<(), Error> {
    let (x0, x1) = range(c.series, |p| p.0, c.opts.x_scale, false);
    let (y0, y1) = match c.opts.y_range {
        Some(r) => r,
        None if c.opts.style == Style::Stems => {
            let (_, hi) = range(c.series, |p| p.1, Scale::Linear, true);
            (0.0, hi.max(f64::MIN_POSITIVE))
        }
        None => range(c.series, |p| p.1, c.opts.y_scale, true),
    };
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80);
    match (c.opts.x_scale, c.opts.y_scale) {
        (Scale::Log, Scale::Log) => {
            let chart = builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale());
            draw_series(chart.map_err(plot_err)?, c, (y0, y1))
        }
        (Scale::Log, Scale::Linear) => {
            let chart = builder.build_cartesian_2d((x0..x1).log_scale(), y0..y1);
            draw_series(chart.map_err(plot_err)?, c, (y0, y1))
        }
        (Scale::Linear, Scale::Log) => {
            let chart = builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale());
            draw_series(chart.map_err(plot_err)?, c, (y0, y1))
        }
        (Scale::Linear, Scale::Linear) => {
            let chart = builder.build_cartesian_2d(x0..x1, y0..y1);
            draw_series(chart.map_err(plot_err)?, c, (y0, y1))
        }
    }
}

/// The mesh, the series and the markers on a built chart of any axis kinds. Points outside
/// the y range are pinned to its edge, so a clipped tail runs along the border.
fn draw_series<'a, X, Y>(
    mut chart: ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
    c: &Content,
    (y0, y1): (f64, f64),
) -> Result<(), Error>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let fmt = |v: &f64| decimal(*v);
    chart
        .configure_mesh()
        .x_desc(c.x_label)
        .y_desc(c.y_label)
        .x_label_formatter(&fmt)
        .y_label_formatter(&fmt)
        .draw()
        .map_err(plot_err)?;
    let keep = |p: &(f64, f64)| {
        p.0.is_finite()
            && p.1.is_finite()
            && (c.opts.x_scale == Scale::Linear || p.0 > 0.0)
            && (c.opts.y_scale == Scale::Linear || p.1 > 0.0)
    };
    let n = c.series.len();
    for (i, s) in c.series.iter().enumerate() {
        let col = color(i, n);
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(keep).collect();
        let pts: Vec<(f64, f64)> = decimate(&pts)
            .into_iter()
            .map(|(x, y)| (x, y.clamp(y0, y1)))
            .collect();
        match c.opts.style {
            Style::Lines => {
                chart
                    .draw_series(LineSeries::new(pts, col.stroke_width(1)))
                    .map_err(plot_err)?;
            }
            Style::Stems => {
                let base = y0.max(0.0);
                chart
                    .draw_series(pts.iter().map(|&(x, y)| {
                        PathElement::new(vec![(x, base), (x, y)], col.stroke_width(2))
                    }))
                    .map_err(plot_err)?;
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, col.filled())))
                    .map_err(plot_err)?;
            }
        }
    }
    let markers = c
        .markers
        .iter()
        .filter(|m| m.x.is_finite() && m.y.is_finite());
    chart
        .draw_series(markers.map(|m| {
            EmptyElement::at((m.x, m.y))
                + Circle::new((0, 0), 4, BLACK.stroke_width(1))
                + Text::new(m.label.clone(), (6, -12), ("sans-serif", 12).into_font())
        }))
        .map_err(plot_err)?;
    Ok(())
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
    let (x0, x1) = range(&all, |p| p.0, Scale::Linear, false);
    let (y0, y1) = range(&all, |p| p.1, Scale::Linear, true);
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
            .x_label_formatter(&|v| decimal(*v))
            .y_label_formatter(&|v| decimal(*v))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Written by hand: four significant digits at most, no exponent in [1e-4, 1e6).
    #[test]
    fn ticks_are_plain_decimals() {
        assert_eq!(decimal(1.0), "1");
        assert_eq!(decimal(0.5), "0.5");
        assert_eq!(decimal(0.001), "0.001");
        assert_eq!(decimal(20.0), "20");
        assert_eq!(decimal(1234.6), "1235");
        assert_eq!(decimal(0.0), "0");
        assert_eq!(decimal(1e-6), "1e-6");
        assert_eq!(decimal(2.5e7), "2.5e7");
    }

    /// A subnormal and a 1e308 in one series: the log range stays within MAX_DECADES and
    /// finite, and the chart is drawn (no hang, no NaN in the SVG).
    #[test]
    fn log_axes_survive_subnormal_and_huge_values() {
        let pts = [(1.0, 5e-324), (10.0, 1e308), (100.0, 1.0)];
        let s = [Series {
            label: "wild".into(),
            points: &pts,
        }];
        let (lo, hi) = range(&s, |p| p.1, Scale::Log, true);
        assert!(lo > 0.0 && hi.is_finite() && (hi / lo).log10() <= MAX_DECADES + 1e-9);
        let svg = loglog_svg("t", "x", "y", &s).unwrap();
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    /// 10 000 points become at most MAX_POINTS, and the extremes survive.
    #[test]
    fn decimation_keeps_the_envelope() {
        let pts: Vec<(f64, f64)> = (0..10_000)
            .map(|i| (i as f64, if i == 4321 { 9.0 } else { (i % 7) as f64 }))
            .collect();
        let d = decimate(&pts);
        assert!(d.len() <= MAX_POINTS);
        assert!(d.contains(&(4321.0, 9.0)));
        assert!(d.iter().any(|p| p.1 == 0.0));
    }

    /// A coherence near 1 on a fixed [0, 1.05] axis: decimal ticks, never `1.000e0`; the
    /// legend lies below the plot area (its text y beyond PLOT_HEIGHT).
    #[test]
    fn fixed_range_chart_has_decimal_ticks_and_the_legend_below() {
        let pts: Vec<(f64, f64)> = (1..500).map(|i| (i as f64, 0.999)).collect();
        let s = [Series {
            label: "coherence".into(),
            points: &pts,
        }];
        let opts = Options {
            y_range: Some((0.0, 1.05)),
            ..Options::lines(Scale::Log, Scale::Linear)
        };
        // plotters puts each text on a line of its own.
        let svg = chart_svg("c", "f", "γ²", &s, &[], opts)
            .unwrap()
            .replace('\n', "");
        assert!(!svg.contains("e0<") && svg.contains(">0.5<"), "{svg:.3000}");
        let legend = svg.split(">coherence<").next().unwrap();
        let y: f64 = legend
            .rsplit(" y=\"")
            .next()
            .and_then(|t| t.split('"').next())
            .unwrap()
            .parse()
            .unwrap();
        assert!(y > PLOT_HEIGHT as f64, "legend text at y = {y}");
    }
}
