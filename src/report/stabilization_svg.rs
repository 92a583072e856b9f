//! The stabilization diagram as SVG: every physical pole at its frequency (x) and model order
//! (y), its marker telling how far it is stable against the previous order, the selected
//! modes as dashed verticals, and the summed FRF magnitude (log, scaled to the order axis)
//! behind them. Raw SVG text, deterministic, like [`super::svg_plot`].

use crate::signal::ema::{DiagramPole, Stability};
use std::fmt::Write as _;

const W: f64 = 900.0;
const H: f64 = 560.0;
const L: f64 = 70.0;
const R: f64 = 190.0;
const T: f64 = 40.0;
const B: f64 = 55.0;

/// What the diagram shows.
pub struct StabilizationPlot<'a> {
    pub title: &'a str,
    pub band_hz: (f64, f64),
    pub order_max: usize,
    pub poles: &'a [DiagramPole],
    /// (f, Σ|H|) of the band.
    pub frf_sum: &'a [(f64, f64)],
    pub selected_hz: &'a [f64],
}

fn marker(s: &mut String, x: f64, y: f64, st: Stability) {
    let _ = match st {
        Stability::Vector => writeln!(
            s,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="3.2" fill="#2ca02c"/>"##
        ),
        Stability::Damping => writeln!(
            s,
            r##"<rect x="{:.1}" y="{:.1}" width="5" height="5" fill="none" stroke="#1f77b4"/>"##,
            x - 2.5,
            y - 2.5
        ),
        Stability::Frequency => writeln!(
            s,
            r##"<path d="M{:.1},{y:.1}h6M{x:.1},{:.1}v6" stroke="#ff7f0e"/>"##,
            x - 3.0,
            y - 3.0
        ),
        Stability::New => writeln!(
            s,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="1.3" fill="#999"/>"##
        ),
    };
}

pub fn render(p: &StabilizationPlot) -> String {
    let (f0, f1) = if p.band_hz.1 > p.band_hz.0 {
        p.band_hz
    } else {
        (p.band_hz.0, p.band_hz.0 + 1.0)
    };
    let ymax = p.order_max.max(2) as f64 + 2.0;
    let px = |f: f64| L + (f - f0) / (f1 - f0) * (W - L - R);
    let py = |o: f64| H - B - o / ymax * (H - T - B);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{W}" height="{H}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="24" text-anchor="middle" font-size="15">{}</text>"#,
        (L + W - R) / 2.0,
        p.title.replace('&', "&amp;").replace('<', "&lt;")
    );
    frame(&mut s, f0, f1, ymax, &px, &py);
    frf_line(&mut s, p.frf_sum, ymax, &px, &py);
    for &f in p.selected_hz {
        let x = px(f);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{T}" x2="{x:.1}" y2="{:.1}" stroke="#d62728" stroke-dasharray="4,3"/>"##,
            H - B
        );
    }
    for pole in p.poles {
        marker(
            &mut s,
            px(pole.frequency_hz),
            py(pole.order as f64),
            pole.stability,
        );
    }
    legend(&mut s);
    s.push_str("</svg>\n");
    s
}

fn frame(
    s: &mut String,
    f0: f64,
    f1: f64,
    ymax: f64,
    px: &dyn Fn(f64) -> f64,
    py: &dyn Fn(f64) -> f64,
) {
    let _ = writeln!(
        s,
        r##"<rect x="{L}" y="{T}" width="{}" height="{}" fill="none" stroke="#000"/>"##,
        W - L - R,
        H - T - B
    );
    for k in 0..=5 {
        let f = f0 + (f1 - f0) * k as f64 / 5.0;
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{:.1}</text>"#,
            px(f),
            H - B + 16.0,
            f
        );
        let o = ymax * k as f64 / 5.0;
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end">{:.0}</text>"#,
            L - 6.0,
            py(o) + 4.0,
            o
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">frequency [Hz]</text>"#,
        (L + W - R) / 2.0,
        H - 14.0
    );
    let _ = writeln!(
        s,
        r#"<text x="18" y="{0:.1}" text-anchor="middle" transform="rotate(-90 18 {0:.1})">model order</text>"#,
        (T + H - B) / 2.0
    );
}

/// log10 Σ|H| scaled so that its range spans the order axis.
fn frf_line(
    s: &mut String,
    pts: &[(f64, f64)],
    ymax: f64,
    px: &dyn Fn(f64) -> f64,
    py: &dyn Fn(f64) -> f64,
) {
    let logs: Vec<(f64, f64)> = pts
        .iter()
        .filter(|(f, v)| f.is_finite() && *v > 0.0 && v.is_finite())
        .map(|(f, v)| (*f, v.log10()))
        .collect();
    let lo = logs.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let hi = logs.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    if logs.is_empty() || hi <= lo {
        return;
    }
    let mut d = String::new();
    for (f, l) in &logs {
        let _ = write!(d, "{:.1},{:.1} ", px(*f), py((l - lo) / (hi - lo) * ymax));
    }
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#bbb" stroke-width="1"/>"##,
        d.trim_end()
    );
}

fn legend(s: &mut String) {
    let items = [
        (Stability::Vector, "stable f, ζ and vector"),
        (Stability::Damping, "stable f and ζ"),
        (Stability::Frequency, "stable f"),
        (Stability::New, "new / unstable"),
    ];
    for (i, (st, label)) in items.iter().enumerate() {
        let y = T + 12.0 + 18.0 * i as f64;
        marker(s, W - R + 16.0, y, *st);
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}">{label}</text>"#,
            W - R + 28.0,
            y + 4.0
        );
    }
    let y = T + 12.0 + 18.0 * 4.0;
    let _ = writeln!(
        s,
        r##"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#d62728" stroke-dasharray="4,3"/><text x="{:.1}" y="{:.1}">selected mode</text>"##,
        W - R + 8.0,
        W - R + 24.0,
        W - R + 28.0,
        y + 4.0
    );
    let y = y + 18.0;
    let _ = writeln!(
        s,
        r##"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#bbb"/><text x="{:.1}" y="{:.1}">Σ|H| (log, scaled)</text>"##,
        W - R + 8.0,
        W - R + 24.0,
        W - R + 28.0,
        y + 4.0
    );
}
