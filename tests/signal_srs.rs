//! Shock response spectrum (`satqual::signal::srs`) against:
//! - data/signal-refs/srs_refs.json (`python3 data/signal-refs/make_srs_refs.py`): scipy.signal.lfilter
//!   with Smallwood's coefficients (checked there against scipy's first-order-hold discretisation),
//!   1e-9 relative to the maximax; and endaq.calc.shock.shock_spectrum on the third-party record
//!   data/realdata/hrshm-pcb-shock (see its SOURCE.md), 1e-6 relative to the maximax;
//! - closed forms: the residual spectrum of a half-sine and the resonant steady-state gain.

use crate::common::{repo_path, satqual, temp_dir};
use satqual::signal::ingest::IngestOptions;
use satqual::signal::srs::{
    Offset, SpecTolerance, SrsOptions, SrsPoint, check_against_spec, natural_frequencies,
    residual_samples, srs, srs_of_file,
};
use serde_json::Value;
use std::f64::consts::PI;

fn refs() -> Value {
    let text = std::fs::read_to_string(repo_path("data/signal-refs/srs_refs.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn case<'a>(refs: &'a Value, name: &str) -> &'a Value {
    refs["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap()
}

fn f(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap()
}

/// Largest |ours - reference| / maximax over the six fields of every point; `pv_scale` converts
/// the reference pseudo-velocity to our unit.
fn worst_vs_lfilter(ours: &[SrsPoint], reference: &[Value], pv_scale: f64) -> f64 {
    assert_eq!(ours.len(), reference.len());
    let mut worst = 0.0f64;
    for (o, r) in ours.iter().zip(reference) {
        assert!((o.frequency_hz - f(r, "frequency_hz")).abs() <= 1e-12 * o.frequency_hz);
        let m = f(r, "maximax");
        for (a, b) in [
            (o.maximax, m),
            (o.positive, f(r, "positive")),
            (o.negative, f(r, "negative")),
            (o.primary, f(r, "primary")),
            (o.residual, f(r, "residual")),
        ] {
            worst = worst.max((a - b).abs() / m);
        }
        let pv = f(r, "pseudo_velocity") * pv_scale;
        worst = worst.max((o.pseudo_velocity - pv).abs() / pv);
    }
    worst
}

#[test]
fn synthetic_record_matches_scipy_lfilter_to_1e_9() {
    let refs = refs();
    let c = case(&refs, "synthetic");
    let x: Vec<f64> = c["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let xm: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let pts = c["srs"].as_array().unwrap();
    let freqs: Vec<f64> = pts.iter().map(|p| f(p, "frequency_hz")).collect();
    let (fs, q) = (f(c, "fs_hz"), f(c, "q"));
    assert_eq!(
        residual_samples(freqs[0], q, 1.0 / fs) as u64,
        c["residual_samples"].as_u64().unwrap()
    );
    // Our grid is the script's grid (fmin·2^(k/12), 20 Hz to 5 kHz).
    let grid = natural_frequencies(20.0, 5000.0, 12);
    assert_eq!(grid.len(), freqs.len());
    let ours = srs(&xm, fs, &freqs, q).unwrap();
    let worst = worst_vs_lfilter(&ours, pts, 1.0);
    println!("synthetic: worst relative difference from lfilter {worst:.3e}");
    assert!(worst <= 1e-9, "{worst}");
}

fn hrshm() -> satqual::signal::LogSrs {
    let opts = SrsOptions {
        q: 10.0,
        fmin_hz: 100.0,
        fmax_hz: 20_000.0,
        per_octave: 12,
        offset: Offset::None,
    };
    let path = repo_path("data/realdata/hrshm-pcb-shock/acc_base_a0_first5ms.csv");
    srs_of_file(&path, &IngestOptions::default(), &opts).unwrap()
}

#[test]
fn third_party_shock_matches_lfilter_and_endaq() {
    let refs = refs();
    let c = case(&refs, "hrshm");
    let res = hrshm();
    assert_eq!(res.channels.len(), 1);
    let ch = &res.channels[0];
    assert_eq!(ch.unit, "g"); // from the column name base_accel_g
    assert_eq!(ch.pv_unit, "m/s");
    assert_eq!(
        res.residual_samples as u64,
        c["residual_samples"].as_u64().unwrap()
    );
    let pts = c["srs"].as_array().unwrap();
    // Pseudo-velocity: the script's is in g·s, ours in m/s (standard gravity 9.80665).
    let worst = worst_vs_lfilter(&ch.srs, pts, 9.80665);
    let mut endaq = 0.0f64;
    for (o, r) in ch.srs.iter().zip(pts) {
        endaq = endaq.max((o.positive - f(r, "endaq_positive")).abs() / o.maximax);
        endaq = endaq.max((o.negative - f(r, "endaq_negative")).abs() / o.maximax);
    }
    println!("hrshm: vs lfilter {worst:.3e}, vs endaq {endaq:.3e}");
    assert!(worst <= 1e-9, "{worst}");
    assert!(endaq <= 1e-6, "{endaq}");
    // Peak: row 40 of the file (t = 39·dt = 0.78 ms), 485.972074 g (SOURCE.md).
    assert_eq!(ch.peak, 485.972074);
    assert!((ch.peak_time_s - 7.801084086170931e-4).abs() < 1e-12);
}

/// Undamped residual spectrum of a half-sine A·sin(πt/τ), 0 ≤ t ≤ τ: the free response after
/// the pulse has absolute-acceleration amplitude ω|Ü(ω)|, Ü the pulse's Fourier transform
/// (Duhamel integral), |Ü(ω)| = (2Aτ/π)|cos(ωτ/2)|/|1 − (ωτ/π)²|, so
/// residual = 4Afτ|cos(πfτ)|/|1 − 4f²τ²| (Irvine, "An introduction to the shock response
/// spectrum", 2012, half-sine residual). Q = 1e6 makes the damping negligible (decay over one
/// period 2πζ = 3e-6). Tolerance 2e-5: the sampled peak of a sinusoid is low by at most
/// 1 − cos(πf/fs) (≤ 1.6e-5 at 180 Hz, fs 100 kHz) and the ramp between samples misses the
/// half-sine by O((πdt/τ)²/8) = 1.2e-6.
#[test]
fn half_sine_residual_matches_closed_form() {
    let (a, tau, fs) = (100.0, 0.01, 100_000.0);
    let n = (tau * fs) as usize;
    let x: Vec<f64> = (0..=n)
        .map(|k| a * (PI * k as f64 / (tau * fs)).sin())
        .collect();
    let freqs = [5.0, 10.0, 20.0, 30.0, 70.0, 180.0];
    let ours = srs(&x, fs, &freqs, 1e6).unwrap();
    let mut worst = 0.0f64;
    for p in &ours {
        let ft = p.frequency_hz * tau;
        let exact = 4.0 * a * ft * (PI * ft).cos().abs() / (1.0 - 4.0 * ft * ft).abs();
        worst = worst.max((p.residual - exact).abs() / exact);
    }
    println!("half-sine residual: worst relative error {worst:.3e}");
    assert!(worst <= 2e-5, "{worst}");
}

/// A sine at the natural frequency, long enough for the transient to die (20 time constants
/// 1/(ζω)): the response amplitude is the transmissibility at resonance,
/// |(2ζωs + ω²)/(s² + 2ζωs + ω²)| at s = iω = sqrt(1 + (2ζ)²)/(2ζ) = Q·sqrt(1 + 1/Q²).
/// Tolerance 2e-5: the sampled-peak loss 1 − cos(πf/fs) = 4.9e-6 at 100 Hz, fs 100 kHz, and the
/// ramp interpolation of the sine, (ωdt)²/8 = 4.9e-6.
#[test]
fn resonant_sine_reaches_the_steady_state_gain() {
    let (fs, fn_hz, q) = (100_000.0, 100.0, 10.0);
    let n = (0.7 * fs) as usize; // 20/(ζω) = 0.64 s
    let x: Vec<f64> = (0..n)
        .map(|k| (2.0 * PI * fn_hz * k as f64 / fs).sin())
        .collect();
    let p = srs(&x, fs, &[fn_hz], q).unwrap()[0];
    let exact = q * (1.0 + 1.0 / (q * q)).sqrt();
    let err = (p.primary - exact).abs() / exact;
    println!("resonant gain {} vs {exact}: {err:.3e}", p.primary);
    assert!(err <= 2e-5, "{err}");
}

#[test]
fn spectrum_is_identical_whatever_the_thread_count() {
    let x: Vec<f64> = (0..5000)
        .map(|k| ((k as f64) * 0.37).sin() * (-(k as f64) / 900.0).exp())
        .collect();
    let freqs = natural_frequencies(10.0, 4000.0, 12);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| srs(&x, 10_000.0, &freqs, 10.0).unwrap())
    };
    let bits = |v: Vec<SrsPoint>| -> Vec<u64> {
        v.iter()
            .flat_map(|p| [p.maximax, p.positive, p.negative, p.pseudo_velocity])
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(run(1)), bits(run(2)));
}

/// Hand-made points at known excursions from a flat 100 g specification: -7, -3, 0, +5, +7 dB.
#[test]
fn spec_check_counts_points_outside_the_limits() {
    let pts: Vec<SrsPoint> = [-7.0, -3.0, 0.0, 5.0, 7.0]
        .iter()
        .enumerate()
        .map(|(i, db)| {
            let m = 100.0 * 10f64.powf(db / 20.0);
            SrsPoint {
                frequency_hz: 100.0 * (i + 1) as f64,
                maximax: m,
                positive: m,
                negative: m,
                primary: m,
                residual: m,
                pseudo_velocity: 1.0,
            }
        })
        .collect();
    let spec = [(100.0, 100.0), (500.0, 100.0)];
    let c = check_against_spec(&pts, &spec, SpecTolerance::default());
    assert_eq!(c.points.len(), 5);
    assert_eq!(c.fraction_above_upper, 0.2);
    assert_eq!(c.fraction_below_lower, 0.2);
    assert!((c.worst_db.abs() - 7.0).abs() < 1e-12);
    assert!(!c.pass);
    let wide = SpecTolerance {
        upper_db: 8.0,
        lower_db: 8.0,
        allowed_fraction: 0.0,
    };
    assert!(check_against_spec(&pts, &spec, wide).pass);
    // Log-log interpolation: 1 g at 10 Hz to 100 g at 1000 Hz is 10 g at 100 Hz, so the
    // 100 Hz point (100·10^(-7/20) g) sits at 20·log10(10^(-7/20)·10) = 13 dB.
    let sloped = check_against_spec(&pts[..1], &[(10.0, 1.0), (1000.0, 100.0)], wide);
    assert!((sloped.points[0].excursion_db - 13.0).abs() < 1e-9);
}

#[test]
fn bad_input_is_a_clear_error() {
    let path = repo_path("data/realdata/hrshm-pcb-shock/acc_base_a0_first5ms.csv");
    // The record starts on the rising edge of the shock: no pre-shock level.
    let opts = SrsOptions {
        fmin_hz: 100.0,
        fmax_hz: 20_000.0,
        offset: Offset::PreShock,
        ..Default::default()
    };
    let e = srs_of_file(&path, &IngestOptions::default(), &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("base_accel_g") && e.contains("acc_base_a0_first5ms.csv"),
        "{e}"
    );
    assert!(e.contains("before the shock onset"), "{e}");
    // Above Nyquist (fs ≈ 49 993 Hz).
    let opts = SrsOptions {
        fmax_hz: 30_000.0,
        offset: Offset::None,
        ..Default::default()
    };
    let e = srs_of_file(&path, &IngestOptions::default(), &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("fs/2") && e.contains("base_accel_g"), "{e}");
    let q = SrsOptions {
        q: 0.4,
        ..Default::default()
    };
    assert!(q.validate().unwrap_err().to_string().contains("`q`"));
    assert!(srs(&[1.0, f64::NAN], 1000.0, &[10.0], 10.0).is_err());
}

#[test]
fn cli_writes_json_csv_and_svg_and_gates_on_the_spec() {
    let dir = temp_dir("srs-cli");
    // A specification 1000 g flat from 200 Hz to 10 kHz: the record's SRS is far below it.
    let spec = dir.join("spec.toml");
    std::fs::write(&spec, "points = [[200.0, 1000.0], [10000.0, 1000.0]]\n").unwrap();
    let out = satqual()
        .args([
            "srs",
            "data/realdata/hrshm-pcb-shock/acc_base_a0_first5ms.csv",
        ])
        .args([
            "--fmin", "100", "--fmax", "20000", "--offset", "none", "--json",
        ])
        .arg("--spec")
        .arg(&spec)
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(
        !out.status.success(),
        "a failed spec check must fail the command"
    );
    assert_eq!(v["pass"], false);
    let ch = &v["channels"][0];
    assert_eq!(ch["name"], "base_accel_g");
    assert_eq!(ch["peak"].as_f64().unwrap(), 485.972074);
    // The CLI prints what the library computed.
    let lib = hrshm();
    let first = &ch["srs"][0];
    assert_eq!(
        first["maximax"].as_f64().unwrap(),
        lib.channels[0].srs[0].maximax
    );
    assert!(
        v["spec"][0]["check"]["fraction_below_lower"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    let csv = std::fs::read_to_string(dir.join("srs.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + lib.channels[0].srs.len());
    assert!(
        std::fs::read_to_string(dir.join("srs.svg"))
            .unwrap()
            .contains("<svg")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Without `--fmax`, the spectrum stops at fs/10 (ten samples per period of the highest
/// oscillator, NASA-HDBK-7005 §3.4) and at most at 10 kHz: a 5 kHz log gets 500 Hz instead of
/// a refusal for the 10 kHz that only a ≥ 20 kHz log could reach; the choice is said on stderr
/// and recorded in the JSON options. An explicit `--fmax` at or above fs/2 is still refused.
#[test]
fn the_default_fmax_follows_the_sampling_rate() {
    let dir = temp_dir("srs-default-fmax");
    let path = dir.join("shock5k.csv");
    let mut text = String::from("t,a\n");
    for i in 0..5000 {
        let t = i as f64 / 5000.0;
        let a = if t > 0.1 {
            (-30.0 * t).exp() * (2.0 * std::f64::consts::PI * 200.0 * t).sin()
        } else {
            0.0
        };
        text.push_str(&format!("{t},{a}\n"));
    }
    std::fs::write(&path, text).unwrap();
    let out = satqual()
        .arg("srs")
        .arg(&path)
        .arg("--json")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("up to 500 Hz"), "{err}");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["options"]["fmax_hz"].as_f64().unwrap(), 500.0);
    let out = satqual()
        .arg("srs")
        .arg(&path)
        .args(["--fmax", "3000"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}
