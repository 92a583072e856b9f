//! Sharded Monte Carlo: shard I of K computes the contiguous block of realizations
//! `I·N/K .. (I+1)·N/K` and writes them as a part file; a merge checks that the parts belong
//! to one campaign and cover every index once, then rebuilds the single-machine result.
//!
//! Exactness: a realization depends only on (seed, index), and the part stores each number as
//! its IEEE 754 bit pattern, so the merged sample is bit-for-bit the single-machine sample
//! whatever JSON float parser reads it back.

use super::montecarlo::Realization;
use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The `format` field of a part file.
pub const PART_FORMAT: &str = "satqual-separate-part/2";
/// The `format` field of a part file of a parameter sweep.
pub const SWEEP_PART_FORMAT: &str = "satqual-sweep-part/1";

/// Environment variables that carry an array job's index, tried in this order when no
/// `--shard` is given: satqual's own, then Slurm, PBS Pro and Kubernetes indexed jobs.
pub const INDEX_VARIABLES: [&str; 4] = [
    "SATQUAL_SHARD_INDEX",
    "SLURM_ARRAY_TASK_ID",
    "PBS_ARRAY_INDEX",
    "JOB_COMPLETION_INDEX",
];

/// Shard `index` of `count`, 0-based like array-job indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub fn new(index: usize, count: usize) -> Result<Shard, Error> {
        if count == 0 || index >= count {
            return Err(Error::Other(format!(
                "shard {index}/{count}: the index must be 0 ≤ I < K and K ≥ 1"
            )));
        }
        Ok(Shard { index, count })
    }

    /// Parses `I/K`.
    pub fn parse(text: &str) -> Result<Shard, Error> {
        let bad = || Error::Other(format!("--shard `{text}`: expected I/K, e.g. 0/4"));
        let (i, k) = text.split_once('/').ok_or_else(bad)?;
        let i = i.trim().parse().map_err(|_| bad())?;
        let k = k.trim().parse().map_err(|_| bad())?;
        Shard::new(i, k)
    }

    /// The realization indices of this shard among `runs`: contiguous, sizes differing by at
    /// most one, together covering `0..runs` once.
    pub fn range(&self, runs: usize) -> Range<u64> {
        let at = |i: usize| (i as u128 * runs as u128 / self.count as u128) as u64;
        at(self.index)..at(self.index + 1)
    }
}

/// The shard to compute: `--shard I/K` when given, otherwise index from the environment
/// variable `variable` (or the first set of [`INDEX_VARIABLES`]) and count `count`.
pub fn resolve(
    shard: Option<&str>,
    count: Option<usize>,
    variable: Option<&str>,
    env: impl Fn(&str) -> Option<String>,
) -> Result<Option<Shard>, Error> {
    if let Some(s) = shard {
        return Shard::parse(s).map(Some);
    }
    let Some(count) = count else {
        return Ok(None);
    };
    let names: Vec<&str> = variable.map_or(INDEX_VARIABLES.to_vec(), |v| vec![v]);
    let Some((name, value)) = names.iter().find_map(|n| env(n).map(|v| (*n, v))) else {
        return Err(Error::Other(format!(
            "--shards {count} without --shard: none of {} is set",
            names.join(", ")
        )));
    };
    let index = value.trim().parse().map_err(|_| {
        Error::Other(format!(
            "environment variable {name} = `{value}` is not a shard index"
        ))
    })?;
    Shard::new(index, count).map(Some)
}

/// One realization in a part file; numbers as IEEE 754 bit patterns.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RunRecord {
    pub index: u64,
    pub final_speed_bits: Vec<u64>,
    pub tip_off_rate_bits: Vec<u64>,
    pub min_clearance_bits: Option<u64>,
    /// Per satellite: it wedged in the bars.
    pub wedged: Vec<bool>,
    /// Per satellite: still sliding when the run ended (absent in parts that predate it).
    #[serde(default)]
    pub cut_short: Vec<bool>,
    pub steps: usize,
}

/// What identifies a campaign: every part of one merge must agree on all of it.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Campaign {
    /// The scene path as given to `separate` (the merged output repeats it).
    pub scene: String,
    /// FNV-1a of the scene text.
    pub scene_hash: String,
    pub seed: u64,
    pub runs: usize,
    pub shards: usize,
    pub satellites: usize,
    /// Present for a parameter sweep, whose work units are points × runs (unit `u` is run
    /// `u mod runs` of point `⌊u / runs⌋`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepTag>,
}

/// What identifies a sweep besides the scene hash: its number of points and its definition.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SweepTag {
    pub points: usize,
    /// The `[sweep]` section as read, re-written as TOML.
    pub definition: String,
}

