//! `satqual separate` end to end: the JSON contract, CSV output, exit codes.

use crate::common::satqual as bin;
use std::path::Path;

#[test]
fn separate_prints_the_json_contract_and_writes_histories() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = crate::common::temp_dir("sep");
    let o = bin()
        .args(["separate", "test-specs/paper-stack.toml", "--json", "--out"])
        .arg(&out)
        .current_dir(root)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON only");
    let sats = v["satellites"].as_array().unwrap();
    assert_eq!(sats.len(), 6);
    for (i, s) in sats.iter().enumerate() {
        assert_eq!(s["index"].as_u64(), Some(i as u64 + 1));
        for k in [
            "max_speed_m_s",
            "final_speed_m_s",
            "final_rate_deg_s",
            "exit_time_s",
        ] {
            assert!(s[k].as_f64().is_some_and(f64::is_finite), "{k} in {s}");
        }
        assert!(s["contacts"].as_u64().is_some());
    }
    assert!(v["energy"]["relative_residual"].as_f64().unwrap() < 1e-6);
    assert!(v["transitions"]["free_to_collision"].as_u64().unwrap() > 0);
    // The human summary went to stderr.
    assert!(String::from_utf8_lossy(&o.stderr).contains("energy residual"));
    let csv = std::fs::read_to_string(out.join("satellite-6.csv")).unwrap();
    assert!(csv.starts_with("time_s,x_m,y_m,z_m"));
    assert!(csv.lines().count() > 100);
    assert!(out.join("energy.csv").exists());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_scene_exits_2_with_a_located_message() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("test-specs/paper-stack.toml"))
        .unwrap()
        .replace("restitution = 0.8", "restitution = 1.5");
    let dir = crate::common::temp_dir("sep-bad");
    let path = dir.join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let o = bin()
        .args(["separate"])
        .arg(&path)
        .args(["--json"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.toml:") && err.contains("separation.contact.restitution"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
    assert!(o.stdout.is_empty(), "no JSON for a failed run");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The reference run ends with satellites 4 and 5 0.356 m apart and closing at 4.9 mm/s
/// (docs/separation.md, "Clearance in free flight"): the summary says they will meet, as the
/// clearance gate of `qualify` does, rather than leave the positive minimum clearance alone.
#[test]
fn the_summary_names_a_pair_still_closing_at_the_end() {
    let (code, out, err) =
        crate::common::run_text(&["separate", "test-specs/paper-stack.toml"], None);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("satellites 4 and 5 still closing at 4.9 mm/s at the end (0.3564 m apart)"),
        "{out}"
    );
}
