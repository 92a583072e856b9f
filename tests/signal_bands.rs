//! Grms, band levels and tolerance bands on the VibControl controller PSD
//! (data/realdata/pyuff-vibcontrol-psd, UFF58 function type 9; see its SOURCE.md).
//! References: SOURCE.md (Grms = 0.5595 g by trapezoid), data/signal-refs/tolerance_refs.json
//! (numpy, `python3 data/signal-refs/make_tolerance_refs.py`), and closed forms for flat spectra.

use satqual::signal::{
    ToleranceSpec, ToleranceStatus, band_rms, octave_bands, read_profile, read_uff58, rms_of,
    tolerance_bands,
};
use serde_json::Value;
use std::path::PathBuf;

fn root() -> PathBuf {
    crate::common::repo_path("")
}

fn uff_psd() -> (Vec<f64>, Vec<f64>) {
    let recs =
        read_uff58(&root().join("data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff"))
            .unwrap();
    assert_eq!(recs.len(), 1);
    let r = &recs[0];
    assert_eq!(r.function.function_type, 9);
    assert_eq!(r.abscissa.len(), 3201);
    (r.abscissa.clone(), r.re.clone())
}

#[test]
fn uff_psd_matches_pyuff_csv_and_source_grms() {
    let (f, p) = uff_psd();
    // The CSV is pyuff's conversion of the same record: identical values (both parse the same
    // decimal text), checked to 1e-12 relative.
    let csv = std::fs::read_to_string(
        root().join("data/realdata/pyuff-vibcontrol-psd/vibcontrol_random_pilot_psd.csv"),
    )
    .unwrap();
    for (k, line) in csv.lines().skip(1).enumerate() {
        let mut it = line.split(',').map(|s| s.parse::<f64>().unwrap());
        let (cf, cp) = (it.next().unwrap(), it.next().unwrap());
        assert!(
            (cf - f[k]).abs() <= 1e-12 * cf.abs().max(1.0)
                && (cp - p[k]).abs() <= 1e-12 * cp.abs().max(1e-300),
            "line {k}"
        );
    }
    let grms = rms_of(&f, &p);
    eprintln!("Grms {grms:.6}");
    // SOURCE.md: sqrt(trapz(PSD, f)) = 0.5595 g, four digits.
    assert!((grms - 0.5595).abs() < 0.00005, "{grms}");
    // SOURCE.md: energy essentially within 1–2204 Hz.
    assert!(band_rms(&f, &p, 1.0, 2204.0) / grms > 0.999);
}

#[test]
fn flat_spectrum_band_levels_are_exact() {
    // S = 0.01 on lines 0..1000 Hz, df 0.5: band RMS² = S·(f_hi − f_lo) exactly, edges between lines.
    let f: Vec<f64> = (0..=2000).map(|k| k as f64 * 0.5).collect();
    let s = vec![0.01; f.len()];
    assert!((band_rms(&f, &s, 10.3, 20.7).powi(2) - 0.01 * 10.4).abs() < 1e-12);
    for b in octave_bands(&f, &s, 3) {
        assert!((b.rms.powi(2) - 0.01 * (b.upper_hz - b.lower_hz)).abs() < 1e-12 * b.upper_hz);
        // IEC 61260-1 base-10 third-octave: upper/lower = 10^(1/10).
        assert!((b.upper_hz / b.lower_hz - 10f64.powf(0.1)).abs() < 1e-12);
    }
    let oct = octave_bands(&f, &s, 1);
    assert!(
        oct.iter()
            .any(|b| (b.center_hz - 1000.0 * 10f64.powf(-0.3)).abs() < 1e-9),
        "{oct:?}"
    );
}

