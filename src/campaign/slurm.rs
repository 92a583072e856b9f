//! The Slurm scripts of a sharded Monte Carlo: an `sbatch` array whose task I runs
//! `separate --shards K` (the index comes from `SLURM_ARRAY_TASK_ID`, the count is checked
//! against `SLURM_ARRAY_TASK_COUNT`), and a merge job submitted with `--dependency=afterok`
//! on the array, so it starts only when every shard succeeded.

use std::fmt::Write as _;
use std::path::PathBuf;

/// Everything the scripts need; paths absolute, so the jobs run from any node's working folder.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The `satqual` binary the nodes run.
    pub exe: PathBuf,
    /// Working folder of the jobs (the scene path is resolved and recorded from here).
    pub workdir: PathBuf,
    /// The scene, as `separate` and `merge` will see it.
    pub scene: String,
    pub runs: usize,
    pub seed: u64,
    pub shards: usize,
    /// Campaign folder: scripts, `parts/`, `logs/` and `result.json`.
    pub dir: PathBuf,
    pub partition: Option<String>,
    pub time: Option<String>,
    pub cpus: usize,
    /// The scene's `[sweep]`: shards run `separate --sweep` and the merge writes the report
    /// folder `DIR/result/` instead of `DIR/result.json`.
    pub sweep: bool,
}

/// Single-quoted for the shell (a quote inside becomes '\'').
pub fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn q(p: &std::path::Path) -> String {
    quote(&p.display().to_string())
}

fn header(p: &Plan, name: &str, cpus: usize, log: &str) -> String {
    let mut s = String::from("#!/bin/bash\n");
    let _ = writeln!(s, "#SBATCH --job-name={name}");
    let _ = writeln!(s, "#SBATCH --cpus-per-task={cpus}");
    let _ = writeln!(
        s,
        "#SBATCH --output={}",
        p.dir.join("logs").join(log).display()
    );
    if let Some(part) = &p.partition {
        let _ = writeln!(s, "#SBATCH --partition={part}");
    }
    if let Some(t) = &p.time {
        let _ = writeln!(s, "#SBATCH --time={t}");
    }
    s
}

/// The array job: one task per shard.
pub fn shards_script(p: &Plan) -> String {
    let mut s = header(p, "satqual-shards", p.cpus, "shard-%a.log");
    let _ = writeln!(s, "#SBATCH --array=0-{}", p.shards - 1);
    s.push_str("set -euo pipefail\n");
    let _ = writeln!(s, "cd {}", q(&p.workdir));
    // A mismatch means the script was edited or submitted with another --array.
    let _ = writeln!(
        s,
        "test \"$SLURM_ARRAY_TASK_COUNT\" = {} || {{ echo \"array of $SLURM_ARRAY_TASK_COUNT tasks, the campaign has {} shards\" >&2; exit 2; }}",
        p.shards, p.shards
    );
    let _ = writeln!(
        s,
        "export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-1}}\""
    );
    let _ = writeln!(
        s,
        "{} separate {}{} --monte-carlo {} --seed {} --shards \"$SLURM_ARRAY_TASK_COUNT\" --shard-env SLURM_ARRAY_TASK_ID --out {}/part-\"$SLURM_ARRAY_TASK_ID\".json",
        q(&p.exe),
        quote(&p.scene),
        if p.sweep { " --sweep" } else { "" },
        p.runs,
        p.seed,
        q(&p.dir.join("parts"))
    );
    s
}

/// The merge job: reads every part, writes `result.json` (a sweep: the folder `result/`).
pub fn merge_script(p: &Plan) -> String {
    let mut s = header(p, "satqual-merge", 1, "merge.log");
    s.push_str("set -euo pipefail\n");
    let _ = writeln!(s, "cd {}", q(&p.workdir));
    let _ = writeln!(
        s,
        "{} merge {}/part-*.json --out {}",
        q(&p.exe),
        q(&p.dir.join("parts")),
        q(&p.dir.join(if p.sweep { "result" } else { "result.json" }))
    );
    s
}

/// The two submissions: the array, then the merge once every array task ended with exit 0.
pub fn submit_commands(p: &Plan) -> [String; 2] {
    [
        format!(
            "array=$(sbatch --parsable {})",
            q(&p.dir.join("shards.sbatch"))
        ),
        format!(
            "sbatch --dependency=afterok:\"${{array%%;*}}\" {}",
            q(&p.dir.join("merge.sbatch"))
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quote_survives_a_quote() {
        assert_eq!(quote("it's"), r"'it'\''s'");
    }
}
