//! `satqual sine` / `satqual random` contract: JSON fields, exit codes, CSV and SVG
//! output, and identical JSON whatever the thread count.

use crate::common::run as satqual;

#[test]
fn sine_json_contract_and_out_dir() {
    let dir = crate::common::temp_dir("sine");
    let out = satqual(
        &[
            "sine",
            "test-specs/shaker-2sat.toml",
            "--axis",
            "z",
            "--json",
            "--out",
            dir.to_str().unwrap(),
        ],
        None,
    );
    let code = out.status.code();
    assert!(
        code == Some(0) || code == Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is JSON");
    let axes = v["axes"].as_array().unwrap();
    assert_eq!(axes.len(), 1);
    assert_eq!(axes[0]["axis"], "z");
    let peaks = axes[0]["peaks"].as_array().unwrap();
    // Stack defaults: sat 1, sat 2, top.
    let names: Vec<&str> = peaks.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["sat 1", "sat 2", "top"]);
    for p in peaks {
        assert!(p["frequency_hz"].as_f64().unwrap() > 5.0);
        assert!(p["acceleration_g"].as_f64().unwrap() > 0.3);
    }
    let ifs = axes[0]["interfaces"].as_array().unwrap();
    assert_eq!(ifs.len(), 8, "2 satellites × 4 column joints");
    for i in ifs {
        assert!(i["name"].as_str().unwrap().starts_with("interface "));
        assert!(i["max_tension_n"].as_f64().unwrap() > 0.0);
        assert!(i["max_shear_n"].is_number());
    }
    let ms = axes[0]["margins"].as_array().unwrap();
    assert!(ms.iter().any(|m| m["kind"] == "gapping"));
    assert!(ms.iter().any(|m| m["kind"] == "bar yield"));
    let pass = ms.iter().all(|m| m["pass"].as_bool().unwrap());
    assert_eq!(v["pass"].as_bool().unwrap(), pass);
    assert_eq!(
        code,
        Some(if pass { 0 } else { 1 }),
        "exit code follows the margins"
    );
    // The human summary went to stderr.
    assert!(String::from_utf8_lossy(&out.stderr).contains("lock integrity"));
    let csv = std::fs::read_to_string(dir.join("sine-z.csv")).unwrap();
    assert!(csv.starts_with("frequency_hz,input_g,\"sat 1 [g]\""));
    let svg = std::fs::read_to_string(dir.join("sine-z.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("polyline"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn random_json_contract_and_out_dir() {
    let dir = crate::common::temp_dir("random");
    let out = satqual(
        &[
            "random",
            "test-specs/verification/sdof-base.toml",
            "--json",
            "--out",
            dir.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let a = &v["axes"][0];
    assert_eq!(a["axis"], "x");
    // Flat 0.1 g²/Hz over 20–2000 Hz: 14.07 Grms.
    assert!((a["input_grms"].as_f64().unwrap() - (0.1f64 * 1980.0).sqrt()).abs() < 1e-9);
    let r = &a["responses"][0];
    assert_eq!(r["name"], "mass");
    let g = r["grms"].as_f64().unwrap();
    assert!((r["three_sigma_g"].as_f64().unwrap() - 3.0 * g).abs() < 1e-12);
    assert!((r["peak_psd_hz"].as_f64().unwrap() - 100.0).abs() < 1.0);
    assert!(r["peak_psd_g2_hz"].as_f64().unwrap() > 10.0);
    assert!(r["miles_grms"].as_f64().unwrap() > 0.0);
    assert_eq!(r["miles"][0]["mode"], 1);
    let csv = std::fs::read_to_string(dir.join("random-x.csv")).unwrap();
    assert!(csv.starts_with("frequency_hz,input_g2_hz,\"mass [g2/Hz]\""));
    let svg = std::fs::read_to_string(dir.join("random-x.svg")).unwrap();
    assert!(
        svg.contains("input profile"),
        "the input is drawn on the random plot"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn json_is_identical_whatever_the_thread_count() {
    for cmd in ["sine", "random"] {
        let a = satqual(
            &[cmd, "test-specs/shaker-2sat.toml", "--axis", "x", "--json"],
            Some("1"),
        );
        let b = satqual(
            &[cmd, "test-specs/shaker-2sat.toml", "--axis", "x", "--json"],
            Some("2"),
        );
        assert!(!a.stdout.is_empty());
        assert_eq!(
            a.stdout, b.stdout,
            "{cmd}: JSON depends on the thread count"
        );
    }
}

/// Limit-level sine segments are raised to the qualification input by 1.25
/// (GSFC-STD-7000A Table 2.4-1); the response is linear in the input, so every peak
/// acceleration and joint load grows by exactly that factor (to rounding, 1e-12) and the peak
/// frequencies stay.
#[test]
fn limit_level_sine_is_raised_by_the_qualification_factor() {
    let dir = crate::common::temp_dir("sine-limit");
    let base =
        std::fs::read_to_string(crate::common::repo_path("test-specs/shaker-2sat.toml")).unwrap();
    let limit = base.replacen("basis = \"test\"", "basis = \"limit\"", 1);
    assert_ne!(limit, base, "the scene names its sine basis");
    let path = dir.join("limit.toml");
    std::fs::write(&path, limit).unwrap();
    let peaks = |scene: &str| {
        let out = satqual(&["sine", scene, "--axis", "x", "--json"], None);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|_| panic!("{}", String::from_utf8_lossy(&out.stderr)));
        let axis = &v["axes"][0];
        let p: Vec<(f64, f64)> = axis["peaks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p["frequency_hz"].as_f64().unwrap(),
                    p["acceleration_g"].as_f64().unwrap(),
                )
            })
            .collect();
        let tension = axis["interfaces"][0]["max_tension_n"].as_f64().unwrap();
        (p, tension)
    };
    let (given, t_given) = peaks("test-specs/shaker-2sat.toml");
    let (raised, t_raised) = peaks(path.to_str().unwrap());
    for (g, r) in given.iter().zip(&raised) {
        assert!((r.0 - g.0).abs() < 1e-9 * g.0, "{g:?} {r:?}");
        assert!((r.1 / g.1 - 1.25).abs() < 1e-12, "{g:?} {r:?}");
    }
    assert!(
        (t_raised / t_given - 1.25).abs() < 1e-12,
        "{t_given} {t_raised}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A per-mode ratio for a mode beyond the ones the response uses (here mode 300 of a model of
/// 306 DOFs whose sine response keeps 98 modes) cannot change the result: the damping line
/// says it is not applied, instead of dropping it unseen.
#[test]
fn a_ratio_for_a_mode_the_response_does_not_use_is_named() {
    let dir = crate::common::temp_dir("unused-ratio");
    let text = std::fs::read_to_string("test-specs/shaker-2sat.toml")
        .unwrap()
        .replace(
            "{ mode = 12, zeta = 0.275264, direction = \"z\" },",
            "{ mode = 12, zeta = 0.275264, direction = \"z\" },\n    { mode = 300, zeta = 0.02 },",
        );
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let (code, stdout, stderr) = crate::common::run_text(
        &["sine", scene.to_str().unwrap(), "--axis", "z", "--json"],
        None,
    );
    assert!(code == 0 || code == 1, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("stdout is JSON");
    let used = v["axes"][0]["modes_used"].as_u64().unwrap();
    assert!(used < 300, "{used}");
    let damping = v["damping"].as_str().unwrap();
    assert!(
        damping.contains(&format!(
            "the ratios given for mode(s) 300 are not applied: the response uses modes 1–{used}"
        )),
        "{damping}"
    );
}