#[test]
fn tolerance_bands_match_numpy_and_gate_correctly() {
    let (f, p) = uff_psd();
    let prof = read_profile(&root().join("data/signal-refs/vibcontrol_profile.toml")).unwrap();
    let refs: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("data/signal-refs/tolerance_refs.json")).unwrap(),
    )
    .unwrap();
    for case in refs["cases"].as_array().unwrap() {
        let scale = case["scale"].as_f64().unwrap();
        let scaled: Vec<(f64, f64)> = prof.iter().map(|&(a, b)| (a, b * scale)).collect();
        let r = tolerance_bands(&f, &p, &scaled, &ToleranceSpec::default()).unwrap();
        eprintln!("scale {scale}: {r:?}");
        // Line counts are exact; dB and Grms to 1e-9 relative (same formulas as numpy).
        assert_eq!(r.lines_checked as u64, case["lines"].as_u64().unwrap());
        assert!((r.fraction_outside_alarm - case["alarm"].as_f64().unwrap()).abs() < 1e-12);
        assert!((r.fraction_outside_abort - case["abort"].as_f64().unwrap()).abs() < 1e-12);
        assert!((r.worst_excursion_db - case["worst_db"].as_f64().unwrap()).abs() < 1e-9);
        assert_eq!(r.worst_frequency_hz, case["worst_hz"].as_f64().unwrap());
        let (m, rf) = (
            case["measured_grms"].as_f64().unwrap(),
            case["reference_grms"].as_f64().unwrap(),
        );
        assert!(
            (r.measured_grms - m).abs() < 1e-9 * m && (r.reference_grms - rf).abs() < 1e-9 * rf
        );
        if scale == 1.0 {
            // The fitted profile: 1.2% of lines beyond ±3 dB (alarm), none beyond ±6 dB, Grms +1.1%.
            assert_eq!(r.status, ToleranceStatus::Alarm);
            assert!(r.pass);
        } else {
            assert_eq!(r.status, ToleranceStatus::Abort);
            assert!(!r.pass);
        }
    }
}

fn run(args: &[&str]) -> (i32, String, String) {
    crate::common::run_text(args, None)
}

#[test]
fn cli_tolerance_passes_fitted_profile_and_fails_a_doubled_one() {
    let uff = root().join("data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff");
    let prof = root().join("data/signal-refs/vibcontrol_profile.toml");
    let (code, out, err) = run(&[
        "psd",
        uff.to_str().unwrap(),
        "--profile",
        prof.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["pass"], true);
    assert_eq!(v["tolerance"]["report"]["status"], "alarm");
    let grms = v["channels"][0]["grms"].as_f64().unwrap();
    assert!((grms - 0.5595).abs() < 0.00005, "{grms}");
    // Twice the level (+3 dB): Grms 29% low and lines beyond −6 dB: abort, exit 1.
    let dir = crate::common::temp_dir("sig-tol");
    let doubled = dir.join("doubled.csv");
    let rows: String = read_profile(&prof)
        .unwrap()
        .iter()
        .map(|(f, g)| format!("{f},{}\n", 2.0 * g))
        .collect();
    std::fs::write(&doubled, format!("f_hz,g2_hz\n{rows}")).unwrap();
    let (code, out, err) = run(&[
        "psd",
        uff.to_str().unwrap(),
        "--profile",
        doubled.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 1, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["pass"], false);
    assert_eq!(v["tolerance"]["report"]["status"], "abort");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn psd_rms_is_parseval_for_white_noise() {
    // Parseval: for a zero-mean signal the one-sided density integrates to the variance, and
    // the Welch estimate (Hann, 50%) is unbiased for white noise. On 2^20 samples of uniform
    // noise (variance 1/12) the relative scatter of a variance estimate is about √(2/N) ≈ 0.14%,
    // so the Grms must be √(1/12) within 1%.
    let mut state = 1u64;
    let x: Vec<f64> = (0..1 << 20)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect();
    let p = satqual::signal::welch(
        &x,
        1000.0,
        &satqual::signal::WelchOptions {
            nperseg: 1024,
            ..Default::default()
        },
    )
    .unwrap();
    let want = (1.0f64 / 12.0).sqrt();
    assert!(
        (p.rms() - want).abs() < 0.01 * want,
        "{} vs {want}",
        p.rms()
    );
    // Half the band holds half the power for white noise.
    assert!((p.band_rms(0.0, 250.0).powi(2) / p.rms().powi(2) - 0.5).abs() < 0.01);
}
