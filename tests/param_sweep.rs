//! Parameter sweeps (`separate --sweep`): a sweep sharded in K parts and merged writes the
//! report folder one machine writes, byte for byte (reference: that run itself, tolerance
//! zero); bad parts are refused with the file and the unit range; swept keys are checked at
//! load with their line; every point goes through the scene's validation.

use crate::common::{line_of, run_text, temp_dir};
use satqual::catalogue::generated::small_stack;
use satqual::spec::Scene;
use std::path::{Path, PathBuf};

/// Two satellites on rigid bars (cheap runs), every dispersion but friction enabled, a 2 × 2
/// grid over the column pitch and the friction, and a third key that is the exit-speed gate
/// itself: 10 m/s is above what the springs can give (v ≤ s·√(Σk/m) = 0.08·√(2800/150) ≈ 0.35
/// m/s, the ideal release of paper §4), so every point with that limit fails its speed gate.
fn scene_text() -> String {
    small_stack(
        2,
        1.5,
        "",
        "[separation.contact]\nfriction = 0.2\n\
         [separation.dispersion]\nspring_stiffness_sigma = 0.05\ncg_offset_sigma_m = 0.002\n\
         clearance_range_m = [0.0005, 0.0015]\nrelease_skew_sigma_s = 0.005\nruns = 4\nseed = 7\n\
         [gates]\nmin_separation_speed_m_s = 0.1\n\
         [sweep]\n\
         [[sweep.parameter]]\nkey = \"stack.satellite_pitch_m\"\nvalues = [0.45, 0.55]\n\
         [[sweep.parameter]]\nkey = \"separation.contact.friction\"\nfrom = 0.1\nto = 0.3\nsteps = 2\n\
         [[sweep.parameter]]\nkey = \"gates.min_separation_speed_m_s\"\nvalues = [0.1, 10.0]\n",
    )
}

fn scene(dir: &Path) -> String {
    let p = dir.join("sweep.toml");
    std::fs::write(&p, scene_text()).unwrap();
    p.display().to_string()
}

fn args(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// Runs the sweep in one process into `out`; returns its --json stdout.
fn single(scene: &str, out: &Path) -> String {
    let a = [
        "separate",
        scene,
        "--sweep",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ];
    let (code, stdout, err) = run_text(&a, None);
    assert_eq!(code, 0, "{err}");
    stdout
}

fn shard(scene: &str, dir: &Path, i: usize, k: usize, extra: &[&str]) -> PathBuf {
    let out = dir.join(format!("part-{i}-of-{k}.json"));
    let mut a: Vec<String> = ["separate", scene, "--sweep", "--shard"]
        .map(String::from)
        .to_vec();
    a.push(format!("{i}/{k}"));
    a.extend(["--out".into(), out.display().to_string()]);
    a.extend(extra.iter().map(|s| s.to_string()));
    let (code, _, err) = run_text(&args(&a), None);
    assert_eq!(code, 0, "{err}");
    out
}

fn merge(parts: &[PathBuf], out: &Path) -> (i32, String, String) {
    let mut a = vec!["merge".to_string()];
    a.extend(parts.iter().map(|p| p.display().to_string()));
    a.extend(["--out".into(), out.display().to_string(), "--json".into()]);
    run_text(&args(&a), None)
}

/// Every file under `dir`, relative path → bytes, sorted.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            let sub = p.file_name().unwrap().to_string_lossy().into_owned();
            out.extend(
                files(&p)
                    .into_iter()
                    .map(|(n, b)| (format!("{sub}/{n}"), b)),
            );
        } else {
            out.push((
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            ));
        }
    }
    out.sort();
    out
}

#[test]
fn merged_sweep_shards_are_byte_identical_to_one_machine() {
    let dir = temp_dir("sweep-merge");
    let scene = scene(&dir);
    let one = dir.join("one");
    let reference_stdout = single(&scene, &one);
    let reference = files(&one);
    // 8 points × 4 runs = 32 units; the report has the table, the CSV and 7 plots per key.
    assert!(reference.iter().any(|(n, _)| n == "sweep.csv"));
    assert_eq!(
        reference
            .iter()
            .filter(|(n, _)| n.starts_with("plots/"))
            .count(),
        3 * 7
    );
    for k in [1, 2, 3, 7] {
        let parts: Vec<PathBuf> = (0..k)
            .rev()
            .map(|i| shard(&scene, &dir, i, k, &[]))
            .collect();
        let out = dir.join(format!("merged-{k}"));
        let (code, stdout, err) = merge(&parts, &out);
        assert_eq!(code, 0, "K = {k}: {err}");
        let merged = files(&out);
        let names = |f: &[(String, Vec<u8>)]| f.iter().map(|x| x.0.clone()).collect::<Vec<_>>();
        assert_eq!(names(&merged), names(&reference), "K = {k}: file list");
        for ((name, a), (_, b)) in merged.iter().zip(&reference) {
            assert!(
                a == b,
                "K = {k}: {name} differs from the single-machine report"
            );
        }
        assert!(stdout == reference_stdout, "K = {k}: merged stdout differs");
    }
}

