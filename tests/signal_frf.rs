//! H1, coherence and resonance picking on measured impact-hammer data
//! (data/realdata/pyfrf-impact, 5 hits, fs = 25600 Hz, 1 s records; see its SOURCE.md).
//! SOURCE.md anchors (no windows, 5 linear averages, H1 = ΣX*Y/Σ|X|²): dominant H1 peaks near
//! 900, 2640, 3669/3690, 4128/4164, 4392, 5969 Hz; median coherence 0.999 over 20–2000 Hz.

use satqual::signal::{
    Detrend, IngestOptions, PeakOptions, WelchOptions, Window, frf, read_csv, resonances,
};
use std::path::PathBuf;

fn dir() -> PathBuf {
    crate::common::repo_path(satqual::catalogue::logs::IMPACT_DIR)
}

#[test]
fn impact_h1_finds_the_source_md_peaks_with_high_coherence() {
    let logs: Vec<_> = (1..=5)
        .map(|i| {
            read_csv(
                &dir().join(format!("impact_{i}.csv")),
                &IngestOptions::default(),
            )
            .unwrap()
        })
        .collect();
    // The time column (%.8f) gives fs; SOURCE.md states 25600 Hz. 1e-6 relative: rounding of
    // the printed times over a 1 s span.
    let fs = logs[0].info.fs_hz;
    assert!((fs - 25600.0).abs() < 25600.0 * 1e-6, "{fs}");
    let records: Vec<(&[f64], &[f64])> = logs
        .iter()
        .map(|l| {
            (
                l.channel("force").unwrap(),
                l.channel("acceleration").unwrap(),
            )
        })
        .collect();
    // One segment per hit, no window, no detrend: the averaging SOURCE.md describes.
    let opts = WelchOptions {
        nperseg: 25600,
        overlap: 0.0,
        window: Window::Boxcar,
        detrend: Detrend::None,
    };
    let h = frf(&records, 25600.0, &opts).unwrap();
    assert_eq!(h.segments, 5);
    let f = h.frequencies();
    let coh = h.coherence();
    let res = resonances(
        &f,
        &h.h1(),
        &coh,
        &PeakOptions {
            max_peaks: 10,
            f_min_hz: 20.0,
            ..Default::default()
        },
    );
    for r in &res {
        eprintln!(
            "{:8.1} Hz  |H1| {:9.3}  Q {:?}  coherence {:.5}",
            r.frequency_hz, r.magnitude, r.q, r.coherence
        );
    }
    for target in [900.0, 2640.0, 5969.0] {
        // "near": within 1% of the SOURCE.md frequency, which is given to the nearest line.
        let r = res
            .iter()
            .find(|r| (r.frequency_hz - target).abs() < 0.01 * target);
        let r = r.unwrap_or_else(|| panic!("no resonance near {target} Hz in {res:?}"));
        assert!(
            r.coherence > 0.99,
            "coherence {} at {}",
            r.coherence,
            r.frequency_hz
        );
        assert!(r.q.is_some_and(|q| q > 1.0), "{r:?}");
    }
    let mut band: Vec<f64> = f
        .iter()
        .zip(&coh)
        .filter(|(f, _)| (20.0..=2000.0).contains(*f))
        .map(|(_, c)| *c)
        .collect();
    band.sort_by(|a, b| a.total_cmp(b));
    let median = band[band.len() / 2];
    eprintln!("median coherence 20-2000 Hz: {median:.5}");
    // SOURCE.md: 0.999; three decimals as stated.
    assert!((median - 0.999).abs() < 0.0005, "{median}");
}

#[test]
fn the_same_channel_as_input_and_output_is_an_error_naming_it() {
    let log = dir().join("impact_1.csv");
    let (code, out, err) = crate::common::run_text(
        &[
            "frf",
            log.to_str().unwrap(),
            "--input",
            "force",
            "--output",
            "force",
        ],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("`force`") && err.contains("both --input and --output"),
        "{err}"
    );
}

