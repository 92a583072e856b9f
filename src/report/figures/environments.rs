//! The input environments: the sine level against frequency and the random profile, with the
//! CSV of each under `curves/`.

use super::{Files, csv};
use crate::error::Error;
use crate::report::document::Figure;
use crate::report::plot::{Scale, Series, lines_svg, loglog_svg};
use crate::spec::environment::{Environments, RandomEnvironment, SineEnvironment};

/// Points per sine segment: a displacement segment is a parabola in g against f.
const SINE_POINTS: usize = 60;

/// The sine figure, then the random one, for those the scene has.
pub fn figures(env: &Environments, files: &mut Files) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    if let Some(s) = &env.sine {
        figs.push(sine(s, files)?);
    }
    if let Some(r) = &env.random {
        figs.push(random(r, files)?);
    }
    Ok(figs)
}

fn sine(s: &SineEnvironment, files: &mut Files) -> Result<Figure, Error> {
    let mut pts = Vec::new();
    for g in &s.segments {
        let ratio = g.to_hz / g.from_hz;
        for k in 0..=SINE_POINTS {
            let f = g.from_hz * ratio.powf(k as f64 / SINE_POINTS as f64);
            pts.push((f, g.level_g(f)));
        }
    }
    files.push((
        "curves/environment_sine.csv".into(),
        csv("frequency_hz,level_g", pts.iter().map(|p| vec![p.0, p.1])),
    ));
    let series = [Series {
        label: "sine level [g]".into(),
        points: &pts,
    }];
    Ok(Figure {
        stem: "environment_sine".into(),
        caption: format!("Sine input level (0-peak) against frequency; {}", s.source),
        svg: lines_svg(
            "Sine input",
            "frequency [Hz]",
            "acceleration 0-pk [g]",
            &series,
            Scale::Log,
            Scale::Linear,
        )?,
    })
}

fn random(r: &RandomEnvironment, files: &mut Files) -> Result<Figure, Error> {
    // Straight lines between the points on log-log axes are the profile itself.
    let pts: Vec<(f64, f64)> = r.profile.iter().map(|p| (p[0], p[1])).collect();
    files.push((
        "curves/environment_random.csv".into(),
        csv("frequency_hz,asd_g2_hz", pts.iter().map(|p| vec![p.0, p.1])),
    ));
    let series = [Series {
        label: format!("random input, {:.2} Grms", r.grms),
        points: &pts,
    }];
    Ok(Figure {
        stem: "environment_random".into(),
        caption: format!("Random input profile as applied; {}", r.source),
        svg: loglog_svg("Random input", "frequency [Hz]", "ASD [g²/Hz]", &series)?,
    })
}
