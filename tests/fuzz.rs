//! Mutation fuzzing of every command's input path, on stable Rust: the release binary runs as
//! a child process on mutants of the seed corpus (`tests/fuzz/seeds.txt`: the repository's own
//! scenes and logs) and on every file of `tests/fuzz/regressions/`. The properties, from the
//! robustness contract (docs/robustness.md):
//! - the exit code is 0, 1 or 2 (no panic, no abort, no kill by the allocator);
//! - on 2, one `satqual: error:` message that says where (file, line, key or channel);
//! - on 0 or 1, no NaN or infinity in stdout or stderr;
//! - each case ends: a watchdog catches hangs (300 s, a thousand times a case's usual cost).
//!   The slowest case's time is printed, a measurement against the contract's 20 s per-case
//!   budget, never asserted: speed belongs to `satqual bench`, not to a test on a loaded machine.
//!
//! The normal test run fuzzes a fixed number of cases (`DEFAULT_CASES`); `SATQUAL_FUZZ_SECS=N` runs
//! N seconds instead (long mode) and `SATQUAL_FUZZ_SEED` picks the seed. The mutants come from a
//! seeded ChaCha generator, so a seed reproduces its sequence. A failing mutant is written to the
//! temporary folder and named in the failure; once its class is fixed it is copied into
//! `tests/fuzz/regressions/` as `CMD--NAME.EXT`.

use crate::common::{repo_path, temp_dir};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The hang watchdog: a case runs in 0.05–0.5 s, so only a hang reaches it.
const HANG_LIMIT: Duration = Duration::from_secs(300);
/// The contract's per-case budget (docs/robustness.md).
const CASE_BUDGET: Duration = Duration::from_secs(20);
/// Cases of the normal test run: a fixed count, so the run checks the same mutants on any
/// machine at any load (a time budget made the cases covered depend on the machine's speed).
/// About 40–60 s on 2 cores.
const DEFAULT_CASES: usize = 600;

/// One seed: the command line, and which argument is the file to mutate.
#[derive(Debug, Clone)]
struct Seed {
    args: Vec<String>,
    file_arg: usize,
}

impl Seed {
    fn command(&self) -> &str {
        &self.args[0]
    }
    fn extension(&self) -> String {
        ext_of(Path::new(&self.args[self.file_arg]))
    }
    fn text(&self) -> Vec<u8> {
        std::fs::read(repo_path(&self.args[self.file_arg])).expect("seed file")
    }
    /// The command line with the mutated file in place of the seed's.
    fn with_file(&self, file: &Path) -> Vec<String> {
        let mut a = self.args.clone();
        a[self.file_arg] = file.display().to_string();
        a
    }
}

fn ext_of(p: &Path) -> String {
    p.extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn seeds() -> Vec<Seed> {
    let text = std::fs::read_to_string(repo_path("tests/fuzz/seeds.txt")).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let args: Vec<String> = l.split_whitespace().map(String::from).collect();
            let file_arg = (1..args.len())
                .find(|&i| repo_path(&args[i]).is_file())
                .unwrap_or_else(|| panic!("seed without a repository file: {l}"));
            Seed { args, file_arg }
        })
        .collect()
}

/// Values a mutated number takes: zero, negative, overflowing, subnormal, not-a-number, and
/// integers too large for any count.
const HOSTILE_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1e300",
    "-1e300",
    "1e-300",
    "1e-308",
    "4e-320",
    "1.7e308",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "99999999999",
    "100000",
    "1e15",
    "18446744073709551615",
];

fn pick(rng: &mut ChaCha8Rng, n: usize) -> usize {
    (rng.next_u64() % n.max(1) as u64) as usize
}

