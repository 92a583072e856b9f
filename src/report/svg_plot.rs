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

/// Renders the series as an SVG document. Non-finite points, and non-positive ones on a log
/// axis, are skipped.
pub fn render(p: &Plot, series: &[Series]) -> String {
    let tx = |v: f64| if p.log_x { v.log10() } else { v };
    let ty = |v: f64| if p.log_y { v.log10() } else { v };
    let ok = |x: f64, y: f64| {
        x.is_finite() && y.is_finite() && (!p.log_x || x > 0.0) && (!p.log_y || y > 0.0)
    };
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for s in series {
        for (&x, &y) in s.x.iter().zip(s.y) {
            if ok(x, y) {
                x0 = x0.min(tx(x));
                x1 = x1.max(tx(x));
                y0 = y0.min(ty(y));
                y1 = y1.max(ty(y));
            }
        }
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if p.log_y {
        // Six decades below the top are enough to read a PSD; deeper tails are clipped.
        y1 = y1.ceil();
        y0 = y0.floor().max(y1 - 6.0);
    }
    if x1 - x0 <= 0.0 {
        x1 = x0 + 1.0;
    }
    if y1 - y0 <= 0.0 {
        y1 = y0 + 1.0;
    }
    let px = |v: f64| L + (tx(v) - x0) / (x1 - x0) * (W - L - R);
    let py = |v: f64| H - B - (ty(v) - y0) / (y1 - y0) * (H - T - B);
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
    // Ticks: decades on log axes, 5 divisions on linear ones.
    let ticks = |a: f64, b: f64, log: bool| -> Vec<f64> {
        if log {
            (a.floor() as i32..=b.ceil() as i32)
                .map(|e| e as f64)
                .filter(|&e| e >= a - 1e-9 && e <= b + 1e-9)
                .collect()
        } else {
            (0..=5).map(|k| a + (b - a) * k as f64 / 5.0).collect()
        }
    };
    for t in ticks(x0, x1, p.log_x) {
        let v = if p.log_x { 10f64.powf(t) } else { t };
        let x = px(v);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{T}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            H - B,
            H - B + 16.0,
            fmt_tick(v)
        );
    }
    for t in ticks(y0, y1, p.log_y) {
        let v = if p.log_y { 10f64.powf(t) } else { t };
        let y = py(v);
        let _ = writeln!(
            s,
            r##"<line x1="{L}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            W - R,
            L - 6.0,
            y + 4.0,
            fmt_tick(v)
        );
    }
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
    for (i, se) in series.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let mut pts = String::new();
        for (&x, &y) in se.x.iter().zip(se.y) {
            if ok(x, y) {
                let yy = py(y).clamp(T, H - B);
                let _ = write!(pts, "{:.1},{:.1} ", px(x), yy);
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
    s.push_str("</svg>\n");
    s
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
