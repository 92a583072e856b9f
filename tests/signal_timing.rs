//! Time columns as loggers write them: jittered timestamps are analysed at the mean step and
//! the jitter reported; a missing stretch stays a located error; resampling onto a lower rate
//! goes through an anti-alias low-pass, so a tone above the new Nyquist frequency does not
//! fold into the band.

use crate::common::{run_text, temp_dir};
use rand::{RngExt, SeedableRng};
use satqual::signal::ingest::{IngestOptions, read_csv};
use std::path::PathBuf;

const FS: f64 = 1000.0;

/// A 50 Hz unit sine sampled on a uniform 1 kHz clock, stamped with the sample time plus a
/// uniform error of ±20% of the interval: steps vary by up to ±40% around the mean. `skip`
/// rows are left out (a missing stretch) from row `skip_at`.
fn jittered_csv(name: &str, rows: usize, skip_at: usize, skip: usize) -> (PathBuf, Vec<f64>) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut s = String::from("time_s,a_g\n");
    let mut times = Vec::new();
    for i in 0..rows {
        let stamp = (i as f64 + rng.random_range(-0.2..0.2)) / FS;
        if (skip_at..skip_at + skip).contains(&i) {
            continue;
        }
        let v = (2.0 * std::f64::consts::PI * 50.0 * i as f64 / FS).sin();
        s.push_str(&format!("{stamp:.9},{v:.12}\n"));
        times.push(format!("{stamp:.9}").parse().unwrap());
    }
    let p = temp_dir(name).join("log.csv");
    std::fs::write(&p, s).unwrap();
    (p, times)
}

/// Amplitude of the component at `f` Hz of `x` sampled at `fs` (one DFT bin; `f` on a bin).
fn amplitude(x: &[f64], fs: f64, f: f64) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for (n, v) in x.iter().enumerate() {
        let ph = 2.0 * std::f64::consts::PI * f * n as f64 / fs;
        re += v * ph.cos();
        im -= v * ph.sin();
    }
    2.0 * (re * re + im * im).sqrt() / x.len() as f64
}

#[test]
fn jittered_timestamps_are_analysed_at_the_mean_step_and_reported() {
    let (p, t) = jittered_csv("timing-jitter", 4096, 0, 0);
    let log = read_csv(&p, &IngestOptions::default()).unwrap();
    // Reference: the mean step of the stamps as written, (t_last - t_0) / (n - 1).
    let mean = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    assert!(
        (log.info.fs_hz * mean - 1.0).abs() < 1e-12,
        "{}",
        log.info.fs_hz
    );
    assert_eq!(log.info.samples, 4096);
    assert!(log.info.resampled.is_none());
    let j = log.info.ingest.jitter.clone().expect("a jitter report");
    // Reference: RMS and largest departure of the steps from their mean, computed here.
    let steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let rms = (steps.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / steps.len() as f64).sqrt();
    let max = steps.iter().map(|s| (s - mean).abs()).fold(0.0, f64::max);
    assert!((j.mean_step_s / mean - 1.0).abs() < 1e-9);
    assert!((j.rms_deviation_pct / (100.0 * rms / mean) - 1.0).abs() < 1e-9);
    assert!((j.max_deviation_pct / (100.0 * max / mean) - 1.0).abs() < 1e-9);
    // Uniform stamp errors of ±20%: step departures within ±40%, RMS 0.2·√(2/3) = 16.3%.
    assert!(j.max_deviation_pct < 40.0 && (j.rms_deviation_pct - 16.33).abs() < 1.0);
    // Reference: the first step off the median of the first 32 steps by more than 1% (the
    // tolerance), on file line index + 3 (header, then the step's second row).
    let mut head = steps[..32].to_vec();
    head.sort_by(f64::total_cmp);
    let first = steps
        .iter()
        .position(|s| (s - head[16]).abs() > 0.01 * head[16]);
    assert_eq!(j.first_jittered_line, first.unwrap() as u64 + 3);
    // The command says so and finds the tone (the 50 Hz bin of a 4096-sample record, 0.24 Hz).
    let (code, out, err) = run_text(
        &["psd", p.to_str().unwrap(), "--nperseg", "4096", "--json"],
        None,
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("jitter") && err.contains("mean step"), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["ingest"]["jitter"]["jittered_steps"].as_u64().unwrap() > 3000);
    let peak = v["channels"][0]["peaks"][0]["frequency_hz"]
        .as_f64()
        .unwrap();
    assert!((peak - 50.0).abs() < 0.25, "{peak}");
}

