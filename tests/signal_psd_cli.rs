//! `satqual psd` end to end on measured data: the USC shaker-beam multi-tone sine dwell
//! (data/realdata/usc-shaker-beam/data_set_1_3200Hz.csv, CC BY-SA 4.0; see its SOURCE.md).
//! SOURCE.md anchors: Welch PSD of acceleration peaks at exactly 100, 120, 150 Hz; acceleration
//! RMS 0.078 g (test 1); fs = 3200 Hz (dt = 312.5 µs).

use serde_json::Value;
use std::path::PathBuf;

fn file() -> PathBuf {
    crate::common::repo_path(satqual::catalogue::logs::SHAKER_BEAM)
}

#[test]
fn shaker_beam_psd_peaks_rms_and_outputs() {
    let out = crate::common::temp_dir("sig-psdcli");
    let o = crate::common::satqual()
        .args([
            "psd",
            file().to_str().unwrap(),
            "--channels",
            "acceleration_g",
            "--nperseg",
            "3200",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    // fs from the time column: 3200 Hz to 1e-6 (times printed with 8+ digits).
    assert!(
        (v["fs_hz"].as_f64().unwrap() - 3200.0).abs() < 3200.0 * 1e-6,
        "{}",
        v["fs_hz"]
    );
    assert_eq!(v["nperseg"], 3200);
    assert!((v["frequency_resolution_hz"].as_f64().unwrap() - 1.0).abs() < 1e-6);
    let ch = &v["channels"][0];
    assert_eq!(ch["name"], "acceleration_g");
    assert_eq!(ch["unit"], "g");
    // SOURCE.md: RMS 0.078 g (two significant digits: ±0.0005).
    let rms = ch["rms"].as_f64().unwrap();
    assert!((rms - 0.078).abs() < 0.0005, "{rms}");
    // Grms from the PSD excludes only the mean: it cannot exceed the RMS.
    assert!(ch["grms"].as_f64().unwrap() <= rms * (1.0 + 1e-9));
    let peaks: Vec<f64> = ch["peaks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["frequency_hz"].as_f64().unwrap())
        .collect();
    for tone in [100.0, 120.0, 150.0] {
        // The tones sit on 1 Hz lines: the interpolated peak must be within a tenth of a line.
        assert!(
            peaks.iter().any(|f| (f - tone).abs() < 0.1),
            "{tone} Hz not in {peaks:?}"
        );
    }
    let svg = std::fs::read_to_string(out.join("psd.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("Grms"),
        "legend with Grms"
    );
    let csv = std::fs::read_to_string(out.join("psd.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 1601);
    assert!(
        std::fs::read_to_string(out.join("third_octave.csv"))
            .unwrap()
            .lines()
            .count()
            > 10
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn frf_cli_writes_curves_and_plots() {
    let out = crate::common::temp_dir("sig-frfcli");
    let o = crate::common::satqual()
        .args([
            "frf",
            file().to_str().unwrap(),
            "--input",
            "force_lbf",
            "--output",
            "acceleration_g",
            "--nperseg",
            "3200",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["peaks"].is_array());
    for p in v["peaks"].as_array().unwrap() {
        for k in ["frequency_hz", "magnitude", "q", "coherence"] {
            assert!(p.get(k).is_some(), "{k} missing in {p}");
        }
    }
    for f in ["frf.csv", "frf.svg", "coherence.svg"] {
        assert!(out.join(f).exists(), "{f}");
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn nperseg_below_the_minimum_is_an_error_and_a_coarse_one_a_warning() {
    // A 1-sample Hann window is 0: every PSD would be 0 (Grms 0 on live channels).
    let f = file();
    let (code, _, err) =
        crate::common::run_text(&["psd", f.to_str().unwrap(), "--nperseg", "1"], None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("nperseg") && err.contains("at least 16"),
        "{err}"
    );
    // 16 is the documented minimum: accepted. At 3200 Hz it gives 200 Hz lines, 9 of them
    // over 0–1600 Hz: fewer than the 16 a band needs, so a warning names the nperseg to pass
    // (16 lines over 1600 Hz: 16·3200/1600 = 32).
    let (code, out, err) = crate::common::run_text(
        &["psd", f.to_str().unwrap(), "--nperseg", "16", "--json"],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let w = v["warnings"][0].as_str().unwrap();
    assert!(w.contains("9 line(s)") && w.contains("--nperseg 32"), "{w}");
    assert!(err.contains(&format!("warning: {w}")), "{err}");
    // The default segment resolves the whole band: no warning.
    let (_, out, _) = crate::common::run_text(&["psd", f.to_str().unwrap(), "--json"], None);
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["warnings"], serde_json::json!([]));
}

/// A log shorter than the default 8192-sample segment: without `--nperseg`, psd takes the
/// largest power of two leaving four segment lengths (3000 samples → 512, 10 segments at 50%
/// overlap) and says so on stderr; with `--nperseg 8192` given, it still refuses. Reference:
/// a unit sine's RMS is 1/√2 (analytic); a Hann-window Welch estimate integrates to it within
/// 1e-3 when the tone sits between lines (50 Hz at 1.953 Hz lines).
#[test]
fn a_short_log_gets_a_shorter_default_segment() {
    let dir = crate::common::temp_dir("psd-short-log");
    let path = dir.join("short.csv");
    let mut text = String::from("t,a\n");
    for i in 0..3000 {
        let t = i as f64 / 1000.0;
        text.push_str(&format!(
            "{t},{}\n",
            (2.0 * std::f64::consts::PI * 50.0 * t).sin()
        ));
    }
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap();
    let (code, out, err) = crate::common::run_text(&["psd", p, "--json"], None);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("nperseg 512"), "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["nperseg"], 512);
    let grms = v["channels"][0]["grms"].as_f64().unwrap();
    assert!((grms - 0.5f64.sqrt()).abs() < 1e-3, "{grms}");
    let (code, _, err) = crate::common::run_text(&["psd", p, "--nperseg", "8192"], None);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("longer than the signal"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
