//! A small, dependency-free SVG line plot (log or linear axes), for the CSV curves of the
//! response and signal reports. Raw SVG rather than plotters: plotters needs a font backend to
//! lay out text, and without one (default-features off, so that a fresh machine needs no
//! system fonts) it cannot measure labels; SVG `<text>` needs no measuring. The output is
//! deterministic text.

use std::fmt::Write as _;

/// One plotted line.
pub struct Series<'a> {
    pub name: &'a str,
    pub x: &'a [f64],
    pub y: &'a [f64],
    /// Dashed (e.g. an input profile).
    pub dashed: bool,
}

/// Plot settings.
pub struct Plot<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub log_x: bool,
    pub log_y: bool,
}

const W: f64 = 800.0;
const H: f64 = 500.0;
const L: f64 = 80.0;
const R: f64 = 200.0;
const T: f64 = 40.0;
const B: f64 = 60.0;
const COLORS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The plotted window in axis units (log10 of the value on a log axis) and its mapping to
/// pixels.
struct Frame {
    log_x: bool,
    log_y: bool,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl Frame {
    /// The window that holds every plottable point of `series`.
    fn fit(p: &Plot, series: &[Series]) -> Self {
        let mut f = Frame {
            log_x: p.log_x,
            log_y: p.log_y,
            x0: f64::MAX,
            x1: f64::MIN,
            y0: f64::MAX,
            y1: f64::MIN,
        };
        for s in series {
            for (&x, &y) in s.x.iter().zip(s.y) {
                if f.plottable(x, y) {
                    f.x0 = f.x0.min(f.tx(x));
                    f.x1 = f.x1.max(f.tx(x));
                    f.y0 = f.y0.min(f.ty(y));
                    f.y1 = f.y1.max(f.ty(y));
                }
            }
        }
        f.settle();
        f
    }

    /// A window for no points, whole decades on a log y axis, and never an empty span.
    fn settle(&mut self) {
        if self.x0 > self.x1 {
            (self.x0, self.x1, self.y0, self.y1) = (0.0, 1.0, 0.0, 1.0);
        }
        if self.log_y {
            // Six decades below the top are enough to read a PSD; deeper tails are clipped.
            self.y1 = self.y1.ceil().clamp(-299.0, 300.0);
            self.y0 = self.y0.floor().max(self.y1 - 6.0);
        }
        if self.log_x {
            // A subnormal or a 1e308 must not stretch the axis over hundreds of decades.
            self.x1 = self.x1.clamp(-299.0, 300.0);
            self.x0 = self.x0.clamp(self.x1 - 10.0, self.x1);
        }
        if self.x1 - self.x0 <= 0.0 {
            self.x1 = self.x0 + 1.0;
        }
        if self.y1 - self.y0 <= 0.0 {
            self.y1 = self.y0 + 1.0;
        }
    }

    fn tx(&self, v: f64) -> f64 {
        if self.log_x { v.log10() } else { v }
    }

    fn ty(&self, v: f64) -> f64 {
        if self.log_y { v.log10() } else { v }
    }

    /// Finite, and positive on a log axis.
    fn plottable(&self, x: f64, y: f64) -> bool {
        x.is_finite() && y.is_finite() && (!self.log_x || x > 0.0) && (!self.log_y || y > 0.0)
    }

    fn px(&self, v: f64) -> f64 {
        L + (self.tx(v) - self.x0) / (self.x1 - self.x0) * (W - L - R)
    }

    fn py(&self, v: f64) -> f64 {
        H - B - (self.ty(v) - self.y0) / (self.y1 - self.y0) * (H - T - B)
    }
}

/// Tick positions in axis units: decades on log axes, 5 divisions on linear ones.
fn ticks(a: f64, b: f64, log: bool) -> Vec<f64> {
    if log {
        (a.floor() as i32..=b.ceil() as i32)
            .map(|e| e as f64)
            .filter(|&e| e >= a - 1e-9 && e <= b + 1e-9)
            .collect()
    } else {
        (0..=5).map(|k| a + (b - a) * k as f64 / 5.0).collect()
    }
}

/// Renders the series as an SVG document. Non-finite points, and non-positive ones on a log
/// axis, are skipped.
pub fn render(p: &Plot, series: &[Series]) -> String {
    let f = Frame::fit(p, series);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{W}" height="{H}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}</text>"#,
        (L + W - R) / 2.0,
        esc(p.title)
    );
    grid(&mut s, &f);
    axes(&mut s, p);
    for (i, se) in series.iter().enumerate() {
        line(&mut s, &f, i, se);
    }
    s.push_str("</svg>\n");
    s
}

/// Grid lines with their tick labels.
fn grid(s: &mut String, f: &Frame) {
    for t in ticks(f.x0, f.x1, f.log_x) {
        let v = if f.log_x { 10f64.powf(t) } else { t };
        let x = f.px(v);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{T}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            H - B,
            H - B + 16.0,
            fmt_tick(v)
        );
    }
    for t in ticks(f.y0, f.y1, f.log_y) {
        let v = if f.log_y { 10f64.powf(t) } else { t };
        let y = f.py(v);
        let _ = writeln!(
            s,
            r##"<line x1="{L}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            W - R,
            L - 6.0,
            y + 4.0,
            fmt_tick(v)
        );
    }
}

/// The plot-area border and the axis labels.
fn axes(s: &mut String, p: &Plot) {
    let _ = writeln!(
        s,
        r##"<rect x="{L}" y="{T}" width="{}" height="{}" fill="none" stroke="#000"/>"##,
        W - L - R,
        H - T - B
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        (L + W - R) / 2.0,
        H - 16.0,
        esc(p.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">{}</text>"#,
        (T + H - B) / 2.0,
        (T + H - B) / 2.0,
        esc(p.y_label)
    );
}

/// Series `i` as a polyline clipped to the plot area, and its legend entry.
fn line(s: &mut String, f: &Frame, i: usize, se: &Series) {
    let c = COLORS[i % COLORS.len()];
    let mut pts = String::new();
    for (&x, &y) in se.x.iter().zip(se.y) {
        if f.plottable(x, y) {
            let yy = f.py(y).clamp(T, H - B);
            let _ = write!(pts, "{:.1},{:.1} ", f.px(x), yy);
        }
    }
    let dash = if se.dashed {
        r#" stroke-dasharray="6,4""#
    } else {
        ""
    };
    let _ = writeln!(
        s,
        r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.5"{dash}/>"#,
        pts.trim_end()
    );
    let ly = T + 10.0 + 18.0 * i as f64;
    let _ = writeln!(
        s,
        r#"<line x1="{:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{c}" stroke-width="2"{dash}/><text x="{:.1}" y="{:.1}">{}</text>"#,
        W - R + 10.0,
        W - R + 35.0,
        W - R + 40.0,
        ly + 4.0,
        esc(se.name)
    );
}

fn fmt_tick(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.0e}")
    } else if a >= 100.0 || a == 0.0 {
        format!("{v:.0}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}
