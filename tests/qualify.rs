//! `satqual qualify` end to end: exit codes, the report folder, skipped analyses,
//! determinism across thread counts, and the rendered HTML.

use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    crate::common::temp_dir(&format!("q-{name}"))
}

fn qualify(scene: &Path, out: &Path, threads: Option<&str>) -> std::process::Output {
    let mut c = crate::common::satqual();
    c.args([
        "qualify",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().unwrap()
}

#[test]
fn modal_only_scene_skips_the_rest_and_says_so() {
    let d = tmp("modal-only");
    let out = d.join("report");
    // FV5: first modes 42.6 Hz (y, z) and 125 Hz (x): every stiffness gate passes.
    let o = qualify(
        Path::new("test-specs/verification/nafems-fv5.toml"),
        &out,
        None,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(v["ran"], serde_json::json!(["modal"]));
    let skipped: Vec<String> = v["skipped"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["analysis"].as_str().unwrap().to_string())
        .collect();
    for a in ["sine", "random", "separation", "test data"] {
        assert!(
            skipped.iter().any(|s| s == a),
            "{a} not listed as skipped: {skipped:?}"
        );
    }
    assert!(v.get("separation").is_none());
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("skipped **separation**"),
        "the report says what was skipped"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("<svg") && html.contains("Verdict"));
    // Self-contained: no external resources (the SVG namespace URI is not a fetch).
    assert!(!html.contains("src=\"http") && !html.contains("href=\"http"));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn failed_gate_exits_1_names_it_and_still_writes_the_report() {
    // FV4 against a 10 Hz lateral minimum: its first modes are at 1.72 Hz, so the stiffness
    // gates must fail, with a negative margin of 1.723/10 − 1 = −82.8% laterally; the axial
    // gate, 1.727/25 − 1 = −93.1%, has the smallest margin and governs the family.
    let d = tmp("fail");
    let text = std::fs::read_to_string("test-specs/verification/nafems-fv4.toml").unwrap();
    let scene = d.join("fv4.toml");
    std::fs::write(&scene, text).unwrap();
    let out = d.join("report");
    let mut c = crate::common::satqual();
    let o = c
        .args([
            "qualify",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("frequency: FAIL")
            && stdout.contains("governing first axial frequency")
            && stdout.contains("margin -93."),
        "{stdout}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(v["pass"], false);
    let failed: Vec<&serde_json::Value> = v["gates"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|g| g["pass"] == false)
        .collect();
    assert!(!failed.is_empty());
    for g in failed {
        assert!(
            g["margin"].as_f64().unwrap() < 0.0
                && g["source"].as_str().unwrap().contains("launcher")
        );
    }
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("class=\"fail\""), "a failed gate is marked");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn results_json_is_byte_identical_across_thread_counts() {
    // The reference scene: modal, separation and a parallel Monte Carlo, cut to 12 runs (its
    // 59 take ~20 s of CPU on one thread; the golden output runs them all).
    let d = tmp("det");
    let text = std::fs::read_to_string("test-specs/paper-stack.toml").unwrap();
    assert!(text.contains("\nruns = 59\n"));
    let scene = d.join("paper-stack.toml");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(&scene, text.replace("\nruns = 59\n", "\nruns = 12\n")).unwrap();
    // The test model its [calibration] names, beside it.
    std::fs::copy("test-specs/shaker-2sat.toml", d.join("shaker-2sat.toml")).unwrap();
    let (a, b) = (d.join("a"), d.join("b"));
    let oa = qualify(&scene, &a, Some("1"));
    let ob = qualify(&scene, &b, Some("2"));
    assert_eq!(oa.status.code(), ob.status.code());
    assert!(
        matches!(oa.status.code(), Some(0) | Some(1)),
        "{}",
        String::from_utf8_lossy(&oa.stderr)
    );
    let ja = std::fs::read(a.join("results.json")).unwrap();
    let jb = std::fs::read(b.join("results.json")).unwrap();
    assert!(ja == jb, "results.json differs between 1 and 2 threads");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_scene_exits_2_and_leaves_no_report() {
    let d = tmp("bad");
    let scene = d.join("bad.toml");
    std::fs::write(&scene, "[stack]\nsatellites = 0\n").unwrap();
    let out = d.join("report");
    let o = qualify(&scene, &out, None);
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists(), "nothing half-written");
    let leftovers: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name())
        .collect();
    assert_eq!(leftovers.len(), 1, "only the scene remains: {leftovers:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn report_renders_in_headless_chromium() {
    let Some(chromium) = [
        "/usr/bin/chromium",
        "/usr/bin/chromium-browser",
        "/usr/bin/google-chrome",
    ]
    .iter()
    .find(|p| Path::new(p).exists()) else {
        println!(
            "SKIPPED report_renders_in_headless_chromium: no Chromium installed (apt-get install chromium)"
        );
        return;
    };
    let d = tmp("chromium");
    let out = d.join("report");
    let o = qualify(
        Path::new("test-specs/verification/nafems-fv4.toml"),
        &out,
        None,
    );
    assert!(o.status.code().is_some());
    let png = d.join("page.png");
    let profile = d.join("profile");
    let r = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            &format!("--user-data-dir={}", profile.display()),
            &format!("--screenshot={}", png.display()),
            "--window-size=1200,3000",
            &format!(
                "file://{}",
                std::fs::canonicalize(out.join("report.html"))
                    .unwrap()
                    .display()
            ),
        ])
        .output()
        .unwrap();
    let bytes = std::fs::read(&png)
        .unwrap_or_else(|_| panic!("no screenshot: {}", String::from_utf8_lossy(&r.stderr)));
    assert_eq!(&bytes[1..4], b"PNG");
    // The page has its plots: count <svg> elements in the DOM as Chromium parsed it.
    let dom = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            &format!("--user-data-dir={}", profile.display()),
            "--dump-dom",
            &format!(
                "file://{}",
                std::fs::canonicalize(out.join("report.html"))
                    .unwrap()
                    .display()
            ),
        ])
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&dom.stdout);
    assert!(
        dom.matches("<svg").count() >= 1,
        "no plot in the rendered page"
    );
    assert!(
        bytes.len() > 20_000,
        "the screenshot is nearly empty ({} bytes)",
        bytes.len()
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn reduced_preload_gaps_and_the_gate_says_so() {
    // The 2-satellite shaker scene with its preload cut from 45 kN to 4.5 kN: the sine z
    // joint tension exceeds the minimum preload, so a gapping gate must fail with a negative
    // margin, the run exit 1, and the report still be written.
    let d = tmp("gap");
    let text = std::fs::read_to_string("test-specs/shaker-2sat.toml").unwrap();
    assert!(text.contains("preload_total_n = 45000.0"));
    let scene = d.join("low-preload.toml");
    std::fs::write(
        &scene,
        text.replacen("preload_total_n = 45000.0", "preload_total_n = 4500.0", 1),
    )
    .unwrap();
    let out = d.join("report");
    let o = crate::common::satqual()
        .args([
            "qualify",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("lock integrity: FAIL") && stdout.contains("gapping: gapping interface"),
        "{stdout}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let gap: Vec<&serde_json::Value> = v["gates"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|g| g["name"].as_str().unwrap().starts_with("gapping") && g["pass"] == false)
        .collect();
    assert!(!gap.is_empty());
    assert!(
        gap.iter().all(|g| g["margin"].as_f64().unwrap() < 0.0
            && g["source"].as_str().unwrap().contains("5020"))
    );
    assert!(out.join("report.html").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn test_data_scene_gates_tolerance_and_signature() {
    // Third-party logs (data/realdata): the controller PSD within its fitted profile's abort
    // band, Grms within 10% (1.07% measured by the signal tests), and the same structure hit
    // twice, so every signature mode passes.
    let d = tmp("testdata");
    let out = d.join("report");
    let o = qualify(Path::new("test-specs/test-data.toml"), &out, None);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(v["ran"], serde_json::json!(["test data"]));
    let sig = v["test_data"]["signature"]["modes"].as_array().unwrap();
    assert!(sig.len() >= 3);
    // The 5969 Hz mode of the SOURCE.md (1 Hz lines, so within 5 Hz) is matched with a
    // negligible shift: the same structure.
    assert!(
        sig.iter()
            .any(|m| (m["before_hz"].as_f64().unwrap() - 5969.0).abs() < 5.0
                && m["shift_pct"].as_f64().unwrap().abs() < 0.1)
    );
    let names: Vec<&str> = v["gates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["name"].as_str().unwrap())
        .collect();
    assert!(names.iter().any(|n| n.contains("abort")) && names.iter().any(|n| n.contains("Grms")));
    assert!(out.join("plots/test_1_psd.svg").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn corrupted_log_exits_2_naming_file_and_row_and_writes_nothing() {
    let d = tmp("corrupt");
    std::fs::create_dir_all(d.join("logs")).unwrap();
    let good = std::fs::read_to_string("data/realdata/pyfrf-impact/impact_1.csv").unwrap();
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    lines[1000] = "0.0390,NaN,0.1".into(); // line 1001 of the file
    std::fs::write(d.join("logs/before.csv"), lines.join("\n") + "\n").unwrap();
    std::fs::copy(
        "data/realdata/pyfrf-impact/impact_2.csv",
        d.join("logs/after.csv"),
    )
    .unwrap();
    let scene = std::fs::read_to_string("test-specs/test-data.toml")
        .unwrap()
        .replace(
            "../data/realdata/pyfrf-impact/impact_1.csv",
            "logs/before.csv",
        )
        .replace(
            "../data/realdata/pyfrf-impact/impact_2.csv",
            "logs/after.csv",
        )
        .replace(
            "../data/realdata/",
            &format!("{}/data/realdata/", env!("CARGO_MANIFEST_DIR")),
        );
    std::fs::write(d.join("scene.toml"), scene).unwrap();
    let out = d.join("report");
    let o = qualify(&d.join("scene.toml"), &out, None);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("before.csv") && err.contains("1001"), "{err}");
    assert!(!out.exists(), "no partial report");
    assert!(
        std::fs::read_dir(&d).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .starts_with('.'))
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// The first screen of the paper stack's report, as Chromium lays it out at 1400 × 900 px:
/// the verdict and the governing-gates table (one row per family) end above 900 px. A script
/// added to a copy of the page measures them with getBoundingClientRect and writes the numbers
/// into the DOM, which `--dump-dom` prints. Also takes the screenshot at that size; with
/// `SATQUAL_SCREENSHOT=path` it is kept there (docs/img/report-first-screen.png is made so).
#[test]
fn first_screen_holds_the_verdict_and_the_governing_gates() {
    let Some(chromium) = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .iter()
        .find(|p| Path::new(p).exists())
    else {
        println!(
            "SKIPPED first_screen_holds_the_verdict_and_the_governing_gates: no Chromium installed (apt-get install chromium)"
        );
        return;
    };
    let d = tmp("first-screen");
    let out = d.join("report");
    let o = qualify(Path::new("test-specs/paper-stack.toml"), &out, None);
    assert_eq!(
        o.status.code(),
        Some(1),
        "the reference stack fails its gates"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    const MEASURE: &str = "<script>addEventListener('load',()=>{\
        const v=document.querySelector('.verdict').getBoundingClientRect();\
        const t=[...document.querySelectorAll('table')].find(t=>t.innerText.includes('governing gate'));\
        const r=t.getBoundingClientRect();\
        document.body.setAttribute('data-layout',[v.top,v.bottom,r.top,r.bottom,t.rows.length].join(' '));});\
        </script></body>";
    let probe = d.join("probe.html");
    std::fs::write(&probe, html.replace("</body>", MEASURE)).unwrap();
    let run = |extra: &[String], page: &Path| {
        let mut c = Command::new(chromium);
        c.args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--no-first-run",
            "--window-size=1400,900",
            &format!("--user-data-dir={}", d.join("profile").display()),
        ]);
        c.args(extra).arg(format!(
            "file://{}",
            std::fs::canonicalize(page).unwrap().display()
        ));
        c.output().unwrap()
    };
    let dom = run(&["--dump-dom".into()], &probe);
    let dom = String::from_utf8_lossy(&dom.stdout);
    let layout = dom
        .split("data-layout=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or_else(|| panic!("no layout measured: {dom:.400}"));
    let n: Vec<f64> = layout.split(' ').map(|x| x.parse().unwrap()).collect();
    let (verdict_bottom, table_bottom, rows) = (n[1], n[3], n[4]);
    assert!(
        verdict_bottom < 900.0,
        "verdict ends at {verdict_bottom} px"
    );
    assert!(
        table_bottom < 900.0,
        "governing gates end at {table_bottom} px"
    );
    // Header + one row per family the paper stack gates: frequency, buckling, lock
    // integrity, bar strength, separation.
    assert_eq!(rows, 6.0, "{layout}");
    let png = d.join("first-screen.png");
    run(
        &[format!("--screenshot={}", png.display())],
        &out.join("report.html"),
    );
    let bytes = std::fs::read(&png).expect("a screenshot");
    assert_eq!(&bytes[1..4], b"PNG");
    if let Some(keep) = std::env::var_os("SATQUAL_SCREENSHOT") {
        std::fs::copy(&png, keep).unwrap();
    }
}

#[test]
fn results_and_report_carry_the_input_environments_as_applied() {
    // The shaker scene asks for the GEVS component table at qualification level with the GEVS
    // weight reduction; its model weighs 270 kg, above the 182 kg at which GEVS holds the
    // spectrum: plateau 0.16·22.7/182 = 0.019956 g²/Hz, 0.01 g²/Hz at 20 and 2000 Hz,
    // 10·log10(182/22.7) = 9.0405 dB, and 5.6418 Grms by the log-log integral of those four
    // points (by hand); 2 min per axis (GEVS qualification duration).
    let d = tmp("env");
    let out = d.join("report");
    let o = qualify(Path::new("test-specs/shaker-2sat.toml"), &out, None);
    assert!(o.status.code() == Some(0) || o.status.code() == Some(1));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let r = &v["environments"]["random"];
    assert_eq!(r["environment"], "gevs-component");
    assert_eq!(r["level"], "qualification");
    assert_eq!(r["duration_s"], 120.0);
    assert!((r["grms"].as_f64().unwrap() - 5.6418).abs() < 1e-4, "{r}");
    let w = &r["weight_reduction"];
    assert_eq!(w["mass_used_kg"], 182.0);
    assert!((w["reduction_db"].as_f64().unwrap() - 9.0405).abs() < 1e-4);
    assert!((r["profile"][1][1].as_f64().unwrap() - 0.16 * 22.7 / 182.0).abs() < 1e-15);
    assert!(r["source"].as_str().unwrap().contains("GSFC-STD-7000A"));
    let s = &v["environments"]["sine"];
    assert_eq!(s["segments"].as_array().unwrap().len(), 2);
    assert!(s["source"].as_str().unwrap().contains("§5.1.1"));
    // 5–100 Hz is log2(20) = 4.3219 octaves: 129.66 s at the qualification 2 oct/min.
    assert_eq!(s["sweep_rate_oct_min"], 2.0);
    assert!((s["duration_s"].as_f64().unwrap() - 129.658).abs() < 1e-3);
    // Every slip gate names the path that carries the joint's shear.
    for g in v["gates"].as_array().unwrap() {
        if g["name"].as_str().unwrap().starts_with("slip") {
            assert!(
                g["source"].as_str().unwrap().starts_with("load path: "),
                "{g}"
            );
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("## Input environments") && md.contains("5.64 Grms"),
        "{md}"
    );
    assert!(out.join("plots/environment_random.svg").exists());
    assert!(out.join("curves/environment_sine.csv").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// The shock scene with `from` replaced by `to`, written to `d`, qualified; (exit code, the
/// results and stderr).
fn qualify_shock(d: &Path, from: &str, to: &str) -> (Option<i32>, serde_json::Value, String) {
    let scene = std::fs::read_to_string("test-specs/test-data-shock.toml")
        .unwrap()
        .replace(from, to)
        .replace(
            "../data/realdata/",
            &format!("{}/data/realdata/", env!("CARGO_MANIFEST_DIR")),
        );
    std::fs::write(d.join("scene.toml"), scene).unwrap();
    let out = d.join("report");
    let o = qualify(&d.join("scene.toml"), &out, None);
    let v = std::fs::read_to_string(out.join("results.json"))
        .map_or(serde_json::Value::Null, |t| {
            serde_json::from_str(&t).unwrap()
        });
    (
        o.status.code(),
        v,
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

#[test]
fn shock_log_is_gated_against_the_scene_shock_spec() {
    // The third-party drop shock (data/realdata/hrshm-pcb-shock) against a spec its SRS
    // follows: the record's maximax SRS at Q = 10 (62.97 g at 100 Hz, 710.7 g at 2263 Hz,
    // 487.3 g at 9051 Hz, `satqual srs` ≡ scipy lfilter to 1e-9 in signal_srs) lies within
    // 2 dB of 60 g at 100 Hz rising to 600 g at 1 kHz, flat to 10 kHz: no point outside ±6 dB.
    let d = tmp("shock");
    let out = d.join("report");
    let o = qualify(Path::new("test-specs/test-data-shock.toml"), &out, None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let gates: Vec<&serde_json::Value> = v["gates"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|g| g["name"].as_str().unwrap().contains("SRS"))
        .collect();
    assert_eq!(gates.len(), 2);
    for g in &gates {
        assert_eq!(
            (g["group"].as_str(), g["unit"].as_str()),
            (Some("test_data"), Some("%"))
        );
        assert!(g["source"].as_str().unwrap().contains("NASA-STD-7003A"));
        assert!(g["source"].as_str().unwrap().contains("MIL-STD-810H"));
        assert_eq!(
            (g["value"].as_f64(), g["pass"].as_bool()),
            (Some(0.0), Some(true))
        );
    }
    let c = &v["test_data"]["logs"][0]["shock"][0];
    // Reference: the peak |a − mean| of the record, 461.81 g at 0.78 ms (SOURCE.md: 485.97 g
    // raw at t = 0.78 ms; the mean of the 5 ms record is removed first).
    assert!((c["peak_time_s"].as_f64().unwrap() - 7.8e-4).abs() < 2.1e-5);
    // 1/6 octave from 100 Hz to 10 kHz: 40 points (the grid stops below 10 kHz·2^(1/12)).
    assert_eq!(c["check"]["points"].as_array().unwrap().len(), 40);
    assert!(c["check"]["worst_db"].as_f64().unwrap().abs() < 2.0);
    assert!(out.join("plots/test_1_srs.svg").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn shock_log_above_its_spec_fails_the_gate_and_without_spec_is_refused() {
    let d = tmp("shock-fail");
    // The spec lowered by 20 dB (a factor 10): every point is more than +6 dB above it.
    let (code, v, err) = qualify_shock(
        &d,
        "srs_g = [[100.0, 60.0], [1000.0, 600.0], [10000.0, 600.0]]",
        "srs_g = [[100.0, 6.0], [1000.0, 60.0], [10000.0, 60.0]]",
    );
    assert_eq!(code, Some(1), "{err}");
    let above = v["gates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|g| g["name"].as_str().unwrap().contains("above +6 dB"))
        .unwrap();
    assert_eq!(
        (above["value"].as_f64(), above["pass"].as_bool()),
        (Some(100.0), Some(false))
    );
    // No [shock]: the log cannot be checked, and the error names the key.
    let (code, _, err) = qualify_shock(&d, "[shock]", "[unused]");
    assert_eq!(code, Some(2), "{err}");
    let (code, _, err) = qualify_shock(
        &d,
        "[shock]\nsrs_g = [[100.0, 60.0], [1000.0, 600.0], [10000.0, 600.0]]\nq = 10.0\nper_octave = 6\nupper_db = 6.0\nlower_db = 6.0\nallowed_fraction = 0.0\n",
        "",
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("kind") && err.contains("[shock]"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The test-data scene with `from` replaced by `to` (log paths made absolute), qualified:
/// (exit code, stderr).
fn qualify_test_data(name: &str, from: &str, to: &str) -> (Option<i32>, String) {
    let d = tmp(name);
    let text = std::fs::read_to_string("test-specs/test-data.toml").unwrap();
    assert!(text.contains(from), "{from}");
    let scene = text.replacen(from, to, 1).replace(
        "../data/realdata/",
        &format!("{}/data/realdata/", env!("CARGO_MANIFEST_DIR")),
    );
    std::fs::write(d.join("scene.toml"), scene).unwrap();
    let o = qualify(&d.join("scene.toml"), &d.join("report"), None);
    let _ = std::fs::remove_dir_all(&d);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A UFF58 PSD file's control channel is chosen by name like a CSV's: a name the file does not
/// hold is refused with the names it does, not replaced by its first record. Two references
/// for one log, or a table out of order, are refused at their key.
#[test]
fn test_log_control_and_reference_profile_are_checked_not_guessed() {
    // (case, text replaced, replacement, every part the error must hold)
    let cases: [(&str, &str, &str, &[&str]); 5] = [
        (
            "control-name",
            "control = \"Channel 1\"",
            "control = \"Channel 9\"",
            &[
                "key `test_log[0].control`",
                "channel `Channel 9` is not in",
                "(its channels: Channel 1)",
            ],
        ),
        (
            "two-profiles",
            "control = \"Channel 1\"",
            "control = \"Channel 1\"\nprofile = \"random\"",
            &["test_log[0].profile", "give one of them"],
        ),
        (
            // impact_1.csv's time column gives 25600 Hz (its SOURCE.md; times written to 8
            // decimals, so 25599.999936 over the record): a scene rate that contradicts it is
            // the scene's error, named at its key with the scene's cure.
            "fs-against-time-column",
            "kind = \"signature-before\"",
            "kind = \"signature-before\"\nfs_hz = 20000.0",
            &[
                "key `test_log[1].fs_hz`",
                "fs_hz 20000 Hz disagrees with the time column",
                "which gives 25599.99",
                "remove fs_hz: the file states its own rate",
            ],
        ),
        (
            // A rate past any recorder's (the plausible range of docs/robustness.md) is a
            // unit slip of the scene, refused at its line before any log is read.
            "fs-implausible",
            "kind = \"signature-before\"",
            "kind = \"signature-before\"\nfs_hz = 1e15",
            &[
                "key `test_log[1].fs_hz`",
                "scene.toml:",
                "outside the plausible range [1e-6, 1e9] Hz",
            ],
        ),
        (
            "profile-order",
            "[10.0, 1.45e-4], [25.0",
            "[30.0, 1.45e-4], [25.0",
            &[
                "test_log[0].profile_table[1]",
                "frequencies must increase: 25 Hz follows 30 Hz",
            ],
        ),
    ];
    for (name, from, to, parts) in cases {
        let (code, err) = qualify_test_data(name, from, to);
        assert_eq!(code, Some(2), "{name}: {err}");
        for part in parts {
            assert!(err.contains(part), "{name}: {part:?} not in {err}");
        }
    }
}
