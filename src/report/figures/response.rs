//! Sine and random response curves per excitation axis, the highest peaks annotated.

use super::Files;
use crate::error::Error;
use crate::report::document::Figure;
use crate::report::plot::{Marker, Scale, Series, lines_markers_svg};
use crate::response::random::RandomAxis;
use crate::response::sine::SineAxis;
use crate::response::{Curves, SceneResponse};

/// Peaks annotated per plot: more labels would overprint one another.
const ANNOTATED_PEAKS: usize = 3;

/// Which analysis a curve set comes from, and how its plot is titled.
#[derive(Clone, Copy)]
enum Kind {
    Sine,
    Random,
}

impl Kind {
    fn stem(self) -> &'static str {
        match self {
            Kind::Sine => "sine",
            Kind::Random => "random",
        }
    }

    /// The CSV column name of the input level.
    fn input_name(self) -> &'static str {
        match self {
            Kind::Sine => "input_g",
            Kind::Random => "input_g2_hz",
        }
    }

    /// Title, y-axis label and caption of the plot along `axis`.
    fn labels(self, axis: &str) -> (String, &'static str, String) {
        match self {
            Kind::Sine => (
                format!("Sine response, {axis} axis"),
                "acceleration [g]",
                format!(
                    "Sine sweep along {axis}: absolute acceleration of the response points against the input level"
                ),
            ),
            Kind::Random => (
                format!("Random response PSD, {axis} axis"),
                "PSD [g²/Hz]",
                format!("Random vibration along {axis}: response PSDs with the input profile"),
            ),
        }
    }
}

/// Every sine axis, then every random axis.
pub fn figures(resp: &SceneResponse, files: &mut Files) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    for a in &resp.sine {
        figs.push(axis_figure(
            Kind::Sine,
            &a.axis,
            &a.curves,
            sine_peaks(a),
            files,
        )?);
    }
    for a in &resp.random {
        figs.push(axis_figure(
            Kind::Random,
            &a.axis,
            &a.curves,
            random_peaks(a),
            files,
        )?);
    }
    Ok(figs)
}

fn sine_peaks(a: &SineAxis) -> Vec<Marker> {
    a.peaks
        .iter()
        .map(|p| Marker {
            x: p.frequency_hz,
            y: p.acceleration_g,
            label: format!(
                "{} {:.2} g @ {:.1} Hz",
                p.name, p.acceleration_g, p.frequency_hz
            ),
        })
        .collect()
}

fn random_peaks(a: &RandomAxis) -> Vec<Marker> {
    a.responses
        .iter()
        .map(|r| Marker {
            x: r.peak_psd_hz,
            y: r.peak_psd_g2_hz,
            label: format!("{} {:.2} Grms", r.name, r.grms),
        })
        .collect()
}

/// The highest peaks at distinct frequencies (more than about 10% apart): labels of points
/// that peak together would overprint.
fn distinct_highest(mut markers: Vec<Marker>) -> Vec<Marker> {
    markers.sort_by(|a, b| b.y.total_cmp(&a.y));
    let mut kept: Vec<Marker> = Vec::new();
    for m in markers {
        if kept.len() < ANNOTATED_PEAKS && kept.iter().all(|k| (k.x / m.x).ln().abs() > 0.1) {
            kept.push(m);
        }
    }
    kept
}

/// The three CSV files of one axis: response points, interface loads, bar loads.
fn push_curves(kind: Kind, axis: &str, c: &Curves, files: &mut Files) {
    let input = kind.input_name();
    let stem = format!("curves/{}_{axis}", kind.stem());
    files.push((format!("{stem}_points.csv"), c.to_csv(input).into_bytes()));
    files.push((
        format!("{stem}_interfaces.csv"),
        c.csv_of(input, &c.interfaces).into_bytes(),
    ));
    files.push((
        format!("{stem}_bars.csv"),
        c.csv_of(input, &c.bars).into_bytes(),
    ));
}

fn axis_figure(
    kind: Kind,
    axis: &str,
    c: &Curves,
    peaks: Vec<Marker>,
    files: &mut Files,
) -> Result<Figure, Error> {
    push_curves(kind, axis, c, files);
    let against_frequency = |v: &[f64]| -> Vec<(f64, f64)> {
        c.frequency_hz
            .iter()
            .copied()
            .zip(v.iter().copied())
            .collect()
    };
    let input = against_frequency(&c.input);
    let responses: Vec<Vec<(f64, f64)>> =
        c.series.iter().map(|(_, v)| against_frequency(v)).collect();
    let mut series = vec![Series {
        label: "input".into(),
        points: &input,
    }];
    for ((name, _), p) in c.series.iter().zip(&responses) {
        series.push(Series {
            label: name.clone(),
            points: p,
        });
    }
    let (title, y_label, caption) = kind.labels(axis);
    Ok(Figure {
        stem: format!("{}_{axis}", kind.stem()),
        caption,
        svg: lines_markers_svg(
            &title,
            "frequency [Hz]",
            y_label,
            &series,
            &distinct_highest(peaks),
            Scale::Log,
            Scale::Log,
        )?,
    })
}
