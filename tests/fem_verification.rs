//! FE core against analytic and NAFEMS reference values. Each assertion names its source and
//! tolerance.

use satqual::fem::FeModel;
use satqual::modal::{ModalOptions, analyze};
use satqual::spec::Scene;
use std::path::Path;

use crate::common::load;

fn freqs(scene: &Scene, opts: ModalOptions) -> Vec<f64> {
    let model = FeModel::from_scene(&scene.model).unwrap();
    analyze(&model, &opts)
        .unwrap()
        .result
        .modes
        .iter()
        .map(|m| m.frequency_hz)
        .collect()
}

use crate::common::rel;

#[test]
fn cantilever_beta_l_roots() {
    // Source: clamped-free Euler-Bernoulli beam, f = (βL)²/(2πL²)·√(EI/ρA), βL = 1.875104,
    // 4.694091, 7.854757, 10.995541. Steel 20×20 mm, 1 m: 16.710, 104.722, 293.224, 574.602 Hz.
    // Tolerance 0.1%: the FE core's acceptance limit against exact solutions.
    let s = load("test-specs/verification/cantilever.toml");
    let f = freqs(
        &s,
        ModalOptions {
            modes: Some(8),
            ..Default::default()
        },
    );
    let exact_hz = satqual::catalogue::analytic::cantilever_frequencies_hz();
    for (n, exact) in exact_hz.into_iter().enumerate() {
        for k in 0..2 {
            let got = f[2 * n + k];
            assert!(
                rel(got, exact) < 1e-3,
                "mode {}: {got} Hz vs {exact} Hz",
                2 * n + k + 1
            );
        }
    }
    // The rounded figures quoted in the requirement, to the same tolerance.
    for (n, r) in [16.710, 104.722, 293.224, 574.602].iter().enumerate() {
        assert!(rel(f[2 * n], *r) < 1e-3);
    }
}

#[test]
fn cantilever_first_mode_effective_mass() {
    // Source: clamped-free beam, first-mode effective mass 0.6131·m·L (e.g. Chopra, Dynamics
    // of Structures, §17), quoted in the requirement as "about 0.613". Tolerance ±0.002.
    let s = load("test-specs/verification/cantilever.toml");
    let model = FeModel::from_scene(&s.model).unwrap();
    let r = analyze(
        &model,
        &ModalOptions {
            modes: Some(2),
            ..Default::default()
        },
    )
    .unwrap()
    .result;
    let m1 = &r.modes[0].effective_mass_fraction;
    let m2 = &r.modes[1].effective_mass_fraction;
    // Degenerate pair aligned with the axes: one mode per bending plane.
    assert!((m1.y - 0.613).abs() < 2e-3, "{m1:?}");
    assert!(m1.z < 1e-9, "{m1:?}");
    assert!((m2.z - 0.613).abs() < 2e-3, "{m2:?}");
}

#[test]
fn nafems_fv5_timoshenko() {
    // Source: NAFEMS R0015 test FV5 (deep simply supported beam). Tolerance 0.5%: the
    // acceptance limit against published (rather than exact) targets.
    let s = load("test-specs/verification/nafems-fv5.toml");
    let f = freqs(
        &s,
        ModalOptions {
            modes: Some(9),
            ..Default::default()
        },
    );
    let target = satqual::catalogue::analytic::NAFEMS_FV5_HZ;
    for (i, (got, t)) in f.iter().zip(target).enumerate() {
        assert!(rel(*got, t) < 5e-3, "mode {}: {got} vs {t}", i + 1);
    }
}

#[test]
fn nafems_fv5_euler_bernoulli_visibly_misses() {
    // A 2 m deep beam over 10 m is shear-flexible: Euler-Bernoulli overestimates the flexural
    // modes. Assert the miss is larger than 1% on the first flexure and above 4% on the third
    // (the Timoshenko result is within 0.1% of both).
    let s = load("test-specs/verification/nafems-fv5.toml");
    let text = s
        .text
        .replace("theory = \"timoshenko\"", "theory = \"euler-bernoulli\"");
    let eb = Scene::parse(Path::new("fv5-eb.toml"), &text).unwrap();
    let f = freqs(
        &eb,
        ModalOptions {
            modes: Some(10),
            ..Default::default()
        },
    );
    assert!(
        rel(f[0], 42.65) > 0.01,
        "EB first flexure {} should miss 42.65 Hz",
        f[0]
    );
    let flex3 = f
        .iter()
        .copied()
        .filter(|x| *x > 250.0)
        .fold(f64::INFINITY, f64::min);
    assert!(
        rel(flex3, 283.47) > 0.04,
        "EB third flexure {flex3} should miss 283.47 Hz"
    );
}

