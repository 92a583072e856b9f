//! The nominal separation over time: position, speed and angular rate of every satellite.

use super::{Files, csv};
use crate::error::Error;
use crate::report::document::Figure;
use crate::report::plot::{Scale, Series, lines_svg};
use crate::separation::History;

/// Indices into a satellite's recorded state: axial position, speed, angular rate.
const Z: usize = 2;
const SPEED: usize = 6;
const RATE: usize = 10;

/// One curve per satellite of state component `k` against time.
fn per_satellite(h: &History, k: usize) -> Vec<Vec<(f64, f64)>> {
    h.satellites
        .iter()
        .map(|states| {
            h.times_s
                .iter()
                .zip(states)
                .map(|(t, s)| (*t, s[k]))
                .collect()
        })
        .collect()
}

fn push_csv(h: &History, files: &mut Files) {
    let mut header = String::from("time_s");
    for i in 1..=h.satellites.len() {
        header.push_str(&format!(",sat{i}_z_m,sat{i}_speed_m_s,sat{i}_rate_deg_s"));
    }
    let rows = h.times_s.iter().enumerate().map(|(k, t)| {
        let mut row = vec![*t];
        for states in &h.satellites {
            // A satellite recorded for fewer steps leaves its columns empty (NaN).
            let s = states.get(k).copied().unwrap_or([f64::NAN; 11]);
            row.extend([s[Z], s[SPEED], s[RATE]]);
        }
        row
    });
    files.push(("curves/separation_history.csv".into(), csv(&header, rows)));
}

fn figure(
    stem: &str,
    caption: &str,
    title: &str,
    y_label: &str,
    curves: &[Vec<(f64, f64)>],
) -> Result<Figure, Error> {
    let series: Vec<Series> = curves
        .iter()
        .enumerate()
        .map(|(i, p)| Series {
            label: format!("satellite {}", i + 1),
            points: p,
        })
        .collect();
    Ok(Figure {
        stem: stem.into(),
        caption: caption.into(),
        svg: lines_svg(
            title,
            "time [s]",
            y_label,
            &series,
            Scale::Linear,
            Scale::Linear,
        )?,
    })
}

pub fn histories(h: &History, files: &mut Files) -> Result<Vec<Figure>, Error> {
    push_csv(h, files);
    Ok(vec![
        figure(
            "separation_position",
            "Axial position of each satellite during the release (bar root at 0)",
            "Separation: trajectories",
            "z [m]",
            &per_satellite(h, Z),
        )?,
        figure(
            "separation_speed",
            "Speed of each satellite; dips are contacts with the guide bars",
            "Separation: speed",
            "speed [m/s]",
            &per_satellite(h, SPEED),
        )?,
        figure(
            "separation_rate",
            "Angular rate of each satellite",
            "Separation: angular rate",
            "rate [deg/s]",
            &per_satellite(h, RATE),
        )?,
    ])
}
