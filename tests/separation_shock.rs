//! The release shock of the separation model: the peak acceleration of an ideal spring
//! release is the spring force over the mass, its SRS above the spring's frequency is the
//! step response of the SRS oscillator, and the component-spec gate passes and fails on
//! scenes made to do each.

use satqual::catalogue::generated::small_stack;
use satqual::gates::separation::release_shock;
use satqual::separation::shock::ReleaseShock;
use satqual::separation::{Model, RunOptions, run, shock};
use satqual::spec::separation::ShockSpec;
use satqual::units::G;

/// One satellite on rigid bars with four equal springs at its symmetric columns: the push is
/// axial and central, so it never tilts and never touches a bar.
fn ideal_release() -> (Model, ReleaseShock, usize) {
    let scene = crate::common::parse(&small_stack(
        1,
        1.5,
        "max_time_s = 10.0\n",
        "[separation.shock]\n",
    ));
    let m = Model::from_scene(&scene).unwrap();
    let opts = RunOptions {
        record_acceleration: true,
        ..Default::default()
    };
    let mut r = run(&m, &opts).unwrap();
    let spec = ShockSpec::default();
    r.shock = Some(shock::release_shock(&m, &r, &spec).unwrap());
    (m, r.shock.unwrap(), r.satellites[0].contacts)
}

/// Reference: at the release the four springs are at full compression, so the satellite's
/// acceleration is Σ k·x / m (Newton; k, x and m as the model holds them). It is the first
/// force the integrator evaluates after the release, so the tolerance is round-off, 1e-12.
#[test]
fn ideal_release_peak_is_spring_force_over_mass() {
    let (m, shock, contacts) = ideal_release();
    assert_eq!(contacts, 0, "the ideal release touches no bar");
    let force: f64 = m
        .springs
        .iter()
        .map(|s| s.stiffness_n_m * s.compression_m)
        .sum();
    let expected_g = force / m.satellites[0].mass_kg / G;
    let b = &shock.bodies[0];
    assert_eq!(b.body, "satellite 1");
    assert_eq!(b.peak_axis, "z");
    let rel = (b.peak_g - expected_g).abs() / expected_g;
    assert!(
        rel < 1e-12,
        "peak {} g against {expected_g} g: {rel:e}",
        b.peak_g
    );
    let release = m.release_times_s[0].unwrap();
    assert_eq!(b.peak_time_s, release);
    // Lateral axes carry nothing (a central push).
    assert!(b.axes[0].peak_g < 1e-12 * expected_g && b.axes[1].peak_g < 1e-12 * expected_g);
}

/// Reference: a release is a step of the base acceleration, A = Σ k·x / m. The absolute
/// acceleration of the SRS oscillator, H(s) = (2ζωs + ω²)/(s² + 2ζωs + ω²), answers a unit
/// step with L⁻¹[H(s)/s] = 1 − e^(−ζωt)(cos ω_d t − ζ/√(1 − ζ²)·sin ω_d t); its maximum
/// (1.85 for Q = 10) times A is the SRS wherever the step looks ideal: the spring force
/// decays as cos(ω_s t), ω_s = √(Σk/m) ≈ 4 rad/s, by (ω_s t)²/2 ≤ 2e-4 by the first peak at
/// 100 Hz; the first ramp of one sample and the sampled maximum cost ≤ 2e-4 each at
/// ωΔt ≤ 0.063 (100–200 Hz at 20 kHz). Tolerance 1e-3.
#[test]
fn srs_above_the_spring_frequency_is_the_step_response() {
    let (m, shock, _) = ideal_release();
    let force: f64 = m
        .springs
        .iter()
        .map(|s| s.stiffness_n_m * s.compression_m)
        .sum();
    let a = force / m.satellites[0].mass_kg / G;
    let zeta = 1.0 / (2.0 * shock.q);
    let step_peak = step_response_peak(zeta);
    assert!((step_peak - 1.85).abs() < 0.01, "{step_peak}");
    let z = &shock.bodies[0].axes[2];
    let checked: Vec<_> = z
        .srs
        .iter()
        .filter(|p| (100.0..=200.0).contains(&p.frequency_hz))
        .collect();
    assert!(checked.len() >= 12, "1/12 octave over one octave");
    for p in checked {
        let rel = (p.maximax - a * step_peak).abs() / (a * step_peak);
        assert!(
            rel < 1e-3,
            "{} Hz: {} g against {} g ({rel:e})",
            p.frequency_hz,
            p.maximax,
            a * step_peak
        );
    }
}

/// Maximum of 1 − e^(−ζωt)(cos ω_d t − ζ/√(1 − ζ²)·sin ω_d t) over its first two periods
/// (ω = 1), on a grid of 2e5 points (the peak is flat to the grid's 3e-5 rad to 1e-9).
fn step_response_peak(zeta: f64) -> f64 {
    let wd = (1.0 - zeta * zeta).sqrt();
    let r = zeta / wd;
    (0..200_000)
        .map(|k| {
            let t = k as f64 * 4.0 * std::f64::consts::PI / wd / 200_000.0;
            1.0 - (-zeta * t).exp() * ((wd * t).cos() - r * (wd * t).sin())
        })
        .fold(0.0, f64::max)
}

/// The reference release-shock scene, its spec replaced by `spec_g`.
fn gated(spec_g: &str) -> Vec<satqual::gates::Verdict> {
    let text = std::fs::read_to_string(crate::common::repo_path("test-specs/release-shock.toml"))
        .unwrap()
        .replace("spec_g = [[10.0, 1.0], [2000.0, 50.0]]", spec_g);
    let scene = crate::common::parse(&text);
    let m = Model::from_scene(&scene).unwrap();
    let opts = RunOptions {
        record_acceleration: true,
        ..Default::default()
    };
    let mut r = run(&m, &opts).unwrap();
    let spec = scene
        .file
        .separation
        .as_ref()
        .unwrap()
        .shock
        .clone()
        .unwrap();
    r.shock = Some(shock::release_shock(&m, &r, &spec).unwrap());
    release_shock(r.shock.as_ref().unwrap())
}

/// The scene's spec (1 g at 10 Hz rising to 50 g) envelopes the release (SRS ≤ 0.6 g): both
/// satellites pass with a positive margin; a flat 0.01 g spec lies 30 dB under it: both fail.
/// Each verdict's margin is its limit (spec + 6 dB) over its value, minus one.
#[test]
fn component_spec_gate_passes_and_fails() {
    let pass = gated("spec_g = [[10.0, 1.0], [2000.0, 50.0]]");
    let fail = gated("spec_g = [[10.0, 0.01], [2000.0, 0.01]]");
    assert_eq!(pass.len(), 2);
    assert_eq!(fail.len(), 2);
    for v in &pass {
        assert!(v.pass && v.margin > 0.0, "{v:?}");
    }
    for v in &fail {
        assert!(!v.pass && v.margin < 0.0, "{v:?}");
        assert!((v.limit - 0.01 * 10f64.powf(0.3)).abs() < 1e-12, "{v:?}");
    }
    for v in pass.iter().chain(&fail) {
        assert!(
            (v.margin - (v.limit / v.value - 1.0)).abs() < 1e-12,
            "{v:?}"
        );
        assert!(v.name.contains("release shock SRS"), "{}", v.name);
    }
}