/// `frf` on the five hits with `extra` flags: the JSON document.
fn impact_frf_json(extra: &[&str]) -> serde_json::Value {
    let logs: Vec<String> = (1..=5)
        .map(|i| dir().join(format!("impact_{i}.csv")).display().to_string())
        .collect();
    let mut args: Vec<&str> = vec!["frf"];
    args.extend(logs.iter().map(String::as_str));
    args.extend(["--input", "force", "--output", "acceleration", "--json"]);
    args.extend(extra);
    let (code, out, err) = crate::common::run_text(&args, None);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

#[test]
fn impact_logs_with_default_options_get_the_impact_options_and_coherent_peaks() {
    let v = impact_frf_json(&[]);
    // Detected and said: one segment per hit (SOURCE.md: 1 s records at 25600 Hz, a force
    // pulse about 7 samples wide), no window, no detrend.
    assert_eq!(v["impact"]["detected"], true, "{v}");
    assert_eq!(v["impact"]["pulses"].as_array().unwrap().len(), 5);
    for p in v["impact"]["pulses"].as_array().unwrap() {
        let w = p["width_s"].as_f64().unwrap() * 25600.0;
        assert!((2.0..=16.0).contains(&w), "pulse of {w} samples");
    }
    assert_eq!(v["nperseg"], 25600);
    assert_eq!(v["window"], "boxcar");
    assert_eq!(v["detrend"], "none");
    assert_eq!(v["segments"], 5);
    assert!(
        v["notes"][0]
            .as_str()
            .unwrap()
            .contains("impact input detected")
    );
    // Every reported peak is coherent (SOURCE.md: 0.999 median) and inside the excited band.
    let (lo, hi) = (
        v["screen"]["searched_hz"][0].as_f64().unwrap(),
        v["screen"]["searched_hz"][1].as_f64().unwrap(),
    );
    let peaks = v["peaks"].as_array().unwrap();
    assert_eq!(peaks.len(), 10);
    for p in peaks {
        let (f, c) = (
            p["frequency_hz"].as_f64().unwrap(),
            p["coherence"].as_f64().unwrap(),
        );
        assert!(c >= 0.99 && (lo..=hi).contains(&f), "{p}");
    }
    for target in [900.0, 2640.0, 5969.0] {
        assert!(
            peaks
                .iter()
                .any(|p| (p["frequency_hz"].as_f64().unwrap() - target).abs() < 0.01 * target),
            "no peak near {target} Hz"
        );
    }
    // The reader's decisions are recorded per log.
    assert_eq!(v["ingest"].as_array().unwrap().len(), 5);
    assert_eq!(v["ingest"][0]["record"]["delimiter"], "comma");
}

#[test]
fn incoherent_peaks_are_left_out_and_listed() {
    // Hann segments of 8192 samples on the hits average the pulse with segments of sensor
    // noise: the coherence at the peaks falls to 0.02-0.15. Over a band given by hand, every
    // such peak is left out of `peaks` and listed in `screen.screened_out`.
    let v = impact_frf_json(&["--window", "hann", "--fmin", "20", "--fmax", "7000"]);
    assert!(v["impact"].is_null(), "Welch flags given: no switch");
    assert_eq!(v["peaks"], serde_json::json!([]));
    let out = v["screen"]["screened_out"].as_array().unwrap();
    assert!(!out.is_empty());
    for p in out {
        assert!(p["coherence"].as_f64().unwrap() < 0.8, "{p}");
    }
    let notes = v["notes"].to_string();
    assert!(notes.contains("looks like an impact") && notes.contains("left out for coherence"));
}

/// Writes `time_s,force,response` like a ground-vibration sweep: the force excites 2-15 Hz
/// (a multisine at 0.05 Hz spacing, random phases, plus sensor noise everywhere), the
/// response is an SDOF (fn 8 Hz, ζ 0.02, H = 1/(1 - r² + 2iζr)) to it plus a 40 Hz
/// disturbance that the force does not drive, plus noise.
fn write_band_limited_log(path: &std::path::Path, seed: u64) {
    use rand::{RngExt, SeedableRng};
    let (fs, n, fnat, zeta) = (200.0, 80_000usize, 8.0, 0.02);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let tones: Vec<(f64, f64, f64, f64)> = (0..=260)
        .map(|k| {
            let f = 2.0 + 0.05 * k as f64;
            let r = f / fnat;
            let h = realfft::num_complex::Complex64::new(1.0 - r * r, 2.0 * zeta * r).inv();
            (
                f,
                rng.random::<f64>() * std::f64::consts::TAU,
                h.norm(),
                h.arg(),
            )
        })
        .collect();
    let mut out = String::from("time_s,force,response\n");
    for i in 0..n {
        let t = i as f64 / fs;
        let (mut x, mut y) = (0.0, 0.0);
        for &(f, ph, mag, arg) in &tones {
            let w = std::f64::consts::TAU * f * t;
            x += (w + ph).sin();
            y += mag * (w + ph + arg).sin();
        }
        x += 0.01 * crate::common::gauss(&mut rng);
        y +=
            30.0 * (std::f64::consts::TAU * 40.0 * t).sin() + 0.05 * crate::common::gauss(&mut rng);
        out.push_str(&format!("{t:.6},{x:.9e},{y:.9e}\n"));
    }
    std::fs::write(path, out).unwrap();
}

/// `satqual frf LOG --input force --output response --json EXTRA`, which must succeed: its
/// JSON and its stderr.
fn frf_force_to_response(log: &std::path::Path, extra: &[&str]) -> (serde_json::Value, String) {
    let mut a = vec![
        "frf",
        log.to_str().unwrap(),
        "--input",
        "force",
        "--output",
        "response",
        "--json",
    ];
    a.extend(extra);
    let (code, out, err) = crate::common::run_text(&a, None);
    assert_eq!(code, 0, "{err}");
    (serde_json::from_str(&out).unwrap(), err)
}

#[test]
fn resonances_are_searched_only_where_the_input_excites_and_coheres() {
    let d = crate::common::temp_dir("sig-frf-band");
    let log = d.join("gvt.csv");
    write_band_limited_log(&log, 7);
    let frf = |extra: &[&str]| frf_force_to_response(&log, extra);
    let freqs = |v: &serde_json::Value, key: &str| -> Vec<f64> {
        v.pointer(key)
            .unwrap()
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["frequency_hz"].as_f64().unwrap())
            .collect()
    };
    // Default: the band is read from the force autospectrum (2-15 Hz, ± a line), and the one
    // mode is the SDOF's: |H| peaks at fn·√(1 - 2ζ²) = 7.9968 Hz; 0.5% covers the 0.024 Hz
    // lines and the parabolic interpolation.
    let (v, err) = frf(&[]);
    let band = &v["screen"]["excited_band"];
    assert!(
        (band["lo_hz"].as_f64().unwrap() - 2.0).abs() < 0.1,
        "{band}"
    );
    assert!(
        (band["hi_hz"].as_f64().unwrap() - 15.0).abs() < 0.1,
        "{band}"
    );
    assert!(err.contains("resonances searched over"), "{err}");
    let peaks = freqs(&v, "/peaks");
    let exact = 8.0 * (1.0f64 - 2.0 * 0.02 * 0.02).sqrt();
    assert!(peaks.iter().all(|f| (1.9..=15.1).contains(f)), "{peaks:?}");
    assert!(
        peaks.iter().any(|f| (f - exact).abs() < 0.005 * exact),
        "{peaks:?}"
    );
    // Over a band given by hand that holds the 40 Hz disturbance, its peak of |H1| (noise over
    // noise) is found but left out for its coherence and listed.
    let (v, _) = frf(&["--fmin", "1", "--fmax", "60"]);
    assert!(
        freqs(&v, "/peaks").iter().all(|f| (f - 40.0).abs() > 0.5),
        "{v}"
    );
    let out = freqs(&v, "/screen/screened_out");
    assert!(out.iter().any(|f| (f - 40.0).abs() < 0.1), "{out:?}");
    // Without the coherence screen the disturbance is reported as a resonance: the screen,
    // not luck, keeps it out.
    let (v, _) = frf(&["--fmin", "1", "--fmax", "60", "--min-coherence", "0"]);
    assert!(
        freqs(&v, "/peaks").iter().any(|f| (f - 40.0).abs() < 0.1),
        "{v}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// A Q the line spacing cannot resolve is flagged. The SDOF of `write_band_limited_log` (fn 8 Hz,
/// ζ 0.02: half-power band 2ζ·fn = 0.32 Hz, Q = 1/(2ζ) = 25) read with the default 0.0244 Hz
/// lines (13 across the band) gives Q within 5 % of 25 (window broadening and noise) and no
/// note; with 0.195 Hz lines (`--nperseg 1024`, 1.6 lines across the band) the note names
/// the resonance and says the Q reads low, and it does (about 15).
#[test]
fn a_q_the_lines_cannot_resolve_is_flagged() {
    let d = crate::common::temp_dir("sig-frf-q-lines");
    let log = d.join("gvt.csv");
    write_band_limited_log(&log, 11);
    let sdof = |extra: &[&str]| {
        let (v, _) = frf_force_to_response(&log, extra);
        let peak = v["peaks"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| (p["frequency_hz"].as_f64().unwrap() - 8.0).abs() < 0.2)
            .unwrap_or_else(|| panic!("no 8 Hz peak: {v}"))
            .clone();
        (peak["q"].as_f64().unwrap(), v["notes"].to_string())
    };
    let (q, notes) = sdof(&[]);
    assert!((q - 25.0).abs() < 0.05 * 25.0, "Q {q}");
    assert!(!notes.contains("half-power band"), "{notes}");
    // At this resolution the peak's coherence also drops below the default screen (0.75:
    // the bias of a band narrower than the window), which is not what is tested here.
    let (q, notes) = sdof(&["--nperseg", "1024", "--min-coherence", "0"]);
    assert!(q < 25.0, "Q {q}");
    assert!(
        notes.contains("resonance at 7.9") && notes.contains("the Q reads low"),
        "{notes}"
    );
}

#[test]
fn a_log_shorter_than_the_default_segment_gets_the_psd_rule() {
    // 2000 samples: the largest power of two leaving four segment lengths is 256
    // (`welch::short_log_nperseg`, the rule `psd` applies), said in a note; a segment the
    // user asks for is kept, and one longer than the log is an error.
    let log = crate::common::repo_path("data/format-refs/wav/wave_pcm16_2ch.wav");
    let log = log.to_str().unwrap();
    let args = ["frf", log, "--input", "ch1", "--output", "ch2", "--json"];
    let (code, out, err) = crate::common::run_text(&args, None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["nperseg"], 256);
    assert!(err.contains("the shortest log has 2000 samples"), "{err}");
    let mut long = args.to_vec();
    long.extend(["--nperseg", "4096"]);
    let (code, _, err) = crate::common::run_text(&long, None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("longer than the signal (2000 samples)"),
        "{err}"
    );
}
