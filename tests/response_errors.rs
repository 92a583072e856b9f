//! Bad response input (issue 4): each case gives one clear error naming the file, line and
//! key, never a panic.

use satqual::spec::Scene;
use std::path::Path;

fn base() -> String {
    std::fs::read_to_string("test-specs/verification/sdof-base.toml").unwrap()
}

/// Parses the SDOF scene with one substitution; returns the error text.
fn err_with(from: &str, to: &str) -> String {
    let b = base();
    assert!(b.contains(from), "fixture lacks {from:?}");
    let text = b.replacen(from, to, 1);
    match Scene::parse(Path::new("bad.toml"), &text) {
        Ok(_) => panic!("scene with {to:?} was accepted"),
        Err(e) => e.to_string(),
    }
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle")
        + 1
}

#[test]
fn profile_with_non_increasing_frequencies() {
    let e = err_with(
        "profile = [[20.0, 0.1], [2000.0, 0.1]]",
        "profile = [[20.0, 0.1], [2000.0, 0.1], [1500.0, 0.1]]",
    );
    assert!(e.contains("key `random.profile[2]`"), "{e}");
    assert!(e.contains("must increase: 1500 Hz follows 2000 Hz"), "{e}");
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(&base(), "profile = "))),
        "{e}"
    );
}

#[test]
fn negative_psd_level() {
    let e = err_with(
        "profile = [[20.0, 0.1], [2000.0, 0.1]]",
        "profile = [[20.0, 0.1], [2000.0, -0.1]]",
    );
    assert!(
        e.contains("key `random.profile[1]`") && e.contains("must be positive"),
        "{e}"
    );
}

#[test]
fn negative_sine_level() {
    let e = err_with("acceleration_g = 1.0", "acceleration_g = -1.0");
    assert!(e.contains("key `sine.segment[0].acceleration_g`"), "{e}");
    assert!(e.contains("the level must be positive, got -1"), "{e}");
    let e = err_with("acceleration_g = 1.0", "displacement_m = -1e-3");
    assert!(e.contains("key `sine.segment[0].displacement_m`"), "{e}");
}

#[test]
fn sine_segment_gap_and_overlap() {
    let two = |from: f64| {
        format!(
            "acceleration_g = 1.0\n[[sine.segment]]\nfrom_hz = {from}\nto_hz = 2000.0\nacceleration_g = 0.5"
        )
    };
    let e = err_with("acceleration_g = 1.0", &two(1200.0));
    assert!(e.contains("key `sine.segment[1].from_hz`"), "{e}");
    assert!(
        e.contains(
            "a gap between segments: segment 0 ends at 1000 Hz but this one starts at 1200 Hz"
        ),
        "{e}"
    );
    let e = err_with("acceleration_g = 1.0", &two(900.0));
    assert!(e.contains("an overlap between segments"), "{e}");
    // The error points at the second segment's from_hz line.
    let text = base().replacen("acceleration_g = 1.0", &two(900.0), 1);
    let line = text
        .lines()
        .position(|l| l.contains("from_hz = 900"))
        .unwrap()
        + 1;
    assert!(e.starts_with(&format!("bad.toml:{line}:")), "{e}");
}

#[test]
fn segment_with_both_or_no_levels_and_backwards_band() {
    let e = err_with(
        "acceleration_g = 1.0",
        "acceleration_g = 1.0\ndisplacement_m = 1e-3",
    );
    assert!(
        e.contains("give exactly one of `displacement_m` or `acceleration_g`"),
        "{e}"
    );
    let e = err_with("to_hz = 1000.0", "to_hz = 5.0");
    assert!(
        e.contains("key `sine.segment[0].to_hz`") && e.contains("10 Hz to 5 Hz"),
        "{e}"
    );
}

#[test]
fn response_point_naming_a_missing_node() {
    let e = err_with("name = \"mass\"\nnode = 2", "name = \"mass\"\nnode = 7");
    assert!(e.contains("key `response[0].node`"), "{e}");
    assert!(
        e.contains("response point `mass` names node 7, which is not defined"),
        "{e}"
    );
}

#[test]
fn damping_not_positive() {
    for (to, key) in [
        ("q = 0.0", "damping.q"),
        ("q = -10.0", "damping.q"),
        ("zeta = 0.0", "damping.zeta"),
        ("zeta = -0.02", "damping.zeta"),
        ("table = [[10.0, 0.02], [100.0, 0.0]]", "damping.table[1]"),
    ] {
        let e = err_with("q = 10.0", to);
        assert!(e.contains(&format!("key `{key}`")), "{to}: {e}");
        assert!(e.contains("must"), "{to}: {e}");
    }
    let e = err_with("q = 10.0", "q = 10.0\nzeta = 0.05");
    assert!(e.contains("exactly one of `q`, `zeta` or `table`"), "{e}");
}

#[test]
fn unknown_keys_axes_and_margins() {
    let e = err_with("[damping]", "[damping]\nqq = 3.0");
    assert!(e.contains("unknown field `qq`"), "{e}");
    let e = err_with("axes = [\"x\"]", "axes = [\"w\"]");
    assert!(
        e.contains("key `sine.axes[0]`") && e.contains("unknown axis `w`"),
        "{e}"
    );
    let e = err_with(
        "[[response]]",
        "[margins]\nfitting_factor = 0.9\n\n[[response]]",
    );
    assert!(
        e.contains("key `margins.fitting_factor`") && e.contains("at least 1"),
        "{e}"
    );
    let e = err_with(
        "[[response]]",
        "[margins]\npreload_loss = 1.5\n\n[[response]]",
    );
    assert!(e.contains("key `margins.preload_loss`"), "{e}");
}

#[test]
fn cli_reports_bad_input_with_exit_2() {
    let dir = std::env::temp_dir().join(format!("satqual-resp-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("gap.toml");
    std::fs::write(&p, base().replacen("acceleration_g = 1.0", "acceleration_g = 1.0\n[[sine.segment]]\nfrom_hz = 1500.0\nto_hz = 2000.0\nacceleration_g = 0.5", 1)).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_satqual"))
        .args(["sine", p.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("gap.toml:") && err.contains("sine.segment[1].from_hz"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.stdout.is_empty());
    // A scene without [random] asked for a random run.
    let p2 = dir.join("nor.toml");
    let b = base();
    let cut = b.find("[random]").unwrap();
    let end = b.find("[[response]]").unwrap();
    std::fs::write(&p2, format!("{}{}", &b[..cut], &b[end..])).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_satqual"))
        .args(["random", p2.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no [random] section"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_satqual"))
        .args([
            "sine",
            "test-specs/verification/sdof-base.toml",
            "--axis",
            "q",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--axis must be x, y or z"));
    let _ = std::fs::remove_dir_all(&dir);
}
