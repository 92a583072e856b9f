//! The `satqual modal` command-line contract: exit codes, JSON on stdout with the human table
//! on stderr, prestress fields, matrix export, and clean errors for bad input.

use crate::common;

fn satqual(args: &[&str]) -> std::process::Output {
    common::run(args, None)
}

#[test]
fn modal_json_contract() {
    let out = satqual(&["modal", "test-specs/verification/cantilever.toml", "--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is JSON");
    // 20×20 mm × 1 m steel: 3.14 kg.
    assert!((v["total_mass_kg"].as_f64().unwrap() - 0.02 * 0.02 * 1.0 * 7850.0).abs() < 1e-9);
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 10, "[modal] modes = 10");
    assert_eq!(modes[0]["index"], 1);
    assert!((modes[0]["frequency_hz"].as_f64().unwrap() - 16.710).abs() < 0.02);
    for k in ["x", "y", "z", "rx", "ry", "rz"] {
        assert!(
            modes[0]["effective_mass_fraction"][k].is_number(),
            "missing {k}"
        );
    }
    assert!(
        v.get("prestress").is_none(),
        "no static loads, no prestress block"
    );
    // The human table went to stderr.
    assert!(String::from_utf8_lossy(&out.stderr).contains("freq [Hz]"));
}

#[test]
fn modal_human_output_goes_to_stdout_without_json() {
    let out = satqual(&[
        "modal",
        "test-specs/verification/nafems-fv5.toml",
        "--modes",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(
        s.contains("freq [Hz]")
            && s.lines()
                .filter(|l| l.trim_start().starts_with(['1', '2', '3']))
                .count()
                >= 3,
        "{s}"
    );
}

#[test]
fn fmax_override_limits_modes() {
    let out = satqual(&[
        "modal",
        "test-specs/verification/cantilever.toml",
        "--fmax",
        "200",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f: Vec<f64> = v["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["frequency_hz"].as_f64().unwrap())
        .collect();
    assert_eq!(f.len(), 4, "{f:?}");
    assert!(f.iter().all(|x| *x <= 200.0));
}

#[test]
fn prestress_block_and_export() {
    let dir = crate::common::temp_dir("export");
    let scene = dir.join("bar.toml");
    let text = std::fs::read_to_string("test-specs/verification/cantilever.toml")
        .unwrap()
        .replace(
            "[modal]",
            "[[static_load]]\nnode = 2\nforce_n = [-1000.0, 0.0, 0.0]\n\n[modal]",
        );
    std::fs::write(&scene, text).unwrap();
    let out = satqual(&[
        "modal",
        scene.to_str().unwrap(),
        "--json",
        "--export-matrices",
        dir.join("mtx").to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // Cantilever under 1 kN compression: P_cr = π²EI/(4L²) = 6 907.6 N -> λ = 6.9076 (Euler
    // column, clamped-free); 1e-3 with 20 elements.
    let ei = 210e9 * 0.02f64.powi(4) / 12.0;
    let expect = std::f64::consts::PI.powi(2) * ei / 4.0 / 1000.0;
    let lambda = v["prestress"]["buckling_factor"].as_f64().unwrap();
    assert!(
        (lambda - expect).abs() < 1e-3 * expect,
        "{lambda} vs {expect}"
    );
    for f in ["K.mtx", "M.mtx", "KG.mtx", "dofs.csv"] {
        let p = dir.join("mtx").join(f);
        let s = std::fs::read_to_string(&p).unwrap_or_else(|_| panic!("{} missing", p.display()));
        assert!(s.len() > 100);
    }
    let k = std::fs::read_to_string(dir.join("mtx/K.mtx")).unwrap();
    assert!(k.starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    let dofs = std::fs::read_to_string(dir.join("mtx/dofs.csv")).unwrap();
    assert_eq!(dofs.lines().count(), 121, "header + 120 reduced DOFs");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_scene_exits_2_with_location_and_no_panic() {
    let dir = crate::common::temp_dir("bad");
    let scene = dir.join("bad.toml");
    let text = std::fs::read_to_string("test-specs/verification/cantilever.toml")
        .unwrap()
        .replace("density_kg_m3 = 7850", "density_kg_m3 = -7850");
    std::fs::write(&scene, &text).unwrap();
    let out = satqual(&["modal", scene.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let line = text
        .lines()
        .position(|l| l.contains("density_kg_m3"))
        .unwrap()
        + 1;
    assert!(
        err.contains(&format!("bad.toml:{line}:")) && err.contains("material[0].density_kg_m3"),
        "{err}"
    );
    assert!(!err.contains("panicked") && out.stdout.is_empty(), "{err}");
    let out = satqual(&["modal", dir.join("missing.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.toml"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn json_is_deterministic_across_thread_counts() {
    let run = |threads: &str| {
        common::run(
            &["modal", "test-specs/verification/nafems-fv4.toml", "--json"],
            Some(threads),
        )
        .stdout
    };
    assert_eq!(run("1"), run("2"));
}