/// Byte ranges of the number literals of a text.
fn numbers(text: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit()
            || (text[i] == b'-' && text.get(i + 1).is_some_and(u8::is_ascii_digit));
        let after_word = i > 0 && (text[i - 1].is_ascii_alphabetic() || text[i - 1] == b'_');
        if starts && !after_word {
            let mut j = i + 1;
            while j < text.len() && (text[j].is_ascii_digit() || b".eE+-".contains(&text[j])) {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// One random mutation: a number replaced, a byte changed, a line deleted or duplicated.
fn mutate_once(rng: &mut ChaCha8Rng, text: &mut Vec<u8>) {
    match pick(rng, 10) {
        0..=5 => {
            let nums = numbers(text);
            if nums.is_empty() {
                return;
            }
            let (a, b) = nums[pick(rng, nums.len())];
            let v = HOSTILE_NUMBERS[pick(rng, HOSTILE_NUMBERS.len())];
            text.splice(a..b, v.bytes());
        }
        6 => {
            if !text.is_empty() {
                let i = pick(rng, text.len());
                text[i] = (rng.next_u32() & 0xff) as u8;
            }
        }
        7 | 8 => {
            let lines: Vec<usize> = line_starts(text);
            let k = pick(rng, lines.len());
            let end = lines.get(k + 1).copied().unwrap_or(text.len());
            text.drain(lines[k]..end);
        }
        _ => {
            let lines: Vec<usize> = line_starts(text);
            let k = pick(rng, lines.len());
            let end = lines.get(k + 1).copied().unwrap_or(text.len());
            let line = text[lines[k]..end].to_vec();
            text.splice(end..end, line);
        }
    }
}

fn line_starts(text: &[u8]) -> Vec<usize> {
    std::iter::once(0)
        .chain(memchr_newlines(text).map(|i| i + 1))
        .filter(|&i| i < text.len())
        .collect()
}

fn memchr_newlines(text: &[u8]) -> impl Iterator<Item = usize> + '_ {
    text.iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .map(|(i, _)| i)
}

/// Outcome of one case: its wall time, or in `Err` the property it broke.
fn run_case(args: &[String], input: &Path) -> Result<Duration, String> {
    let out_dir = input.with_extension("out");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_satqual"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .env("RAYON_NUM_THREADS", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let _ = std::fs::remove_dir_all(&out_dir);
    let mut child = cmd.spawn().map_err(|e| format!("spawn: {e}"))?;
    // Drain the pipes on threads, so a child that writes much never blocks on a full pipe.
    let mut so = child.stdout.take().unwrap();
    let mut se = child.stderr.take().unwrap();
    let ho = std::thread::spawn(move || read_all(&mut so));
    let he = std::thread::spawn(move || read_all(&mut se));
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if t0.elapsed() > HANG_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("no end within {} s", HANG_LIMIT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let took = t0.elapsed();
    let stdout = ho.join().unwrap();
    let stderr = he.join().unwrap();
    check_outcome(status.code(), &stdout, &stderr, input).map(|()| took)
}

fn read_all(r: &mut impl std::io::Read) -> String {
    let mut v = Vec::new();
    let _ = r.read_to_end(&mut v);
    String::from_utf8_lossy(&v).into_owned()
}

/// The properties of the contract on one finished run.
fn check_outcome(
    code: Option<i32>,
    stdout: &str,
    stderr: &str,
    input: &Path,
) -> Result<(), String> {
    match code {
        Some(0 | 1) => {
            for (name, text) in [("stdout", stdout), ("stderr", stderr)] {
                if let Some(t) = non_finite_token(text) {
                    return Err(format!("exit {code:?} with `{t}` in {name}"));
                }
            }
            Ok(())
        }
        Some(2) => {
            // Notes may come first (what the reader or a default decided); the error is the
            // message from "satqual: error:" on, and that message must carry the location.
            let error = stderr
                .lines()
                .position(|l| l.starts_with("satqual: error:"))
                .map(|i| stderr.lines().skip(i).collect::<Vec<_>>().join("\n"));
            let located = error.is_some_and(|e| {
                e.contains(&*input.file_name().unwrap().to_string_lossy())
                    || e.contains("key `")
                    || e.contains("line ")
                    || e.contains("channel")
            });
            if located {
                Ok(())
            } else {
                Err(format!("exit 2 without a located message: {stderr}"))
            }
        }
        other => Err(format!(
            "exit {other:?} (killed or aborted): {}",
            stderr.lines().last().unwrap_or("")
        )),
    }
}

/// The first word of `text` that is a non-finite number as Rust or serde would print it.
/// Quoted text (JSON and TOML strings: titles, names) is passed over: a number is never quoted.
fn non_finite_token(text: &str) -> Option<&str> {
    text.split('"').step_by(2).find_map(non_finite_word)
}

fn non_finite_word(text: &str) -> Option<&str> {
    text.split(|c: char| c.is_whitespace() || ",;:()[]{}\"=|".contains(c))
        .map(|w| w.trim_end_matches('.'))
        .find(|w| matches!(*w, "NaN" | "inf" | "-inf" | "+inf" | "-NaN"))
}

/// Long mode's time budget, when `SATQUAL_FUZZ_SECS` is set.
fn fuzz_seconds() -> Option<u64> {
    std::env::var("SATQUAL_FUZZ_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
}

fn fuzz_seed() -> u64 {
    std::env::var("SATQUAL_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
}

/// One mutant of `seed` in `dir`, named by its case number.
fn write_mutant(rng: &mut ChaCha8Rng, seed: &Seed, dir: &Path, case: usize) -> PathBuf {
    let mut text = seed.text();
    for _ in 0..1 + pick(rng, 3) {
        mutate_once(rng, &mut text);
    }
    let path = dir.join(format!(
        "{}--case{case}.{}",
        seed.command(),
        seed.extension()
    ));
    std::fs::write(&path, &text).unwrap();
    path
}

#[test]
fn mutants_of_the_seed_corpus_keep_the_contract() {
    let seeds = seeds();
    let dir = temp_dir("fuzz-mutants");
    let mut rng = ChaCha8Rng::seed_from_u64(fuzz_seed());
    let budget = fuzz_seconds().map(Duration::from_secs);
    let t0 = Instant::now();
    let mut failures = Vec::new();
    let mut cases = 0;
    let mut slowest = Duration::ZERO;
    // Cases over the contract's per-case budget: kept on disk and listed, not failed (a loaded
    // machine stretches any case), so that a slow class can be found and fixed.
    let mut slow: Vec<String> = Vec::new();
    let more = |cases: usize| match budget {
        Some(b) => t0.elapsed() < b,
        None => cases < DEFAULT_CASES,
    };
    while more(cases) {
        let seed = &seeds[cases % seeds.len()];
        let path = write_mutant(&mut rng, seed, &dir, cases);
        match run_case(&seed.with_file(&path), &path) {
            Ok(took) => {
                slowest = slowest.max(took);
                if took > CASE_BUDGET {
                    slow.push(format!("{} ({:.1} s)", path.display(), took.as_secs_f64()));
                } else {
                    let _ = std::fs::remove_file(&path);
                }
            }
            Err(e) => failures.push(format!("{}: {e}", path.display())),
        }
        cases += 1;
    }
    eprintln!(
        "fuzz: {cases} cases in {:.0} s (seed {}), slowest {:.2} s, {} failures",
        t0.elapsed().as_secs_f64(),
        fuzz_seed(),
        slowest.as_secs_f64(),
        failures.len()
    );
    for s in &slow {
        eprintln!("fuzz: over the {} s budget: {s}", CASE_BUDGET.as_secs());
    }
    // At least one case per seed, or the budget measured nothing.
    assert!(cases >= seeds.len(), "only {cases} cases ran");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_regression_file_keeps_the_contract() {
    let seeds = seeds();
    let dir = repo_path("tests/fuzz/regressions");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && p.extension().is_some())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no regression file in {}", dir.display());
    let work = temp_dir("fuzz-regressions");
    let mut failures = Vec::new();
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let command = name.split("--").next().unwrap();
        let seed = seeds
            .iter()
            .find(|s| s.command() == command && s.extension() == ext_of(f))
            .unwrap_or_else(|| panic!("{name}: no seed runs `{command}` on .{}", ext_of(f)));
        // Run a copy, so that outputs land in the temporary folder, not in the corpus.
        let copy = work.join(&name);
        std::fs::copy(f, &copy).unwrap();
        if let Err(e) = run_case(&seed.with_file(&copy), &copy) {
            failures.push(format!("{name}: {e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_mutator_finds_numbers_and_keeps_words() {
    // Hand-checked: `x2 = 1.5e3` has one number literal (`x2` is a key), `[-4, 7]` two.
    let t = b"x2 = 1.5e3\nv = [-4, 7]\n";
    let n: Vec<&[u8]> = numbers(t).iter().map(|&(a, b)| &t[a..b]).collect();
    assert_eq!(n, vec![&b"1.5e3"[..], b"-4", b"7"]);
    assert_eq!(non_finite_token("peak: NaN g"), Some("NaN"));
    assert_eq!(non_finite_token("infinite margin, info"), None);
}
