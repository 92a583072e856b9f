//! Golden outputs: the machine-readable result of every command on the repository's own scenes
//! and logs, compared byte for byte with the files in `tests/golden/`. They catch any change of
//! a result that was not meant. A change that moves results on purpose regenerates them with
//! `SATQUAL_BLESS=1 cargo test --release golden` in the same commit, and its message says which
//! numbers moved, by how much, and why.

use std::path::{Path, PathBuf};

use satqual::catalogue::logs::{CONTROLLER_PSD_UFF as UFF_PSD, SHAKER_BEAM as SHAKER_LOG, impact};
use satqual::catalogue::{ALL_SCENES as SCENES, RESPONSE_SCENES};

fn stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .unwrap()
        .to_string_lossy()
        .into_owned()
}

/// (golden file name, command arguments) for every command that prints `--json` on stdout.
fn stdout_cases() -> Vec<(String, Vec<String>)> {
    let mut cases: Vec<(String, Vec<String>)> = Vec::new();
    let mut add = |name: String, args: &[&str]| {
        cases.push((name, args.iter().map(|s| s.to_string()).collect()));
    };
    for s in SCENES.iter().filter(|s| !s.contains("test-data")) {
        add(format!("modal-{}.json", stem(s)), &["modal", s, "--json"]);
    }
    for s in RESPONSE_SCENES {
        add(format!("sine-{}.json", stem(s)), &["sine", s, "--json"]);
        add(format!("random-{}.json", stem(s)), &["random", s, "--json"]);
    }
    let paper = "test-specs/paper-stack.toml";
    add(
        "separate-paper-stack.json".into(),
        &["separate", paper, "--json"],
    );
    add(
        "separate-paper-stack-mc8-seed3.json".into(),
        &[
            "separate",
            paper,
            "--monte-carlo",
            "8",
            "--seed",
            "3",
            "--json",
        ],
    );
    add("expand-paper-stack.toml".into(), &["expand", paper]);
    add(
        "psd-usc-shaker-beam.json".into(),
        &["psd", SHAKER_LOG, "--json"],
    );
    add(
        "psd-vibcontrol-uff.json".into(),
        &["psd", UFF_PSD, "--json"],
    );
    add("psd-impact-1.json".into(), &["psd", &impact(1), "--json"]);
    let logs: Vec<String> = (1..=5).map(impact).collect();
    let mut frf: Vec<&str> = vec!["frf"];
    frf.extend(logs.iter().map(String::as_str));
    frf.extend(["--input", "force", "--output", "acceleration", "--json"]);
    add("frf-impact-1-5.json".into(), &frf);
    let (i1, i2) = (impact(1), impact(2));
    add(
        "signature-impact-1-2.json".into(),
        &[
            "signature",
            &i1,
            &i2,
            "--input",
            "force",
            "--output",
            "acceleration",
            "--json",
        ],
    );
    cases
}

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn run(args: &[String]) -> Vec<u8> {
    let out = crate::common::satqual()
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .expect("run satqual");
    let code = out.status.code();
    assert!(
        matches!(code, Some(0) | Some(1)),
        "satqual {args:?} exited {code:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// Compares `actual` with the stored golden file, or stores it when blessing. Returns a
/// description of the difference, if any.
fn check(name: &str, actual: &[u8]) -> Option<String> {
    let path = golden_dir().join(name);
    if std::env::var_os("SATQUAL_BLESS").is_some() {
        std::fs::create_dir_all(golden_dir()).unwrap();
        std::fs::write(&path, actual).unwrap();
        return None;
    }
    let expected = match std::fs::read(&path) {
        Ok(e) => e,
        Err(e) => return Some(format!("{name}: cannot read the golden file ({e})")),
    };
    if expected == actual {
        return None;
    }
    let (e, a) = (
        String::from_utf8_lossy(&expected),
        String::from_utf8_lossy(actual),
    );
    let line = e
        .lines()
        .zip(a.lines())
        .position(|(x, y)| x != y)
        .unwrap_or_else(|| e.lines().count().min(a.lines().count()));
    Some(format!(
        "{name}: differs from line {}: golden {:?}, now {:?}",
        line + 1,
        e.lines().nth(line).unwrap_or("<end>"),
        a.lines().nth(line).unwrap_or("<end>")
    ))
}

#[test]
fn command_outputs_match_the_golden_files() {
    let diffs: Vec<String> = stdout_cases()
        .iter()
        .filter_map(|(name, args)| check(name, &run(args)))
        .collect();
    assert!(
        diffs.is_empty(),
        "golden outputs moved:\n{}",
        diffs.join("\n")
    );
}

#[test]
fn qualify_results_match_the_golden_files() {
    let tmp = crate::common::temp_dir("golden");
    let mut diffs = Vec::new();
    for scene in SCENES {
        let out = tmp.join(stem(scene));
        let args: Vec<String> = ["qualify", scene, "--quiet", "--out", out.to_str().unwrap()]
            .iter()
            .map(|s| s.to_string())
            .collect();
        run(&args);
        let results = std::fs::read(out.join("results.json")).expect("results.json written");
        diffs.extend(check(&format!("qualify-{}.json", stem(scene)), &results));
    }
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(
        diffs.is_empty(),
        "golden outputs moved:\n{}",
        diffs.join("\n")
    );
}

/// The gate schema of results.json, read from the stored qualify goldens (so it holds for
/// every reference scene): each gate has `name, group, value, limit, unit, margin, pass,
/// source`, its group is one of the six families, and no source points into the code (a
/// Rust path such as `spec::qualify`) instead of a standard or a stated assumption.
#[test]
fn every_qualify_gate_has_a_group_a_unit_and_a_source_outside_the_code() {
    const GROUPS: [&str; 6] = [
        "frequency",
        "buckling",
        "lock_integrity",
        "bar_strength",
        "separation",
        "test_data",
    ];
    let mut checked = 0;
    for scene in SCENES {
        let name = format!("qualify-{}.json", stem(scene));
        let text = std::fs::read_to_string(golden_dir().join(&name)).expect("golden file");
        let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        let gates = json["gates"].as_array().expect("a gates array");
        assert!(!gates.is_empty(), "{name}: no gates");
        for g in gates {
            let gate = g["name"].as_str().unwrap_or("?");
            for key in ["value", "limit", "margin", "pass"] {
                assert!(g.get(key).is_some(), "{name}: {gate}: no {key}");
            }
            let group = g["group"].as_str().unwrap_or("");
            assert!(GROUPS.contains(&group), "{name}: {gate}: group {group:?}");
            assert!(g["unit"].is_string(), "{name}: {gate}: no unit field");
            let source = g["source"].as_str().unwrap_or("");
            assert!(!source.is_empty(), "{name}: {gate}: empty source");
            assert!(!source.contains("::"), "{name}: {gate}: source {source:?}");
            checked += 1;
        }
    }
    // The paper stack alone has 79 gates, so far more than a handful were checked.
    assert!(checked > 79, "only {checked} gates checked");
}
