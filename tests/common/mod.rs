//! Helpers shared by the test modules: running the `satqual` binary, fresh temporary folders,
//! loading scenes, and locating a line in scene text. The problems themselves come from
//! `satqual::catalogue`.

use satqual::spec::Scene;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `satqual` binary built with the tests, run from the repository root.
pub fn satqual() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_satqual"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// Runs `satqual args`, with `RAYON_NUM_THREADS` set when `threads` is given.
pub fn run(args: &[&str], threads: Option<&str>) -> Output {
    let mut c = satqual();
    c.args(args);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().expect("run satqual")
}

/// Runs `satqual args` and returns (exit code, stdout, stderr); −1 when killed by a signal.
pub fn run_text(args: &[&str], threads: Option<&str>) -> (i32, String, String) {
    let o = run(args, threads);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// An empty folder of its own for the test called `name`. All tests share one process, so the
/// name, not the process id, keeps two tests apart.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = run_root().join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// This run's folder, `satqual-tests/<pid>` in the system's temporary folder. The test harness
/// has no teardown, so the folders of earlier runs whose process has ended are removed here,
/// on first use (only where /proc tells which processes are alive).
fn run_root() -> &'static Path {
    static ROOT: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    ROOT.get_or_init(|| {
        let base = std::env::temp_dir().join("satqual-tests");
        let alive = |pid: &str| Path::new("/proc").join(pid).exists();
        if Path::new("/proc/self").exists()
            && let Ok(entries) = std::fs::read_dir(&base)
        {
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                if name.parse::<u32>().is_ok() && !alive(&name) {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        base.join(std::process::id().to_string())
    })
}

/// A copy of the repository file `from`, edited, in a fresh temporary folder as `NAME.EXT`
/// (the binary format readers' refusal tests).
pub fn edited_copy(from: &Path, name: &str, edit: impl Fn(&mut Vec<u8>)) -> PathBuf {
    let mut b = std::fs::read(from).unwrap();
    edit(&mut b);
    let ext = from.extension().and_then(|e| e.to_str()).unwrap_or("bin");
    let p = temp_dir(&format!("{ext}-{name}")).join(format!("{name}.{ext}"));
    std::fs::write(&p, b).unwrap();
    p
}

/// The error of `satqual psd FILE`, which must exit with 2 (bad input).
pub fn psd_error(p: &Path) -> String {
    let (code, _, err) = run_text(&["psd", p.to_str().unwrap()], None);
    assert_eq!(code, 2, "{err}");
    err
}

/// Every byte of `original[..bytes]` set in turn to 0x00, 0xFF and its value + 1, then the
/// file cut at every `cut_step`-th length from `cut_from`: each mutant is handed to `read`
/// (the binary format readers' no-panic tests).
pub fn mutate_bytes(
    original: &[u8],
    bytes: usize,
    (cut_from, cut_step): (usize, usize),
    mut read: impl FnMut(&[u8]),
) {
    for i in 0..bytes.min(original.len()) {
        for v in [0u8, 0xFF, original[i].wrapping_add(1)] {
            let mut b = original.to_vec();
            b[i] = v;
            read(&b);
        }
    }
    for n in (cut_from..original.len()).step_by(cut_step) {
        read(&original[..n]);
    }
}

/// A reference value stored as text by a reference script (Python's repr), read back to the
/// same bits: serde_json's default float parser may be off by one unit in the last place.
pub fn exact(v: &serde_json::Value) -> f64 {
    v.as_str().unwrap().parse().unwrap()
}

/// A repository file, whatever the working directory.
pub fn repo_path(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// Loads a scene; panics with its path and the error.
pub fn load(path: &str) -> Scene {
    Scene::load(Path::new(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Parses generated scene text; panics with the error.
pub fn parse(text: &str) -> Scene {
    Scene::parse(Path::new("generated.toml"), text).unwrap_or_else(|e| panic!("{e}"))
}

/// Parses `base` with its first `from` replaced by `to`, as `bad.toml`; returns the error
/// text. Panics if `base` lacks `from` or the changed scene is accepted.
pub fn scene_error(base: &str, from: &str, to: &str) -> String {
    assert!(base.contains(from), "fixture does not contain {from:?}");
    let text = base.replacen(from, to, 1);
    match Scene::parse(Path::new("bad.toml"), &text) {
        Ok(_) => panic!("scene with {to:?} was accepted"),
        Err(e) => e.to_string(),
    }
}

/// The 1-based number of the first line of `text` containing `needle`.
pub fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in the text"))
        + 1
}

/// Asserts that `error` is located in the generated scene `text` (`generated.toml`, see
/// [`parse`]) at the first line containing `needle`, and contains every one of `parts`.
pub fn assert_error_at(error: &str, text: &str, needle: &str, parts: &[&str]) {
    let line = line_of(text, needle);
    assert!(
        error.starts_with(&format!("generated.toml:{line}:")),
        "{error}"
    );
    for part in parts {
        assert!(error.contains(part), "{part:?} not in: {error}");
    }
}

/// The `[[update.parameter]]` of the round-trip cantilever that no z-bending mode feels: the
/// root spring's torsion stiffness (rx).
pub const UNFELT_TORSION: &str =
    "\n[[update.parameter]]\npath = \"spring.0.stiffness.3\"\nlower = 1e5\nupper = 1e9\n";

/// Asserts that `update` refuses the generated scene `text` at the line of `path`, as a
/// parameter the targets cannot identify, naming it with its correlation (+1.000).
pub fn assert_refused_as_unidentifiable(text: &str, path: &str) {
    let e = satqual::pipeline::workflows::update::run(&parse(text))
        .expect_err("must refuse")
        .to_string();
    let named = format!("{path} (+1.000)");
    assert_error_at(&e, text, path, &["cannot identify", &named]);
}

/// Asserts that only the last parameter of `u` is flagged not identifiable, with its warning.
pub fn assert_only_the_last_unidentifiable(u: &satqual::pipeline::workflows::update::Update) {
    let flags: Vec<bool> = u.parameters.iter().map(|p| p.identifiable).collect();
    let mut expected = vec![true; flags.len()];
    *expected.last_mut().expect("parameters") = false;
    assert_eq!(flags, expected);
    let path = &u.parameters.last().expect("parameters").path;
    let warning = format!("`{path}` is not identifiable");
    assert!(
        u.warnings.iter().any(|w| w.contains(&warning)),
        "{:?}",
        u.warnings
    );
}

/// |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A standard normal sample by Box–Muller: rand's core crate has no normal distribution.
pub fn gauss(rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
    use rand::RngExt;
    let u1: f64 = rng.random::<f64>().max(1e-300);
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Bad-input cases as a table, one `#[test]` per row. `error(from, to)` returns the error of a
/// scene with one substitution (see [`scene_error`]); the error must contain every needle and,
/// where `at` gives a line number, start with `bad.toml:LINE:` so that the user finds the key
/// (`starting` gives the expected start itself).
macro_rules! refused_input_cases {
    (error: $error:expr; $($name:ident: $from:expr => $to:expr, contains $needles:expr
        $(, at $line:expr)? $(, starting $prefix:expr)?;)+) => {
        $(
            #[test]
            fn $name() {
                let e: String = $error($from, $to);
                for needle in $needles {
                    assert!(e.contains(needle), "{needle:?} not in: {e}");
                }
                $(
                    let at = format!("bad.toml:{}:", $line);
                    assert!(e.starts_with(&at), "expected to start with {at}: {e}");
                )?
                $(
                    assert!(e.starts_with($prefix), "expected to start with {}: {e}", $prefix);
                )?
            }
        )+
    };
}

/// One FRF record (function type 4, complex double, acceleration over force) of response
/// `node` +Z to reference `reference` +Z, its values in `unit` per newton.
pub fn frf_record(id4: &str, node: i64, reference: i64, unit: &str, h: &[(f64, f64)]) -> String {
    let mut s = format!("    -1\n    58\nFRF\nNONE\nNONE\n{id4}\nNONE\n");
    s.push_str(&format!(
        "    4         0    0         0 mass      {node:10}   3 mass      {reference:10}   3\n"
    ));
    s.push_str(&format!(
        "         6{:10}         1 0.00000E+00 2.50000E-01 0.00000E+00\n",
        h.len()
    ));
    s.push_str("        18    0    0    0 Frequency            Hz                  \n");
    s.push_str(&format!(
        "        12    0    0    0 Acceleration         {unit:<20}\n"
    ));
    s.push_str("        13    0    0    0 Force                N                   \n");
    s.push_str("         0    0    0    0 NONE                 NONE                \n");
    let values: Vec<f64> = h.iter().flat_map(|&(re, im)| [re, im]).collect();
    for line in values.chunks(4) {
        let cells: String = line.iter().map(|x| format!("{x:20.11E}")).collect();
        s.push_str(&cells);
        s.push('\n');
    }
    s.push_str("    -1\n");
    s
}

/// The `name` of every entry of a command's JSON `channels` array, in order.
pub fn channel_names(v: &serde_json::Value) -> Vec<&str> {
    v["channels"]
        .as_array()
        .map(|a| a.iter().filter_map(|c| c["name"].as_str()).collect())
        .unwrap_or_default()
}