impl Campaign {
    /// The number of work units shards split: runs, or points × runs for a sweep.
    pub fn units(&self) -> usize {
        self.runs * self.sweep.as_ref().map_or(1, |s| s.points)
    }

    /// How the units are named in messages.
    pub fn unit_name(&self) -> &'static str {
        if self.sweep.is_some() {
            "units"
        } else {
            "runs"
        }
    }

    fn format(&self) -> &'static str {
        if self.sweep.is_some() {
            SWEEP_PART_FORMAT
        } else {
            PART_FORMAT
        }
    }
}

/// A part file: shard `shard` of the campaign, runs `first..end`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Part {
    pub format: String,
    #[serde(flatten)]
    pub campaign: Campaign,
    pub shard: usize,
    pub first: u64,
    pub end: u64,
    pub realizations: Vec<RunRecord>,
}

impl Part {
    pub fn new(campaign: Campaign, shard: Shard, results: &[Realization]) -> Part {
        let r = shard.range(campaign.units());
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect();
        Part {
            format: campaign.format().into(),
            campaign,
            shard: shard.index,
            first: r.start,
            end: r.end,
            realizations: results
                .iter()
                .map(|x| RunRecord {
                    index: x.index,
                    final_speed_bits: bits(&x.final_speed_m_s),
                    tip_off_rate_bits: bits(&x.tip_off_rate_deg_s),
                    min_clearance_bits: x.min_clearance_m.map(f64::to_bits),
                    wedged: x.wedged.clone(),
                    cut_short: x.cut_short.clone(),
                    steps: x.steps,
                })
                .collect(),
        }
    }

    /// Reads and checks a part file on its own (format, declared range, records).
    pub fn read(path: &Path) -> Result<Part, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let part: Part = serde_json::from_str(&text).map_err(|e| {
            Error::Other(format!(
                "{}: not a complete shard part (truncated or corrupt?): {e}",
                path.display()
            ))
        })?;
        part.check(path)?;
        Ok(part)
    }

    fn check(&self, path: &Path) -> Result<(), Error> {
        let p = path.display();
        let c = &self.campaign;
        if self.format != c.format() {
            return Err(Error::Other(format!(
                "{p}: format `{}`, expected `{}` (`{SWEEP_PART_FORMAT}` with a `sweep` field)",
                self.format,
                if self.format == SWEEP_PART_FORMAT {
                    SWEEP_PART_FORMAT
                } else {
                    PART_FORMAT
                }
            )));
        }
        let shard =
            Shard::new(self.shard, c.shards).map_err(|e| Error::Other(format!("{p}: {e}")))?;
        let want = shard.range(c.units());
        let u = c.unit_name();
        if (self.first..self.end) != want {
            return Err(Error::Other(format!(
                "{p}: shard {}/{} declares {u} {}..{}, but that shard holds {u} {}..{}",
                self.shard, c.shards, self.first, self.end, want.start, want.end
            )));
        }
        for (k, r) in self.realizations.iter().enumerate() {
            let expected = self.first + k as u64;
            if r.index != expected {
                return Err(Error::Other(format!(
                    "{p}: shard {} ({u} {}..{}) record {k} is number {}, expected {expected}; \
                     {} of {} {u} present",
                    self.shard,
                    self.first,
                    self.end,
                    r.index,
                    self.realizations.len(),
                    self.end - self.first
                )));
            }
            r.check(path, c.satellites)?;
        }
        if self.realizations.len() as u64 != self.end - self.first {
            return Err(Error::Other(format!(
                "{p}: shard {} holds {} of its {u} {}..{}: {u} {}..{} are missing (truncated part?)",
                self.shard,
                self.realizations.len(),
                self.first,
                self.end,
                self.first + self.realizations.len() as u64,
                self.end
            )));
        }
        Ok(())
    }
}

impl RunRecord {
    fn check(&self, path: &Path, satellites: usize) -> Result<(), Error> {
        let bad =
            |why: &str| Error::Other(format!("{}: run {}: {why}", path.display(), self.index));
        let counts = [
            self.final_speed_bits.len(),
            self.tip_off_rate_bits.len(),
            self.wedged.len(),
        ];
        if counts.iter().any(|&c| c != satellites) {
            return Err(bad(&format!("expected {satellites} satellites")));
        }
        if !self.cut_short.is_empty() && self.cut_short.len() != satellites {
            return Err(bad(&format!(
                "cut_short has {} entries, expected {satellites} satellites",
                self.cut_short.len()
            )));
        }
        let all = self
            .final_speed_bits
            .iter()
            .chain(&self.tip_off_rate_bits)
            .chain(&self.min_clearance_bits);
        if all.map(|b| f64::from_bits(*b)).any(|x| !x.is_finite()) {
            return Err(bad("a value is not finite"));
        }
        Ok(())
    }