#[test]
fn a_missing_stretch_in_a_jittered_log_is_a_located_error() {
    // Rows 2000..2010 missing: the step on file line 2001 + 1 (header) + 1 is ten intervals.
    let (p, _) = jittered_csv("timing-gap", 4096, 2000, 10);
    let e = read_csv(&p, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("log.csv") && e.contains("line 2002") && e.contains("gap"),
        "{e}"
    );
    assert!(e.contains("--resample"), "{e}");
}

/// A 50 Hz and a 380 Hz unit tone at 1 kHz, resampled to 500 Hz: 380 Hz is above the new
/// Nyquist frequency (250 Hz) and would fold to 120 Hz.
fn two_tones(name: &str) -> PathBuf {
    let mut s = String::from("time_s,a_g\n");
    for i in 0..4000 {
        let t = i as f64 / FS;
        let w = 2.0 * std::f64::consts::PI * t;
        s.push_str(&format!(
            "{t:.6},{:.12}\n",
            (50.0 * w).sin() + (380.0 * w).sin()
        ));
    }
    let p = temp_dir(name).join("tones.csv");
    std::fs::write(&p, s).unwrap();
    p
}

#[test]
fn resampling_to_a_lower_rate_filters_out_what_would_fold() {
    let p = two_tones("timing-antialias");
    let opts = IngestOptions {
        resample_fs: Some(500.0),
        ..Default::default()
    };
    let log = read_csv(&p, &opts).unwrap();
    assert_eq!(log.info.fs_hz, 500.0);
    assert_eq!(log.info.samples, 2000);
    let r = log.info.resampled.clone().expect("a resampling report");
    let a = r.anti_alias.expect("the anti-alias filter");
    assert_eq!((a.passband_hz, a.stopband_hz), (200.0, 250.0));
    // Interior 2 s (1000 samples, whole periods of both frequencies), clear of the ends where
    // the kernel is cut.
    let x = &log.data[0][500..1500];
    // Reference (analytic): the 50 Hz tone passes with amplitude 1 and the 380 Hz tone is
    // stopped, so nothing appears at its alias 500 − 380 = 120 Hz. Tolerance 1e-3 (−60 dB),
    // above the Blackman window's pass-band ripple and −74 dB stop band.
    assert!((amplitude(x, 500.0, 50.0) - 1.0).abs() < 1e-3);
    assert!(
        amplitude(x, 500.0, 120.0) < 1e-3,
        "{}",
        amplitude(x, 500.0, 120.0)
    );
    // Without the filter, keeping every second row folds the tone at full amplitude.
    let raw = read_csv(&p, &IngestOptions::default()).unwrap();
    let naive: Vec<f64> = raw.data[0][1000..3000].iter().step_by(2).copied().collect();
    assert!((amplitude(&naive, 500.0, 120.0) - 1.0).abs() < 1e-6);
}

#[test]
fn the_command_states_the_anti_alias_filter() {
    let p = two_tones("timing-antialias-cli");
    let (code, out, err) = run_text(
        &[
            "psd",
            p.to_str().unwrap(),
            "--resample-fs",
            "500",
            "--nperseg",
            "500",
            "--json",
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("anti-alias") && err.contains("200 Hz"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["fs_hz"], 500.0);
    assert_eq!(v["resampled"]["anti_alias"]["stopband_hz"], 250.0);
    // Reference (analytic): only the 50 Hz tone is in the band; whatever is left at the 120 Hz
    // alias is more than 60 dB (a factor 1e6 in PSD) below it.
    let peaks = v["channels"][0]["peaks"].as_array().unwrap();
    let at = |f: f64| {
        peaks
            .iter()
            .find(|p| (p["frequency_hz"].as_f64().unwrap() - f).abs() < 1.0)
            .map(|p| p["value"].as_f64().unwrap())
    };
    let tone = at(50.0).expect("the 50 Hz peak");
    assert!(at(120.0).is_none_or(|a| a < 1e-6 * tone), "{peaks:?}");
}
