//! Effective mass by mode: where the structure's mass participates.

use super::{Files, csv};
use crate::error::Error;
use crate::report::ModalSummary;
use crate::report::document::Figure;
use crate::report::plot::{Options, Scale, Series, Style, chart_svg};

/// Below this a mode is a rigid-body mode, with no place on a log frequency axis.
const RIGID_BODY_HZ: f64 = 1e-3;

pub fn effective_mass(m: &ModalSummary, files: &mut Files) -> Result<Figure, Error> {
    let modes: Vec<&crate::modal::Mode> = m
        .result
        .modes
        .iter()
        .filter(|x| x.frequency_hz > RIGID_BODY_HZ)
        .collect();
    files.push((
        "curves/effective_mass.csv".into(),
        csv(
            "mode,frequency_hz,fraction_x,fraction_y,fraction_z,fraction_rx,fraction_ry,fraction_rz",
            modes.iter().map(|md| {
                let mut row = vec![md.index as f64, md.frequency_hz];
                row.extend(md.effective_mass_fraction.to_array());
                row
            }),
        ),
    ));
    let points: Vec<Vec<(f64, f64)>> = (0..3)
        .map(|d| {
            modes
                .iter()
                .map(|md| (md.frequency_hz, md.effective_mass_fraction.to_array()[d]))
                .collect()
        })
        .collect();
    let series: Vec<Series> = ["x", "y", "z"]
        .iter()
        .zip(&points)
        .map(|(l, p)| Series {
            label: format!("effective mass fraction {l}"),
            points: p,
        })
        .collect();
    Ok(Figure {
        stem: "effective_mass".into(),
        caption: "Effective-mass fraction of each mode against its frequency".into(),
        svg: chart_svg(
            "Effective mass by mode",
            "frequency [Hz]",
            "fraction of total mass",
            &series,
            &[],
            Options {
                style: Style::Stems,
                ..Options::lines(Scale::Log, Scale::Linear)
            },
        )?,
    })
}