    fn realization(&self) -> Realization {
        let vals = |v: &[u64]| v.iter().map(|b| f64::from_bits(*b)).collect();
        Realization {
            index: self.index,
            final_speed_m_s: vals(&self.final_speed_bits),
            tip_off_rate_deg_s: vals(&self.tip_off_rate_bits),
            min_clearance_m: self.min_clearance_bits.map(f64::from_bits),
            wedged: self.wedged.clone(),
            cut_short: self.cut_short.clone(),
            steps: self.steps,
        }
    }
}

/// Checks that the parts (path, part) form one complete campaign: same campaign fields, every
/// shard exactly once. Returns the campaign and all realizations in index order.
pub fn merge(parts: &[(PathBuf, Part)]) -> Result<(Campaign, Vec<Realization>), Error> {
    let Some((first_path, first)) = parts.first() else {
        return Err(Error::Other("merge: no part files given".into()));
    };
    let c = &first.campaign;
    let mut holder: Vec<Option<&Path>> = vec![None; c.shards];
    let u = c.unit_name();
    for (path, part) in parts {
        if part.campaign != *c {
            return Err(Error::Other(format!(
                "{}: shard {} ({} {}..{}) belongs to another campaign: {} (the first part, {}, is {})",
                path.display(),
                part.shard,
                part.campaign.unit_name(),
                part.first,
                part.end,
                describe(&part.campaign),
                first_path.display(),
                describe(c)
            )));
        }
        if let Some(other) = holder[part.shard].replace(path) {
            return Err(Error::Other(format!(
                "{}: shard {} ({u} {}..{}) is duplicated: {} holds it too",
                path.display(),
                part.shard,
                part.first,
                part.end,
                other.display()
            )));
        }
    }
    if let Some(i) = holder.iter().position(Option::is_none) {
        let r = Shard {
            index: i,
            count: c.shards,
        }
        .range(c.units());
        return Err(Error::Other(format!(
            "shard {i}/{} ({u} {}..{}) of {} is missing: none of the {} part files holds it; re-run it with --shard {i}/{}",
            c.shards,
            r.start,
            r.end,
            c.scene,
            parts.len(),
            c.shards
        )));
    }
    let mut ordered: Vec<&Part> = parts.iter().map(|(_, p)| p).collect();
    ordered.sort_by_key(|p| p.shard);
    let all = ordered
        .iter()
        .flat_map(|p| p.realizations.iter().map(RunRecord::realization))
        .collect();
    Ok((c.clone(), all))
}

fn describe(c: &Campaign) -> String {
    let sweep = c.sweep.as_ref().map_or(String::new(), |s| {
        format!(
            ", a sweep of {} points ({})",
            s.points,
            s.definition
                .lines()
                .filter(|l| !l.trim().is_empty())
                .collect::<Vec<_>>()
                .join("; ")
        )
    });
    format!(
        "scene {} hash {}, seed {}, {} runs in {} shards, {} satellites{sweep}",
        c.scene, c.scene_hash, c.seed, c.runs, c.shards, c.satellites
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_ranges_cover_every_run_once() {
        // Contiguous blocks ⌊I·N/K⌋..⌊(I+1)·N/K⌋: 10 runs in 3 shards are 0..3, 3..6, 6..10.
        let r: Vec<_> = (0..3)
            .map(|i| Shard::new(i, 3).unwrap().range(10))
            .collect();
        assert_eq!(r, vec![0..3, 3..6, 6..10]);
        // More shards than runs: some shards are empty, none overlaps.
        let r: Vec<_> = (0..7).map(|i| Shard::new(i, 7).unwrap().range(3)).collect();
        let covered: Vec<u64> = r.into_iter().flatten().collect();
        assert_eq!(covered, vec![0, 1, 2]);
    }

    #[test]
    fn shard_comes_from_flag_or_environment() {
        let none = |_: &str| None;
        assert_eq!(
            resolve(Some("2/5"), None, None, none).unwrap(),
            Some(Shard { index: 2, count: 5 })
        );
        assert_eq!(resolve(None, None, None, none).unwrap(), None);
        let pbs = |n: &str| (n == "PBS_ARRAY_INDEX").then(|| "3".to_string());
        assert_eq!(
            resolve(None, Some(4), None, pbs).unwrap(),
            Some(Shard { index: 3, count: 4 })
        );
        let mine = |n: &str| (n == "MY_INDEX").then(|| "1".to_string());
        assert_eq!(
            resolve(None, Some(2), Some("MY_INDEX"), mine).unwrap(),
            Some(Shard { index: 1, count: 2 })
        );
        let e = resolve(None, Some(4), None, none).unwrap_err().to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_ID"), "{e}");
        assert!(resolve(Some("4/4"), None, None, none).is_err());
        assert!(resolve(Some("x"), None, None, none).is_err());
    }
}