#[test]
fn nafems_fv4_offset_masses() {
    // Source: NAFEMS R0015 test FV4 (cantilever with off-centre point masses, rigid arm).
    // Tolerance 0.5% (published targets, as FV5). The reference is a slender-beam solution
    // (see the scene).
    let s = load("test-specs/verification/nafems-fv4.toml");
    let f = freqs(
        &s,
        ModalOptions {
            modes: Some(6),
            ..Default::default()
        },
    );
    let target = [1.723, 1.727, 7.413, 9.972, 18.155, 26.957];
    for (i, (got, t)) in f.iter().zip(target).enumerate() {
        assert!(rel(*got, t) < 5e-3, "mode {}: {got} vs {t}", i + 1);
    }
}

fn axial_bar(force_x: f64) -> Scene {
    // Pinned-pinned steel bar 20×20 mm, L = 1 m, axial load at the roller end.
    let text = format!(
        r#"
[[material]]
name = "steel"
youngs_modulus_pa = 210e9
poisson_ratio = 0.3
density_kg_m3 = 7850
[[section]]
name = "bar"
shape = "rectangle"
width_m = 0.02
height_m = 0.02
[[node]]
id = 1
position_m = [0.0, 0.0, 0.0]
[[node]]
id = 2
position_m = [1.0, 0.0, 0.0]
[[beam]]
nodes = [1, 2]
section = "bar"
material = "steel"
elements = 40
orientation = [0.0, 0.0, 1.0]
theory = "euler-bernoulli"
[[support]]
node = 1
dofs = "1234"
[[support]]
node = 2
dofs = "23"
[[static_load]]
node = 2
force_n = [{force_x}, 0.0, 0.0]
"#
    );
    Scene::parse(Path::new("axial-bar.toml"), &text).unwrap()
}

#[test]
fn axially_loaded_pinned_bar_frequency_and_buckling() {
    // Source: exact beam-column result f(N) = f0·√(1 + N·L²/(π²·EI)), f0 = π/(2L²)·√(EI/ρA);
    // tolerance 0.1%. Buckling factor against P_cr = π²EI/L², tolerance 1e-4
    // (the acceptance limit for the buckling factor).
    let (e, rho, a, i, l) = (210e9, 7850.0, 4e-4, 0.02f64.powi(4) / 12.0, 1.0);
    let pi = std::f64::consts::PI;
    let f0 = pi / (2.0 * l * l) * (e * i / (rho * a)).sqrt();
    let pcr = pi * pi * e * i / (l * l);
    for n in [45_000.0, -20_000.0] {
        let s = axial_bar(n);
        let model = FeModel::from_scene(&s.model).unwrap();
        let sys = analyze(
            &model,
            &ModalOptions {
                modes: Some(2),
                ..Default::default()
            },
        )
        .unwrap();
        let exact = f0 * (1.0 + n * l * l / (pi * pi * e * i)).sqrt();
        for m in &sys.result.modes {
            assert!(
                rel(m.frequency_hz, exact) < 1e-3,
                "N = {n}: {} vs {exact}",
                m.frequency_hz
            );
        }
        let ps = sys.result.prestress.as_ref().unwrap();
        assert!(
            rel(ps.members[0].axial_force_n, n) < 1e-9,
            "axial force {}",
            ps.members[0].axial_force_n
        );
        if n < 0.0 {
            let lambda = ps.buckling_factor.unwrap();
            let expect = pcr / -n;
            assert!(
                rel(lambda, expect) < 1e-4,
                "buckling factor {lambda} vs {expect}"
            );
        } else {
            assert!(
                ps.buckling_factor.is_none(),
                "tension cannot buckle the bar"
            );
        }
    }
}

#[test]
fn effective_mass_sums_and_orthonormality() {
    // Completeness: Σ over all modes of Γ² = Dᵀ·M·D of the free DOFs (exact identity, since
    // the mass-normalised shapes are a complete M-orthonormal basis), to 1e-9 relative; and
    // Φᵀ·M·Φ = I to 1e-10 (round-off of the dense eigen-solve). FV4 has offset masses, rigid links and coupled modes.
    for path in [
        "test-specs/verification/nafems-fv4.toml",
        "test-specs/verification/nafems-fv5.toml",
    ] {
        let s = load(path);
        let model = FeModel::from_scene(&s.model).unwrap();
        let sys = analyze(&model, &ModalOptions::default()).unwrap();
        let r = &sys.result;
        assert_eq!(r.modes.len(), r.dofs);
        let rb = r.rigid_body_mass.to_array();
        let mut sum = [0.0; 6];
        for m in &r.modes {
            for (s, e) in sum.iter_mut().zip(m.effective_mass.to_array()) {
                *s += e;
            }
        }
        for a in 0..6 {
            assert!(
                (sum[a] - rb[a]).abs() <= 1e-9 * rb[a].max(1e-30),
                "{path} dir {a}: {} vs {}",
                sum[a],
                rb[a]
            );
        }
        let n = r.dofs;
        let md = satqual::fem::model::dense(n, &sys.m);
        let mut worst = 0.0f64;
        for (p, mp) in r.modes.iter().enumerate() {
            let v: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| md[(i, j)] * mp.shape[j]).sum())
                .collect();
            for (q, mq) in r.modes.iter().enumerate() {
                let d: f64 = mq.shape.iter().zip(&v).map(|(a, b)| a * b).sum();
                let expect = if p == q { 1.0 } else { 0.0 };
                worst = worst.max((d - expect).abs());
            }
        }
        assert!(worst < 1e-10, "{path}: max |ΦᵀMΦ − I| = {worst:e}");
    }
}

