//! `satqual update`: model updating against paired test frequencies.

use crate::common::{load, rel};
use satqual::pipeline::plan::{ModalOverrides, modal_options};
use satqual::pipeline::workflows::correlate::test_modes;
use satqual::pipeline::workflows::update::problem::{Param, Problem, Target};
use satqual::spec::Scene;

const USC: &str = "test-specs/correlation/usc-beam-update.toml";

/// The updating problem of a scene with every test mode a target of weight 1.
fn problem(scene: &Scene) -> Problem<'_> {
    let spec = scene.file.update.clone().expect("[update]");
    let loc = scene.locator();
    let params = spec
        .parameter
        .iter()
        .map(|p| {
            let key = p.key();
            let start = satqual::spec::sweep::find(loc.doc_item(), &key)
                .unwrap()
                .as_value()
                .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                .unwrap();
            Param {
                path: p.path.clone(),
                key,
                start,
                lower: p.lower,
                upper: p.upper,
                scale: p.scale,
            }
        })
        .collect();
    let (test, _) = test_modes::test_modes(scene).unwrap();
    let targets = (0..test.len())
        .map(|t| Target {
            test: t,
            weight: 1.0,
        })
        .collect();
    Problem {
        base: scene,
        params,
        targets,
        test,
        opts: modal_options(scene, &ModalOverrides::default()),
    }
}

/// The analytic Jacobian (Fox–Kapoor sensitivities from assembled-matrix differences) against
/// central differences of full eigen-solves (relative step 1e-4 in ln p; truncation error
/// O(1e-8) of the entry), to 1e-4 of the largest entry.
#[test]
fn sensitivities_match_finite_differences_of_eigen_solves() {
    let scene = load(USC);
    let pr = problem(&scene);
    let start: Vec<f64> = pr.params.iter().map(|p| p.start * 3.0).collect();
    let s = pr.solve(&start).unwrap();
    let j = pr.jacobian(&s).unwrap();
    let h = 1e-4;
    let big = j.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for c in 0..pr.params.len() {
        let at = |sign: f64| {
            let mut v = start.clone();
            v[c] *= (sign * h).exp();
            pr.residuals(&pr.solve(&v).unwrap())
        };
        let fd = (at(1.0) - at(-1.0)) / (2.0 * h);
        for i in 0..fd.len() {
            assert!(
                (fd[i] - j[(i, c)]).abs() < 1e-4 * big,
                "param {c} target {i}: analytic {} vs FD {}",
                j[(i, c)],
                fd[i]
            );
        }
    }
    let _ = rel(1.0, 1.0);
}
