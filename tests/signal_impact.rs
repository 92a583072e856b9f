//! Impact tests beyond one hit per record: several hits in one record (cut one segment per
//! hit) and a response that has not died away by the end of its segment (exponential window,
//! its damping taken out of the reported Q).

use serde_json::Value;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn impact_dir() -> PathBuf {
    crate::common::repo_path(satqual::catalogue::logs::IMPACT_DIR)
}

fn frf_json(logs: &[&Path], input: &str, output: &str) -> Value {
    let logs: Vec<String> = logs.iter().map(|p| p.display().to_string()).collect();
    let (input, output) = (format!("--input={input}"), format!("--output={output}"));
    cli_json("frf", &logs, &[&input, &output])
}

/// `satqual CMD LOGS... ARGS... --json`, which must succeed, as JSON.
fn cli_json(cmd: &str, logs: &[String], args: &[&str]) -> Value {
    let mut argv: Vec<&str> = vec![cmd];
    argv.extend(logs.iter().map(String::as_str));
    argv.extend_from_slice(args);
    argv.push("--json");
    let (code, out, err) = crate::common::run_text(&argv, None);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

/// The five 1 s hammer records of data/realdata/pyfrf-impact, each trimmed to start the same
/// number of samples before its pulse (the pulses start at sample 19 or 20) and to one common
/// length, written as five files and as one 5 s record (a roving-hammer acquisition). Five hits
/// are found in the one record, cut at the same samples, and its FRF equals the five-record
/// one. Reference: the same samples analysed as five records (a peer on the same data);
/// tolerance 1e-3 on |H1| at every peak and 1e-3 Hz on its frequency: the force offset removed
/// is the median of each record, over 5 s instead of 1 s, which differ by at most 0.004 N
/// against pulses of 68–89 N.
#[test]
fn several_hits_in_one_record_are_one_segment_each() {
    let dir = crate::common::temp_dir("impact-multi-hit");
    let records: Vec<Vec<(f64, String)>> = (1..=5)
        .map(|i| {
            let src =
                std::fs::read_to_string(impact_dir().join(format!("impact_{i}.csv"))).unwrap();
            src.lines()
                .skip(1)
                .map(|l| {
                    let rest = l.split_once(',').unwrap().1.to_string();
                    (rest.split(',').next().unwrap().parse().unwrap(), rest)
                })
                .collect()
        })
        .collect();
    let starts: Vec<usize> = records
        .iter()
        .map(|r| {
            let force: Vec<f64> = r.iter().map(|x| x.0).collect();
            let hit = satqual::signal::impact::detect_hits(&force, 25600.0).unwrap();
            (hit[0].start_s * 25600.0).round() as usize
        })
        .collect();
    let pre = *starts.iter().min().unwrap();
    let len = starts.iter().map(|s| 25600 - (s - pre)).min().unwrap();
    let mut joined = String::from("time_s,force,acceleration\n");
    let mut row = 0usize;
    let mut five_paths = Vec::new();
    for (i, (r, s)) in records.iter().zip(&starts).enumerate() {
        let mut own = String::from("time_s,force,acceleration\n");
        for (j, (_, rest)) in r[s - pre..s - pre + len].iter().enumerate() {
            own.push_str(&format!("{:.8},{rest}\n", j as f64 / 25600.0));
            joined.push_str(&format!("{:.8},{rest}\n", row as f64 / 25600.0));
            row += 1;
        }
        let path = dir.join(format!("hit_{}.csv", i + 1));
        std::fs::write(&path, own).unwrap();
        five_paths.push(path);
    }
    let joined_path = dir.join("five_hits.csv");
    std::fs::write(&joined_path, joined).unwrap();
    let one = frf_json(&[&joined_path], "force", "acceleration");
    let five_refs: Vec<&Path> = five_paths.iter().map(PathBuf::as_path).collect();
    let five = frf_json(&five_refs, "force", "acceleration");
    let hits = one["impact"]["pulses"].as_array().unwrap();
    assert_eq!(hits.len(), 5, "{}", one["impact"]);
    assert!(hits.iter().all(|h| h["record"] == 0));
    assert_eq!(one["segments"], 5);
    assert_eq!(one["nperseg"], len);
    assert_eq!(five["nperseg"], len);
    let peaks = |v: &Value| -> Vec<(f64, f64)> {
        v["peaks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p["frequency_hz"].as_f64().unwrap(),
                    p["magnitude"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    let (a, b) = (peaks(&one), peaks(&five));
    assert_eq!(a.len(), b.len());
    for ((fa, ma), (fb, mb)) in a.iter().zip(&b) {
        assert!((fa - fb).abs() <= 1e-3, "{fa} vs {fb}");
        assert!((ma - mb).abs() <= 1e-3 * mb, "{ma} vs {mb} at {fa} Hz");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Force and acceleration of an SDOF (m = 1 kg, f_n = 40 Hz, ζ = 0.005) struck by a 2 ms
/// half-sine of 100 N at 0.05 s, fs = 1000 Hz, `seconds` long: RK4 at 20 steps per sample
/// (phase error per period ~ (ω·dt)⁴ ≈ 1e-8).
fn write_sdof_impact(path: &Path, seconds: f64) {
    let (fs, fnat, zeta) = (1000.0, 40.0, 0.005);
    let w = 2.0 * PI * fnat;
    let (k, c) = (w * w, 2.0 * zeta * w);
    let force = |t: f64| {
        let s = t - 0.05;
        if (0.0..0.002).contains(&s) {
            100.0 * (PI * s / 0.002).sin()
        } else {
            0.0
        }
    };
    let acc = |t: f64, x: f64, v: f64| force(t) - c * v - k * x;
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let dt = 1.0 / (fs * 20.0);
    let mut text = String::from("time_s,force,acceleration\n");
    let n = (seconds * fs) as usize;
    for i in 0..n {
        let t0 = i as f64 / fs;
        text.push_str(&format!(
            "{t0:.6},{:.9e},{:.9e}\n",
            force(t0),
            acc(t0, x, v)
        ));
        for j in 0..20 {
            let t = t0 + j as f64 * dt;
            let (k1x, k1v) = (v, acc(t, x, v));
            let (k2x, k2v) = (
                v + 0.5 * dt * k1v,
                acc(t + 0.5 * dt, x + 0.5 * dt * k1x, v + 0.5 * dt * k1v),
            );
            let (k3x, k3v) = (
                v + 0.5 * dt * k2v,
                acc(t + 0.5 * dt, x + 0.5 * dt * k2x, v + 0.5 * dt * k2v),
            );
            let (k4x, k4v) = (v + dt * k3v, acc(t + dt, x + dt * k3x, v + dt * k3v));
            x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
    }
    std::fs::write(path, text).unwrap();
}

/// A 2 s record of the SDOF above ends at e^(−ζω·1.95 s) = 8% of its peak: it leaks, so the
/// exponential window is applied, and the Q it reports has the window's damping taken out.
/// Reference: Q = 1/(2ζ) = 100 (analytic). Tolerance 3%: the half-power points of the
/// windowed peak (ζ + 1/(2π f τ) ≈ 0.0095, a bandwidth of 0.76 Hz) fall between lines 0.5 Hz
/// apart, and the half-power estimate interpolates between them. A 20 s record has decayed
/// (e^(−25) of its peak): no exponential window, Q within the same tolerance.
#[test]
fn a_leaking_response_gets_an_exponential_window_and_its_damping_is_removed() {
    let dir = crate::common::temp_dir("impact-exponential");
    for (seconds, leaks) in [(2.0, true), (20.0, false)] {
        let path = dir.join(format!("sdof_{seconds}.csv"));
        write_sdof_impact(&path, seconds);
        let v = frf_json(&[&path], "force", "acceleration");
        let tau = &v["impact"]["windows"]["exponential_tau_s"];
        assert_eq!(tau.is_f64(), leaks, "{}", v["impact"]);
        let p = &v["peaks"][0];
        let f = p["frequency_hz"].as_f64().unwrap();
        let fd = 40.0 * (1.0f64 - 0.005 * 0.005).sqrt();
        assert!((f - fd).abs() < 0.5, "{f}");
        let q = p["q"].as_f64().unwrap();
        assert!((q - 100.0).abs() < 3.0, "{seconds} s record: Q {q}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn ema_json(log: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["--input=force", "--output=acceleration"];
    args.extend_from_slice(&["--fmin=10", "--fmax=100", "--order-max=20"]);
    args.extend_from_slice(extra);
    cli_json("ema", &[log.display().to_string()], &args)
}

/// `ema` estimates its FRFs as `frf` does: on the leaking 2 s record of the SDOF above the
/// exponential window is applied, and the identified pole has the window's decay 1/τ taken
/// out. Reference: ζ = 0.005, f_n = 40 Hz (analytic). The windowed record is an exact free
/// decay of the shifted pole (force and response carry the same e^(−t/τ)), so LSCF finds it
/// closely (measured: ζ 0.4% low, f_n 7e-5 Hz off): tolerance 2% on ζ and 0.01 Hz on f_n.
/// Uncorrected, the window's 1/(2π·40·τ) would nearly double ζ. With the Welch flags given (Hann, 1 s segments), the window is not applied
/// and a note says the input looks like an impact.
#[test]
fn ema_takes_the_exponential_window_out_of_the_identified_damping() {
    let dir = crate::common::temp_dir("ema-impact-exponential");
    let path = dir.join("sdof_2s.csv");
    write_sdof_impact(&path, 2.0);
    let v = ema_json(&path, &[]);
    let tau = v["impact_windows"]["exponential_tau_s"].as_f64().unwrap();
    let added = 1.0 / (2.0 * PI * 40.0 * tau);
    assert!(added > 0.002, "the window adds ζ {added}");
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 1, "{v}");
    let (f, z) = (
        modes[0]["frequency_hz"].as_f64().unwrap(),
        modes[0]["damping_ratio"].as_f64().unwrap(),
    );
    eprintln!("ema on a leaking SDOF record: f {f} Hz, ζ {z}, window ζ {added}");
    assert!((f - 40.0).abs() < 0.01, "f {f}");
    assert!((z / 0.005 - 1.0).abs() < 0.02, "ζ {z}");
    assert!(
        v["notes"][0]
            .as_str()
            .unwrap()
            .contains("exponential window")
    );
    let given = ema_json(&path, &["--nperseg=1000"]);
    assert!(given["impact_windows"].is_null());
    assert!(
        given["notes"][0]
            .as_str()
            .unwrap()
            .contains("looks like an impact")
    );
    std::fs::remove_dir_all(&dir).ok();
}