/// The table marks the points that fail a gate: the four points with a 10 m/s speed limit
/// fail it (see `scene_text`), and their crosses appear in the plots.
#[test]
fn sweep_table_marks_points_that_fail_a_gate() {
    let dir = temp_dir("sweep-table");
    let scene = scene(&dir);
    let out = dir.join("report");
    let json: serde_json::Value = serde_json::from_str(&single(&scene, &out)).unwrap();
    let points = json["points"].as_array().unwrap();
    assert_eq!(points.len(), 8);
    for p in points {
        let limit = p["values"][2].as_f64().unwrap();
        let speed = &p["gates"][0];
        assert_eq!(speed["limit"].as_f64().unwrap(), limit);
        if limit == 10.0 {
            assert_eq!(speed["pass"], false, "{p}");
            assert_eq!(p["pass"], false, "{p}");
        }
        assert_eq!(p["runs"], 4);
    }
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(
        &head[..4],
        [
            "point",
            "stack.satellite_pitch_m",
            "separation.contact.friction",
            "gates.min_separation_speed_m_s"
        ]
    );
    let pass = head.iter().position(|h| *h == "pass").unwrap();
    for line in csv.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        if cells[3] == "10" {
            assert_eq!(cells[pass], "false", "{line}");
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("## Plots") && md.contains("plots/sweep_1_1_satellite_pitch_m.svg"),
        "{md}"
    );
    let svg = std::fs::read_to_string(out.join("plots/sweep_1_1_satellite_pitch_m.svg")).unwrap();
    assert!(svg.contains("fails a gate"), "no failure legend");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("<svg") && html.contains("Parameter sweep"));
}

#[test]
fn bad_sweep_merges_are_located() {
    let dir = temp_dir("sweep-bad");
    let scene = scene(&dir);
    let parts: Vec<PathBuf> = (0..3).map(|i| shard(&scene, &dir, i, 3, &[])).collect();
    let out = dir.join("merged");
    let refused = |set: &[PathBuf], needles: &[&str]| {
        let (code, _, err) = merge(set, &out);
        assert_ne!(code, 0, "accepted: {needles:?}");
        assert!(!err.contains("panicked"), "{err}");
        for n in needles {
            assert!(err.contains(n), "`{n}` not in: {err}");
        }
    };
    let name = |p: &PathBuf| p.display().to_string();
    // 8 points × 4 runs = 32 units in 3 shards: 0..10, 10..21, 21..32.
    refused(&parts[..2], &["shard 2/3", "units 21..32", "missing"]);
    let dup = vec![
        parts[0].clone(),
        parts[1].clone(),
        parts[1].clone(),
        parts[2].clone(),
    ];
    refused(&dup, &[&name(&parts[1]), "units 10..21", "duplicated"]);
    let foreign = shard(
        &scene,
        &temp_dir("sweep-bad-foreign"),
        1,
        3,
        &["--monte-carlo", "4", "--seed", "8"],
    );
    let set = vec![parts[0].clone(), foreign.clone(), parts[2].clone()];
    refused(
        &set,
        &[
            &name(&foreign),
            "units 10..21",
            "another campaign",
            "seed 8",
        ],
    );
    // A Monte Carlo part among sweep parts.
    let mc = dir.join("mc.json");
    let a = [
        "separate",
        &scene,
        "--monte-carlo",
        "4",
        "--seed",
        "7",
        "--shard",
        "1/3",
        "--out",
        mc.to_str().unwrap(),
    ];
    assert_eq!(run_text(&a, None).0, 0);
    let set = vec![parts[0].clone(), mc.clone(), parts[2].clone()];
    refused(
        &set,
        &[&name(&mc), "another campaign", "a sweep of 8 points"],
    );
    let bytes = std::fs::read(&parts[2]).unwrap();
    let cut = dir.join("cut.json");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    refused(
        &[parts[0].clone(), parts[1].clone(), cut.clone()],
        &[&name(&cut), "truncated"],
    );
    let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    v["realizations"].as_array_mut().unwrap().pop();
    let short = dir.join("short.json");
    std::fs::write(&short, v.to_string()).unwrap();
    refused(
        &[parts[0].clone(), parts[1].clone(), short.clone()],
        &[&name(&short), "units 31..32", "missing"],
    );
}

