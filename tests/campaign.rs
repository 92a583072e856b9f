//! Campaigns beyond one machine: a sharded Monte Carlo merged back must be byte-identical to
//! the single-machine `separate --monte-carlo N --seed S --json` (reference: that run itself,
//! tolerance zero), and a bad set of parts is refused with the file and the run range.

use crate::common::{run, run_text, temp_dir};
use satqual::catalogue::generated::small_stack;
use std::path::{Path, PathBuf};

const RUNS: &str = "10";
const SEED: &str = "7";

/// A two-satellite stack on rigid bars with every dispersion enabled (cheap runs).
fn scene(dir: &Path) -> String {
    let text = small_stack(
        2,
        1.5,
        "",
        "[separation.dispersion]\nspring_stiffness_sigma = 0.05\ncg_offset_sigma_m = 0.002\n\
         clearance_range_m = [0.0005, 0.0015]\nfriction_range = [0.1, 0.3]\n\
         release_skew_sigma_s = 0.005\n",
    );
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

fn single(scene: &str) -> Vec<u8> {
    let o = run(
        &[
            "separate",
            scene,
            "--monte-carlo",
            RUNS,
            "--seed",
            SEED,
            "--json",
        ],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o.stdout
}

/// Writes shard `i` of `k` to `dir/part-i-of-k.json`.
fn shard(scene: &str, dir: &Path, i: usize, k: usize, seed: &str) -> PathBuf {
    let out = dir.join(format!("part-{i}-of-{k}.json"));
    let (code, _, err) = run_text(
        &[
            "separate",
            scene,
            "--monte-carlo",
            RUNS,
            "--seed",
            seed,
            "--shard",
            &format!("{i}/{k}"),
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    out
}

fn merge(parts: &[PathBuf], out: &Path) -> (i32, String, String) {
    let mut args = vec!["merge".to_string()];
    args.extend(parts.iter().map(|p| p.display().to_string()));
    args.extend(["--out".into(), out.display().to_string(), "--json".into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    run_text(&args, None)
}

#[test]
fn merged_shards_are_byte_identical_to_one_machine() {
    let dir = temp_dir("campaign-merge");
    let scene = scene(&dir);
    let reference = single(&scene);
    for k in [1, 2, 3, 7] {
        // Reverse order: the merge sorts by shard, not by argument position.
        let parts: Vec<PathBuf> = (0..k)
            .rev()
            .map(|i| shard(&scene, &dir, i, k, SEED))
            .collect();
        let out = dir.join(format!("merged-{k}.json"));
        let (code, stdout, err) = merge(&parts, &out);
        assert_eq!(code, 0, "K = {k}: {err}");
        assert!(
            std::fs::read(&out).unwrap() == reference,
            "K = {k}: merged file differs from the single-machine output"
        );
        assert!(
            stdout.as_bytes() == reference,
            "K = {k}: merged stdout differs"
        );
    }
}

#[test]
fn shard_index_comes_from_an_array_job_variable() {
    let dir = temp_dir("campaign-env");
    let scene = scene(&dir);
    let by_flag = shard(&scene, &dir, 1, 3, SEED);
    for var in [
        "SLURM_ARRAY_TASK_ID",
        "PBS_ARRAY_INDEX",
        "JOB_COMPLETION_INDEX",
    ] {
        let out = dir.join(format!("{var}.json"));
        let o = crate::common::satqual()
            .args(["separate", &scene, "--monte-carlo", RUNS, "--seed", SEED])
            .args(["--shards", "3", "--out", out.to_str().unwrap()])
            .env_remove("SATQUAL_SHARD_INDEX")
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("PBS_ARRAY_INDEX")
            .env(var, "1")
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{var}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(
            std::fs::read(&out).unwrap(),
            std::fs::read(&by_flag).unwrap(),
            "{var}"
        );
    }
}

#[test]
fn bad_merges_are_located() {
    let dir = temp_dir("campaign-bad");
    let scene = scene(&dir);
    let parts: Vec<PathBuf> = (0..3).map(|i| shard(&scene, &dir, i, 3, SEED)).collect();
    let out = dir.join("merged.json");
    let refused = |set: &[PathBuf], needles: &[&str]| {
        let (code, _, err) = merge(set, &out);
        assert_ne!(code, 0, "accepted: {needles:?}");
        assert!(!err.contains("panicked"), "{err}");
        for n in needles {
            assert!(err.contains(n), "`{n}` not in: {err}");
        }
    };
    let name = |p: &PathBuf| p.display().to_string();
    // 10 runs in 3 shards: 0..3, 3..6, 6..10.
    refused(&parts[..2], &["shard 2/3", "runs 6..10", "missing"]);
    let dup = vec![
        parts[0].clone(),
        parts[1].clone(),
        parts[1].clone(),
        parts[2].clone(),
    ];
    refused(
        &dup,
        &[&name(&parts[1]), "shard 1", "runs 3..6", "duplicated"],
    );
    let foreign = shard(&scene, &temp_dir("campaign-bad-foreign"), 1, 3, "8");
    let set = vec![parts[0].clone(), foreign.clone(), parts[2].clone()];
    refused(
        &set,
        &[&name(&foreign), "runs 3..6", "another campaign", "seed 8"],
    );
    // A part cut off mid-write (half its bytes).
    let bytes = std::fs::read(&parts[2]).unwrap();
    let cut = dir.join("cut.json");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let set = vec![parts[0].clone(), parts[1].clone(), cut.clone()];
    refused(&set, &[&name(&cut), "truncated"]);
    // A part with its last realization removed, still valid JSON.
    let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    v["realizations"].as_array_mut().unwrap().pop();
    let short = dir.join("short.json");
    std::fs::write(&short, v.to_string()).unwrap();
    let set = vec![parts[0].clone(), parts[1].clone(), short.clone()];
    refused(&set, &[&name(&short), "runs 9..10", "missing"]);
    // The scene edited after the shards ran.
    std::fs::write(
        &scene,
        std::fs::read_to_string(&scene).unwrap() + "\n# edited\n",
    )
    .unwrap();
    refused(&parts, &["scene.toml", "changed since the shards ran"]);
}

/// The Slurm scripts: an array of K tasks reading SLURM_ARRAY_TASK_ID/COUNT, and a merge job
/// chained with afterok (reference: sbatch(1) for the directives and dependency syntax).
#[test]
fn campaign_writes_a_slurm_array_and_a_chained_merge() {
    let dir = temp_dir("campaign-slurm");
    let scene = scene(&dir);
    let camp = dir.join("camp");
    let (code, out, err) = run_text(
        &[
            "campaign",
            &scene,
            "--slurm",
            "--shards",
            "4",
            "--monte-carlo",
            "59",
            "--seed",
            "3",
            "--partition",
            "debug",
            "--time",
            "00:10:00",
            "--cpus",
            "2",
            "--dir",
            camp.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let shards = std::fs::read_to_string(camp.join("shards.sbatch")).unwrap();
    for line in [
        "#SBATCH --array=0-3",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --partition=debug",
        "#SBATCH --time=00:10:00",
        "--monte-carlo 59 --seed 3 --shards \"$SLURM_ARRAY_TASK_COUNT\" --shard-env SLURM_ARRAY_TASK_ID",
        "/part-\"$SLURM_ARRAY_TASK_ID\".json",
    ] {
        assert!(shards.contains(line), "`{line}` not in:\n{shards}");
    }
    let merge = std::fs::read_to_string(camp.join("merge.sbatch")).unwrap();
    assert!(
        merge.contains(" merge ") && merge.contains("result.json"),
        "{merge}"
    );
    assert!(out.contains("sbatch --parsable"), "{out}");
    assert!(out.contains("sbatch --dependency=afterok:"), "{out}");
    assert!(camp.join("parts").is_dir() && camp.join("logs").is_dir());
}

/// A 4-shard campaign on a one-node Slurm cluster on localhost (scripts/slurm-local.sh):
/// the merged result must equal the single-machine run byte for byte (the script's `cmp`).
#[test]
fn slurm_campaign_merges_byte_identical() {
    let on_path = std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("sbatch").is_file()));
    if !on_path {
        println!("skipped: sbatch is not on PATH (scripts/slurm-local.sh installs Slurm)");
        return;
    }
    let dir = temp_dir("campaign-slurm-local");
    let scene = scene(&dir);
    let o = std::process::Command::new(crate::common::repo_path("scripts/slurm-local.sh"))
        .args([scene.as_str(), RUNS, SEED])
        .env("SATQUAL", env!("CARGO_BIN_EXE_satqual"))
        .env("SHARD_COUNTS", "4")
        .env("SLURM_LOCAL_DIR", dir.join("slurm"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && text.contains("K = 4: merged result byte-identical"),
        "{text}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The Monte Carlo's progress counts every finished run once (1 to N, in completion order,
/// from the worker threads) and reporting changes nothing in the result (reference: the same
/// Monte Carlo without reporting, tolerance zero).
#[test]
fn a_monte_carlo_reports_each_finished_run_once() {
    use satqual::separation::{Model, montecarlo};
    let dir = temp_dir("campaign-progress");
    let path = scene(&dir);
    let model = Model::from_scene(&crate::common::load(&path)).unwrap();
    let seen = std::sync::Mutex::new(Vec::new());
    let done = |k: usize| seen.lock().unwrap().push(k);
    let reported = montecarlo::monte_carlo_reporting(&model, 10, 7, &done).unwrap();
    let mut seen = seen.into_inner().unwrap();
    seen.sort_unstable();
    assert_eq!(seen, (1..=10).collect::<Vec<_>>());
    assert_eq!(reported, montecarlo::monte_carlo(&model, 10, 7).unwrap());
    std::fs::remove_dir_all(&dir).ok();
}
