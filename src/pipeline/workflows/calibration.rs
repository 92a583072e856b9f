//! A flight scene's calibration record (`[calibration]`) checked against its test scene, and
//! the flight prediction across the test fixture's plausible range: for each end of the range
//! the test model is updated again with the fixture's stiffness scaled, the flight scene takes
//! the new values, and its first modes are solved.

use crate::error::Error;
use crate::gates::frequency::first_mode;
use crate::pipeline::plan::{ModalOverrides, modal_options};
use crate::results::{CalibratedValue, CalibrationSummary, FixtureCase};
use crate::spec::Scene;
use crate::spec::calibration::CalibrationSpec;
use crate::spec::sweep::{Target, target};
use crate::spec::update::normalize_path;
use crate::spec::update_edit::{Written, with_values};

/// Relative difference above which a flight value no longer is the test model's.
const SAME_VALUE: f64 = 1e-3;
/// Band solved for the first modes of each flight case, Hz: above the stack's first lateral
/// and axial modes with room (a first mode above it is reported absent).
const FIRST_MODES_FMAX_HZ: f64 = 300.0;

/// Checks the flight scene's calibrated values against its test scene and re-predicts the
/// flight modes at both ends of the fixture's plausible range.
pub fn run(flight: &Scene, spec: &CalibrationSpec) -> Result<CalibrationSummary, Error> {
    let dir = flight
        .path
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_default();
    let test = Scene::load(&dir.join(&spec.test_scene))?;
    let keys: Vec<String> = spec.parameters.iter().map(|p| normalize_path(p)).collect();
    let flight_values = numbers(flight, &keys)?;
    let test_values = numbers(&test, &keys)?;
    let mut warnings = Vec::new();
    let parameters = (spec.parameters.iter().zip(&flight_values).zip(&test_values))
        .map(|((path, &f), &t)| {
            if ((f - t) / t).abs() > SAME_VALUE {
                warnings.push(format!(
                    "`{path}` is {f} here but {t} in {}: the flight scene no longer holds the test model's value (update it, or the test scene)",
                    spec.test_scene
                ));
            }
            CalibratedValue { path: path.clone(), flight: f, test: t }
        })
        .collect();
    let fixture = test.file.stack.as_ref().and_then(|s| s.fixture.clone());
    let mut cases = vec![case(flight, &keys, 1.0, flight_values)?];
    if let Some([lo, hi]) = fixture.as_ref().and_then(|f| f.plausible_range) {
        for factor in [lo, hi] {
            let values = recalibrated(&test, &keys, &test_values, factor)?;
            cases.push(case(flight, &keys, factor, values)?);
        }
    }
    Ok(CalibrationSummary {
        test_scene: spec.test_scene.clone(),
        parameters,
        fixture_source: fixture.and_then(|f| f.source),
        cases,
        warnings,
    })
}

/// The numbers at `keys` in `scene`'s text.
fn numbers(scene: &Scene, keys: &[String]) -> Result<Vec<f64>, Error> {
    let loc = scene.locator();
    keys.iter()
        .map(|k| match target(loc.doc_item(), k) {
            Ok(Target::Float(v)) => Ok(v),
            Ok(Target::Integer(i)) => Ok(i as f64),
            Err(e) => Err(loc.err(k, e).into()),
        })
        .collect()
}

/// The test scene's frequency fit redone with its fixture's stiffness × `factor`: the values
/// at `keys`; a key the fit does not adjust (a damping ratio identified after it) keeps its
/// value in `nominal`.
fn recalibrated(
    test: &Scene,
    keys: &[String],
    nominal: &[f64],
    factor: f64,
) -> Result<Vec<f64>, Error> {
    let fixture = test.file.stack.as_ref().and_then(|s| s.fixture.as_ref());
    let Some(fixture) = fixture else {
        return Err(Error::Other(format!(
            "{}: no [stack.fixture]",
            test.path.display()
        )));
    };
    let scaled = fixture.scaled(factor);
    let edits: Vec<Written> = [
        ("lateral_stiffness_n_m", scaled.lateral_stiffness_n_m),
        ("axial_stiffness_n_m", scaled.axial_stiffness_n_m),
        (
            "rocking_stiffness_n_m_rad",
            scaled.rocking_stiffness_n_m_rad,
        ),
        (
            "torsional_stiffness_n_m_rad",
            scaled.torsional_stiffness_n_m_rad,
        ),
    ]
    .map(|(key, value)| Written {
        key: format!("stack.fixture.{key}"),
        value,
        note: None,
    })
    .into();
    let text = with_values(&test.text, &edits)
        .map_err(|e| Error::Other(format!("{}: {e}", test.path.display())))?;
    let updated = super::update::frequencies_only(&Scene::parse(&test.path, &text)?)?;
    Ok((keys.iter().zip(nominal))
        .map(|(k, &v)| {
            let p = updated
                .parameters
                .iter()
                .find(|p| normalize_path(&p.path) == *k);
            p.map_or(v, |p| p.value)
        })
        .collect())
}

/// The flight scene with `values` at `keys`: its first modes.
fn case(
    flight: &Scene,
    keys: &[String],
    factor: f64,
    values: Vec<f64>,
) -> Result<FixtureCase, Error> {
    let edits: Vec<Written> = (keys.iter().zip(&values))
        .map(|(k, &value)| Written {
            key: k.clone(),
            value,
            note: None,
        })
        .collect();
    let text = with_values(&flight.text, &edits)
        .map_err(|e| Error::Other(format!("{}: {e}", flight.path.display())))?;
    let scene = Scene::parse(&flight.path, &text)?;
    let overrides = ModalOverrides {
        fmax_hz: Some(FIRST_MODES_FMAX_HZ),
        ..Default::default()
    };
    let opts = modal_options(&scene, &overrides);
    let model = super::modal::fe_model(&scene)?;
    let sys = crate::modal::analyze(&model, &opts)?;
    let first_hz = [0, 1, 2].map(|d| first_mode(&sys.result, d).map(|(_, f)| f));
    Ok(FixtureCase {
        fixture_factor: factor,
        values,
        first_hz,
    })
}