/// Swept keys are checked when the scene loads; the error names the line of the `key`.
#[test]
fn swept_keys_are_checked_at_load_with_their_line() {
    let base = scene_text();
    let cases = [
        (
            "stack.satellite_pitch_m\"",
            "stack.satelite_pitch_m\"",
            "no key `satelite_pitch_m`",
        ),
        (
            "stack.satellite_pitch_m\"",
            "stack.column_material\"",
            "holds string, not a number",
        ),
        (
            "stack.satellite_pitch_m\"",
            "stack.interface\"",
            "a table, not a number",
        ),
        (
            "stack.satellite_pitch_m\"",
            "stack.satellites\"",
            "is an integer in the scene",
        ),
        (
            "stack.satellite_pitch_m\"",
            "separation.dispersion.cg_offset_sigma_m\"",
            "",
        ),
    ];
    for (from, to, needle) in cases {
        let text = base.replacen(from, to, 1);
        let r = Scene::parse(Path::new("bad.toml"), &text);
        if needle.is_empty() {
            assert!(r.is_ok(), "{to}: {:?}", r.err());
            continue;
        }
        let e = r.expect_err(to).to_string();
        let line = line_of(&text, to);
        assert!(
            e.contains(needle) && e.contains(&format!("bad.toml:{line}:")),
            "{to}: {e}"
        );
        assert!(e.contains("sweep.parameter[0].key"), "{e}");
    }
    // Friction redrawn in every run by a friction_range: sweeping it would change nothing.
    let text = base.replacen(
        "release_skew_sigma_s",
        "friction_range = [0.1, 0.3]\nrelease_skew_sigma_s",
        1,
    );
    let e = Scene::parse(Path::new("bad.toml"), &text)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("sweep.parameter[1].key") && e.contains("friction_range"),
        "{e}"
    );
}

/// A point is a scene like any other: a value outside a plausible range, or a stack that no
/// longer fits on its bars, is refused with the point and the key.
#[test]
fn every_point_goes_through_the_scene_checks() {
    let dir = temp_dir("sweep-point-error");
    // Two satellites at a 1.0 m pitch on 1.5 m bars with a 0.2 m base do not fit.
    let text = scene_text().replace("values = [0.45, 0.55]", "values = [0.45, 1.0]");
    let p = dir.join("sweep.toml");
    std::fs::write(&p, &text).unwrap();
    let (code, _, err) = run_text(
        &[
            "separate",
            p.to_str().unwrap(),
            "--sweep",
            "--out",
            dir.join("r").to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("sweep point 4") && err.contains("stack.satellite_pitch_m = 1"),
        "{err}"
    );
    assert!(
        !dir.join("r").exists(),
        "a report was written for a failed sweep"
    );
}

/// A Latin hypercube sweep: `points` points, each key's values inside its bounds, one per
/// stratum (McKay et al. 1979); the same seed gives the same table.
#[test]
fn latin_hypercube_sweep_runs_with_one_point_per_stratum() {
    let dir = temp_dir("sweep-lhs");
    let base = scene_text();
    let sweep = base.find("[sweep]").unwrap();
    let text = format!(
        "{}[sweep]\nmethod = \"lhs\"\npoints = 5\nseed = 11\n\
         [[sweep.parameter]]\nkey = \"stack.satellite_pitch_m\"\nbounds = [0.4, 0.6]\n\
         [[sweep.parameter]]\nkey = \"separation.contact.friction\"\nbounds = [0.05, 0.35]\n",
        &base[..sweep]
    );
    let p = dir.join("lhs.toml");
    std::fs::write(&p, &text).unwrap();
    let s = p.to_str().unwrap();
    let a = single(s, &dir.join("a"));
    let b = single(s, &dir.join("b"));
    assert_eq!(a, b);
    let json: serde_json::Value = serde_json::from_str(&a).unwrap();
    let points = json["points"].as_array().unwrap();
    assert_eq!(points.len(), 5);
    for (j, [lo, hi]) in [[0.4, 0.6], [0.05, 0.35]].iter().enumerate() {
        let mut strata: Vec<usize> = points
            .iter()
            .map(|p| ((p["values"][j].as_f64().unwrap() - lo) / (hi - lo) * 5.0) as usize)
            .collect();
        strata.sort();
        assert_eq!(strata, vec![0, 1, 2, 3, 4], "key {j}");
    }
}

/// `campaign --slurm` on a sweep scene: the array tasks run `separate --sweep` and the merge
/// writes the report folder (reference: sbatch(1) for the directives).
#[test]
fn campaign_writes_a_sweep_array() {
    let dir = temp_dir("sweep-slurm");
    let scene = scene(&dir);
    let camp = dir.join("camp");
    let a = [
        "campaign",
        &scene,
        "--slurm",
        "--shards",
        "3",
        "--dir",
        camp.to_str().unwrap(),
    ];
    let (code, _, err) = run_text(&a, None);
    assert_eq!(code, 0, "{err}");
    let shards = std::fs::read_to_string(camp.join("shards.sbatch")).unwrap();
    // Runs and seed from [separation.dispersion] (4, 7).
    assert!(shards.contains("#SBATCH --array=0-2"), "{shards}");
    assert!(
        shards.contains("--sweep --monte-carlo 4 --seed 7 --shards"),
        "{shards}"
    );
    let merge = std::fs::read_to_string(camp.join("merge.sbatch")).unwrap();
    assert!(
        merge.contains("/result'") && !merge.contains("result.json"),
        "{merge}"
    );
}
