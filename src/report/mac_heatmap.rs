//! The MAC matrix as an SVG heat map (plotters, as the other report plots): test modes down,
//! FE modes across, each cell shaded from white (0) to dark blue (1) and labelled with its
//! value, the paired cells outlined.

use crate::error::Error;
use plotters::prelude::*;

const CELL: u32 = 54;
const MARGIN_LEFT: u32 = 150;
const MARGIN_TOP: u32 = 90;

/// What the heat map shows: `mac[i][j]` for test mode i and FE mode j.
pub struct Heatmap<'a> {
    pub title: &'a str,
    pub test_labels: &'a [String],
    pub fe_labels: &'a [String],
    pub mac: &'a [Vec<f64>],
    /// (test row, FE column) of each pair.
    pub paired: &'a [(usize, usize)],
}

fn plot_err(e: impl std::fmt::Display) -> Error {
    Error::Other(format!("MAC heat map: {e}"))
}

/// White at 0 to a dark blue at 1.
fn shade(v: f64) -> RGBColor {
    let t = v.clamp(0.0, 1.0);
    let mix = |from: f64, to: f64| (from + (to - from) * t).round() as u8;
    RGBColor(mix(255.0, 8.0), mix(255.0, 48.0), mix(255.0, 107.0))
}

pub fn render(h: &Heatmap) -> Result<String, Error> {
    let (rows, cols) = (h.test_labels.len() as u32, h.fe_labels.len() as u32);
    let size = (
        MARGIN_LEFT + cols * CELL + 20,
        MARGIN_TOP + rows * CELL + 20,
    );
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let font = ("sans-serif", 13).into_font();
        root.draw(&Text::new(
            h.title.to_string(),
            (10, 12),
            ("sans-serif", 16).into_font(),
        ))
        .map_err(plot_err)?;
        for (j, label) in h.fe_labels.iter().enumerate() {
            let x = (MARGIN_LEFT + j as u32 * CELL + 4) as i32;
            root.draw(&Text::new(
                label.clone(),
                (x, MARGIN_TOP as i32 - 22),
                font.clone(),
            ))
            .map_err(plot_err)?;
        }
        for (i, label) in h.test_labels.iter().enumerate() {
            let y = (MARGIN_TOP + i as u32 * CELL + CELL / 2 - 7) as i32;
            root.draw(&Text::new(label.clone(), (10, y), font.clone()))
                .map_err(plot_err)?;
            for j in 0..h.fe_labels.len() {
                draw_cell(&root, i, j, h)?;
            }
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

fn draw_cell(
    root: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    i: usize,
    j: usize,
    h: &Heatmap,
) -> Result<(), Error> {
    let v = h.mac[i][j];
    let x0 = (MARGIN_LEFT + j as u32 * CELL) as i32;
    let y0 = (MARGIN_TOP + i as u32 * CELL) as i32;
    let corners = [(x0, y0), (x0 + CELL as i32, y0 + CELL as i32)];
    root.draw(&Rectangle::new(corners, shade(v).filled()))
        .map_err(plot_err)?;
    let outline = if h.paired.contains(&(i, j)) {
        RED.stroke_width(3)
    } else {
        RGBColor(200, 200, 200).stroke_width(1)
    };
    root.draw(&Rectangle::new(corners, outline))
        .map_err(plot_err)?;
    let ink = if v > 0.5 { WHITE } else { BLACK };
    let text = ("sans-serif", 12).into_font().color(&ink);
    root.draw(&Text::new(
        format!("{v:.2}"),
        (x0 + 12, y0 + CELL as i32 / 2 - 6),
        text,
    ))
    .map_err(plot_err)?;
    Ok(())
}

/// The heat map of a correlation's MAC matrix under `title`, its pairs outlined.
pub fn of_correlation(
    c: &crate::pipeline::workflows::correlate::Correlation,
    title: &str,
) -> Result<String, Error> {
    let test_labels: Vec<String> = (c.test_modes.iter().enumerate())
        .map(|(i, m)| format!("test {} {:.2} Hz", i + 1, m.frequency_hz))
        .collect();
    let fe_labels: Vec<String> = c
        .fe_modes
        .iter()
        .map(|m| format!("FE {}", m.mode))
        .collect();
    let paired: Vec<(usize, usize)> = (c.pairs.iter())
        .map(|p| {
            let j = c
                .fe_modes
                .iter()
                .position(|m| m.mode == p.fe_mode)
                .unwrap_or(0);
            (p.test_mode - 1, j)
        })
        .collect();
    render(&Heatmap {
        title,
        test_labels: &test_labels,
        fe_labels: &fe_labels,
        mac: &c.mac_matrix,
        paired: &paired,
    })
}