#[test]
fn total_mass_includes_offset_masses() {
    // FV4: beam ρ·A·L = 8000·π·0.25²/4·10 = 15 707.96 kg plus 11 000 kg of point masses.
    let s = load("test-specs/verification/nafems-fv4.toml");
    let model = FeModel::from_scene(&s.model).unwrap();
    let r = analyze(
        &model,
        &ModalOptions {
            modes: Some(1),
            ..Default::default()
        },
    )
    .unwrap()
    .result;
    let expect = 8000.0 * std::f64::consts::PI * 0.25 * 0.25 * 10.0 + 11_000.0;
    assert!(rel(r.total_mass_kg, expect) < 1e-12, "{}", r.total_mass_kg);
}

#[test]
fn free_free_model_returns_rigid_body_modes() {
    // No supports: six rigid-body modes at ~0 Hz, then the first free-free bending pair at
    // (4.730041)²/(2πL²)·√(EI/ρA) (free-free beam root), 0.1%.
    let s = load("test-specs/verification/cantilever.toml");
    let text = s
        .text
        .replace("[[support]]\nnode = 1\ndofs = \"123456\"\n", "");
    let free = Scene::parse(Path::new("free.toml"), &text).unwrap();
    let f = freqs(
        &free,
        ModalOptions {
            modes: Some(8),
            ..Default::default()
        },
    );
    for (i, x) in f.iter().take(6).enumerate() {
        assert!(x.abs() < 1e-2, "rigid mode {i}: {x} Hz");
    }
    let (e, rho, a, i) = (210e9, 7850.0, 4e-4, 0.02f64.powi(4) / 12.0);
    let exact =
        4.730040744862704f64.powi(2) / (2.0 * std::f64::consts::PI) * (e * i / (rho * a)).sqrt();
    assert!(rel(f[6], exact) < 1e-3, "{} vs {exact}", f[6]);
}

#[test]
fn guide_bar_modes_match_cantilever_roots() {
    // The separation model's bar modes come from the FE beam model. Steel bar d = 20 mm,
    // L = 3.85 m (the paper's bar length, §4): EB roots βL = 1.875104, 4.694091; the slender bar
    // (L/d = 192) makes Timoshenko corrections < 0.01%. Tolerance 0.1%. Unit modal mass:
    // Σ shape² · μ · Δx ≈ 1 (trapezoid on 40 elements, 1%).
    let steel = satqual::spec::Material {
        name: "steel".into(),
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
        density_kg_m3: 7850.0,
        yield_strength_pa: None,
        ultimate_strength_pa: None,
    };
    let (l, d) = (3.85, 0.02);
    let b = satqual::separation::bar_modes::cantilever_bar_modes(l, d, &steel, 40, 3).unwrap();
    let (a, i) = (
        std::f64::consts::PI * d * d / 4.0,
        std::f64::consts::PI * d.powi(4) / 64.0,
    );
    for (k, bl) in [1.875104068711961f64, 4.694091132974175].iter().enumerate() {
        let exact =
            bl * bl / (2.0 * std::f64::consts::PI * l * l) * (210e9 * i / (7850.0 * a)).sqrt();
        assert!(
            rel(b.frequencies_hz[k], exact) < 1e-3,
            "{} vs {exact}",
            b.frequencies_hz[k]
        );
        let s = &b.shapes[k];
        let dx = l / 40.0;
        let mut integral = 0.0;
        for w in s.windows(2) {
            integral += 0.5 * (w[0] * w[0] + w[1] * w[1]) * b.mass_per_length_kg_m * dx;
        }
        assert!((integral - 1.0).abs() < 0.01, "modal mass {integral}");
    }
    assert_eq!(b.stations_m.len(), 41);
    assert_eq!(b.shapes[0][0], 0.0);
}
