//! Bad response input: each case gives one clear error naming the file, line and
//! key, never a panic.

fn base() -> String {
    std::fs::read_to_string("test-specs/verification/sdof-base.toml").unwrap()
}

/// Parses the SDOF scene with one substitution; returns the error text.
fn err_with(from: &str, to: &str) -> String {
    scene_error(&base(), from, to)
}

use crate::common::{line_of, scene_error};

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

refused_input_cases! {
    error: err_with;
    negative_psd_level: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "profile = [[20.0, 0.1], [2000.0, -0.1]]",
        contains ["key `random.profile[1]`", "must be positive"];
    // A third column (a tolerance, a slope) would be dropped without a word.
    three_column_profile_row: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "profile = [[20.0, 0.1, 3.0], [2000.0, 0.1]]",
        contains ["random.profile[0]", "has 3 entries, but takes 2"];
    negative_sine_level: "acceleration_g = 1.0" => "acceleration_g = -1.0",
        contains ["key `sine.segment[0].acceleration_g`", "the level must be positive, got -1"];
    negative_sine_displacement: "acceleration_g = 1.0" => "displacement_m = -1e-3",
        contains ["key `sine.segment[0].displacement_m`"];
    segment_with_both_levels: "acceleration_g = 1.0" => "acceleration_g = 1.0\ndisplacement_m = 1e-3",
        contains ["give exactly one of `displacement_m` or `acceleration_g`"];
    segment_with_a_backwards_band: "to_hz = 1000.0" => "to_hz = 5.0",
        contains ["key `sine.segment[0].to_hz`", "10 Hz to 5 Hz"];
    response_point_naming_a_missing_node: "name = \"mass\"\nnode = 2" => "name = \"mass\"\nnode = 7",
        contains ["key `response[0].node`", "response point `mass` names node 7, which is not defined"];
    q_zero: "q = 10.0" => "q = 0.0", contains ["key `damping.q`", "must"];
    q_negative: "q = 10.0" => "q = -10.0", contains ["key `damping.q`", "must"];
    zeta_zero: "q = 10.0" => "zeta = 0.0", contains ["key `damping.zeta`", "must"];
    zeta_negative: "q = 10.0" => "zeta = -0.02", contains ["key `damping.zeta`", "must"];
    damping_table_with_a_zero: "q = 10.0" => "table = [[10.0, 0.02], [100.0, 0.0]]",
        contains ["key `damping.table[1]`", "must"];
    two_damping_forms: "q = 10.0" => "q = 10.0\nzeta = 0.05",
        contains ["exactly one of `q`, `zeta` or `table`"];
    unknown_damping_key: "[damping]" => "[damping]\nqq = 3.0", contains ["unknown field `qq`"];
    unknown_axis: "axes = [\"x\"]" => "axes = [\"w\"]",
        contains ["key `sine.axes[0]`", "unknown axis `w`"];
    // Limit-level segments are multiplied by the level's factor: without a level there is none.
    limit_basis_without_level: "axes = [\"x\"]" => "axes = [\"x\"]\nbasis = \"limit\"",
        contains ["sine.basis", "limit-level segments need `level`"];
    // The same axis twice would run (and report) its sweep twice.
    axis_listed_twice: "axes = [\"x\"]" => "axes = [\"x\", \"x\"]",
        contains ["sine.axes[1]", "axis `x` is listed twice"];
    fitting_factor_below_one: "[[response]]" => "[margins]\nfitting_factor = 0.9\n\n[[response]]",
        contains ["key `margins.fitting_factor`", "at least 1"];
    preload_loss_above_one: "[[response]]" => "[margins]\npreload_loss = 1.5\n\n[[response]]",
        contains ["key `margins.preload_loss`"];
    unknown_environment: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "environment = \"atlas-v\"",
        contains ["key `random.environment`", "unknown environment `atlas-v`", "gevs-component"];
    profile_and_environment: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "profile = [[20.0, 0.1], [2000.0, 0.1]]\nenvironment = \"gevs-component\"",
        contains ["key `random.environment`", "either `profile` or `environment`"];
    neither_profile_nor_environment: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "level = \"acceptance\"",
        contains ["give a `profile`", "or a named `environment`"];
    weight_reduction_of_an_explicit_profile: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "profile = [[20.0, 0.1], [2000.0, 0.1]]\nweight_reduction = \"gevs\"",
        contains ["key `random.weight_reduction`", "environment = \"gevs-component\""];
    unknown_level: "profile = [[20.0, 0.1], [2000.0, 0.1]]" => "environment = \"gevs-component\"\nlevel = \"flight\"",
        contains ["unknown variant `flight`", "qualification"];
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
fn cli_reports_bad_input_with_exit_2() {
    let dir = crate::common::temp_dir("resp-bad");
    let p = dir.join("gap.toml");
    std::fs::write(&p, base().replacen("acceleration_g = 1.0", "acceleration_g = 1.0\n[[sine.segment]]\nfrom_hz = 1500.0\nto_hz = 2000.0\nacceleration_g = 0.5", 1)).unwrap();
    let out = crate::common::satqual()
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
    let out = crate::common::satqual()
        .args(["random", p2.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no [random] section"));
    let out = crate::common::satqual()
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

/// A `[damping] modes` entry names its mode's direction; when the model's numbering no longer
/// matches (here the paper stack's axial entry moved to mode 21, whose largest effective-mass
/// fraction is in rx), `sine` refuses
/// the scene with exit 2, naming the key's line and the lowest mode of that direction (mode 22,
/// the paper stack's first axial mode in `tests/golden/modal-paper-stack.json`).
#[test]
fn damping_given_to_a_renumbered_mode_is_refused() {
    let text = std::fs::read_to_string("test-specs/paper-stack.toml").unwrap();
    let entry = "{ mode = 22, zeta = 0.275264, direction = \"z\" }";
    assert!(text.contains(entry));
    let moved = text.replace(entry, "{ mode = 21, zeta = 0.275264, direction = \"z\" }");
    let dir = crate::common::temp_dir("resp-damping-direction");
    let p = dir.join("renumbered.toml");
    std::fs::write(&p, &moved).unwrap();
    let (code, out, err) = crate::common::run_text(&["sine", p.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 2, "{err}");
    let line = line_of(&moved, "{ mode = 21");
    assert!(
        err.contains(&format!("renumbered.toml:{line}:"))
            && err.contains("damping.modes[2].direction")
            && err.contains("the lowest `z` mode is mode 22"),
        "{err}"
    );
    assert!(out.is_empty());
    // An unknown direction is a scene error.
    let bad = text.replace(entry, "{ mode = 22, zeta = 0.275264, direction = \"up\" }");
    let e = scene_error(&bad, "", "");
    assert!(
        e.contains("damping.modes[2].direction") && e.contains("got `up`"),
        "{e}"
    );
}

/// Modes extracted only below the top of the excitation band would leave resonances inside
/// the band out of the response: the SDOF scene (fn = 100 Hz, sine to 1000 Hz, random to
/// 2000 Hz) with `modal.fmax_hz = 50` is refused by `sine` and `random` with exit 2, naming the
/// key's line and both frequencies. With fmax at the sine band's top, or with `modes = 1`, every
/// mode of this one-DOF model is extracted, so nothing is missing and both run (the random band
/// reaching above fmax then leaves out no mode).
#[test]
fn modes_stopping_below_the_excitation_band_are_refused() {
    let dir = crate::common::temp_dir("resp-truncated-basis");
    let run = |modal: &str, cmd: &str| {
        let text = format!("{}\n[modal]\n{modal}\n", base());
        let p = dir.join("truncated.toml");
        std::fs::write(&p, &text).unwrap();
        let (code, _, err) = crate::common::run_text(&[cmd, p.to_str().unwrap(), "--json"], None);
        (code, err, line_of(&text, modal))
    };
    for cmd in ["sine", "random"] {
        let (code, err, line) = run("fmax_hz = 50.0", cmd);
        let top = if cmd == "sine" { "1000.0" } else { "2000.0" };
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains(&format!("truncated.toml:{line}:"))
                && err.contains("key `modal.fmax_hz`")
                && err.contains("the modes stop at 50.0 Hz")
                && err.contains(&format!("the {cmd} band reaches {top} Hz")),
            "{err}"
        );
    }
    for (modal, cmd) in [
        ("fmax_hz = 1000.0", "sine"),
        ("fmax_hz = 1000.0", "random"),
        ("modes = 1", "sine"),
        ("modes = 1", "random"),
    ] {
        let (code, err, _) = run(modal, cmd);
        assert!(code == 0 || code == 1, "{modal} {cmd}: {err}");
    }
}

/// A `[damping] modes` entry for a mode the model cannot have (mode 5000 of the paper stack's
/// 692 DOFs) is refused at its line, not dropped without a word.
#[test]
fn damping_given_to_a_mode_beyond_the_model_is_refused() {
    let text = std::fs::read_to_string("test-specs/paper-stack.toml").unwrap();
    let entry = "{ mode = 22, zeta = 0.275264, direction = \"z\" },";
    assert!(text.contains(entry));
    let extra = text.replace(
        entry,
        &format!("{entry}\n    {{ mode = 5000, zeta = 0.05 }},"),
    );
    let dir = crate::common::temp_dir("resp-damping-beyond");
    let p = dir.join("beyond.toml");
    std::fs::write(&p, &extra).unwrap();
    let (code, _, err) =
        crate::common::run_text(&["sine", p.to_str().unwrap(), "--axis", "x"], None);
    assert_eq!(code, 2, "{err}");
    let line = line_of(&extra, "{ mode = 5000");
    assert!(
        err.contains(&format!("beyond.toml:{line}:"))
            && err.contains("damping.modes[3].mode")
            && err.contains("mode 5000 does not exist: the model has 692 DOFs"),
        "{err}"
    );
}
