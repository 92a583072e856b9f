//! Hostile input, one class per test (docs/robustness.md): sizes that would allocate without
//! bound are refused before any work with the key, the estimate and the limit; physical values
//! outside their plausible range are refused with the key and the range; no non-finite number
//! reaches an output. Every error comes with exit 2 and a location, never a panic or a hang.

use crate::common::{run_text, scene_error, temp_dir};
use satqual::response::grid::{self, GridSpec, MAX_GRID_POINTS};

fn cantilever() -> String {
    std::fs::read_to_string("test-specs/verification/cantilever.toml").unwrap()
}

fn sdof() -> String {
    std::fs::read_to_string("test-specs/verification/sdof-base.toml").unwrap()
}

fn paper_stack() -> String {
    std::fs::read_to_string("test-specs/paper-stack.toml").unwrap()
}

refused_input_cases! {
    error: |from, to| scene_error(&cantilever(), from, to);
    beam_with_a_billion_elements: "elements = 20" => "elements = 1000000000",
        contains ["key `beam[0].elements`", "1000000000 beam elements", "limit of 200000"];
    youngs_modulus_of_1e_300: "youngs_modulus_pa = 210e9" => "youngs_modulus_pa = 1e-300",
        contains ["key `material[0].youngs_modulus_pa`", "plausible range [1e5, 1e13] Pa"];
    subnormal_youngs_modulus: "youngs_modulus_pa = 210e9" => "youngs_modulus_pa = 4e-320",
        contains ["key `material[0].youngs_modulus_pa`", "must be positive", "not subnormal"];
    overflowing_youngs_modulus: "youngs_modulus_pa = 210e9" => "youngs_modulus_pa = 1.7e308",
        contains ["key `material[0].youngs_modulus_pa`", "at most 1e30"];
    nan_youngs_modulus: "youngs_modulus_pa = 210e9" => "youngs_modulus_pa = nan",
        contains ["key `material[0].youngs_modulus_pa`", "NaN is not a finite number"];
    infinite_density: "density_kg_m3 = 7850" => "density_kg_m3 = inf",
        contains ["key `material[0].density_kg_m3`", "inf is not a finite number"];
}

refused_input_cases! {
    error: |from, to| scene_error(&sdof(), from, to);
    q_of_1e300: "q = 10.0" => "q = 1e300",
        contains ["key `damping.q`", "plausible range [5e-1, 1e4]"];
    q_nan: "q = 10.0" => "q = nan", contains ["key `damping.q`", "NaN"];
    subnormal_zeta: "q = 10.0" => "zeta = 4e-320", contains ["key `damping.zeta`"];
    spring_of_1e300: "stiffness = [394784.1760435743" => "stiffness = [1e300",
        contains ["key `spring[0].stiffness[0]`", "at most 1e30"];
    mass_of_1e20: "mass_kg = 1.0" => "mass_kg = 1e20",
        contains ["key `mass[0].mass_kg`", "[1e-9, 1e9] kg (or 0)"];
    node_far_away: "position_m = [1.0, 0.0, 0.0]" => "position_m = [1e200, 0.0, 0.0]",
        contains ["key `node[1].position_m[0]`", "plausible range"];
    sine_band_to_1e300_hz: "to_hz = 1000.0" => "to_hz = 1e300",
        contains ["key `sine.segment[0].to_hz`", "[1e-6, 1e7] Hz"];
    sine_displacement_in_millimetres: "acceleration_g = 1.0" => "displacement_m = 1.17",
        contains ["key `sine.segment[0].displacement_m`", "plausible range [1e-12, 1e-1] m"];
    sine_level_nan: "acceleration_g = 1.0" => "acceleration_g = nan",
        contains ["key `sine.segment[0].acceleration_g`"];
    psd_level_subnormal: "[2000.0, 0.1]]" => "[2000.0, 1e-310]]",
        contains ["key `random.profile[1]`", "g²/Hz"];
}

refused_input_cases! {
    error: |from, to| scene_error(&paper_stack(), from, to);
    fitting_factor_of_1_7e308: "fitting_factor = 1.15" => "fitting_factor = 1.7e308",
        contains ["key `margins.fitting_factor`", "plausible range [1e0, 1e1]"];
    // A stack typed in millimetres: its pitch (550 for 0.55 m) is past any fairing, and its
    // bar diameter (20 for 0.020 m) past any guide bar.
    stack_pitch_in_millimetres: "satellite_pitch_m = 0.55" => "satellite_pitch_m = 550",
        contains ["key `stack.satellite_pitch_m`", "plausible range [1e-9, 1e1] m"];
    stack_bar_diameter_in_millimetres: "bar_diameter_m = 0.020" => "bar_diameter_m = 20",
        contains ["key `stack.bar_diameter_m`", "plausible range [1e-9, 2e0] m"];
    stack_with_huge_column_elements: "column_elements = 1" => "column_elements = 100000",
        contains ["key `stack.column_elements`", "4800000 in the columns", "limit of 200000"];
    // The count-or-word keys say what they take and what they got.
    bar_modes_as_a_float: "bar_modes = 3 " => "bar_modes = 3.0 ",
        contains ["key `separation.bar_modes`", "floating point `3.0`",
            "expected a whole number of modes per bending plane, or `rigid`"],
        at crate::common::line_of(&paper_stack(), "bar_modes = 3 ");
    negative_run_count: "runs = 59" => "runs = -5",
        contains ["key `separation.dispersion.runs`", "integer `-5`",
            "expected a whole number of runs, or `auto`"],
        at crate::common::line_of(&paper_stack(), "runs = 59");
}

#[test]
fn frequency_grid_past_its_limit_is_refused_before_allocation() {
    // One mode at 100 Hz with ζ = 1e-300: the random grid's tails (x·ζ < 0.3, x ×1.25 per
    // step) stop after ~3100 steps, and a band of 1e-100..1e100 Hz at 60 points per decade is
    // 12 000 points: admitted. A density of 1e5 per decade over 200 decades (2e7) is refused.
    let modes = [(100.0, 1e-300)];
    let ok = grid::clustered(1e-100, 1e100, &modes, GridSpec::RANDOM, &[]).unwrap();
    assert!(ok.len() < MAX_GRID_POINTS && ok.iter().all(|f| f.is_finite()));
    let dense = GridSpec {
        per_decade: 100_000,
        ..GridSpec::SINE
    };
    let e = grid::clustered(1e-100, 1e100, &modes, dense, &[]).unwrap_err();
    assert!(e.to_string().contains("limit of 2000000"), "{e}");
}

#[test]
fn frequency_grid_on_a_degenerate_band_is_an_error_not_an_abort() {
    // lo = 0 made log10(hi/lo) infinite and the point count usize::MAX: "capacity overflow".
    for (lo, hi) in [
        (0.0, 100.0),
        (-1.0, 100.0),
        (10.0, f64::NAN),
        (4e-320, 1.0),
        (5.0, 5.0),
        // The ratio overflows: no log grid spans it.
        (1e-300, 1e300),
    ] {
        let e = grid::clustered(lo, hi, &[(50.0, 0.05)], GridSpec::SINE, &[]).unwrap_err();
        assert!(e.to_string().contains("frequency band"), "{lo}..{hi}: {e}");
    }
    let e = grid::clustered(1.0, 10.0, &[(5.0, 0.0)], GridSpec::RANDOM, &[]).unwrap_err();
    assert!(e.to_string().contains("frequency grid"), "{e}");
}

#[test]
fn uff_psd_starting_at_1e15_hz_is_refused_not_zero_filled() {
    // Four lines at 1 Hz spacing from 1e15 Hz would need 1e15 zeros below them (8 PB).
    let uff = "    -1\n    58\nPSD\nx\nx\nx\nNONE\n    9         0    0         0 Pilot 1            0   0 NONE               0   0\n         2         4         1 1.000000E+15 1.000000E+00 0.000000E+00\n         0    0    0    0 Hz                   Hz\n         0    0    0    0 NONE                 NONE\n         0    0    0    0 NONE                 NONE\n         0    0    0    0 NONE                 NONE\n 1.0E-03 1.0E-03 1.0E-03 1.0E-03\n    -1\n";
    let dir = temp_dir("hostile-uff");
    let f = dir.join("far.uff");
    std::fs::write(&f, uff).unwrap();
    let (code, _, err) = run_text(&["psd", f.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("far.uff: line 2:") && err.contains("above the limit of 16777216"),
        "{err}"
    );
    // The limit is a flag: lowered below the 3201 lines of a real record, it refuses it.
    let real = "data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff";
    let (code, _, err) = run_text(&["psd", real, "--max-psd-lines", "3200"], None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("above the limit of 3200") && err.contains("--max-psd-lines"),
        "{err}"
    );
    let (code, _, err) = run_text(&["psd", real, "--max-psd-lines", "3201"], None);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn sine_with_q_1e300_exits_2_naming_the_key() {
    // The reported case: Q = 1e300 wrote `null` into the JSON with exit 0.
    let dir = temp_dir("hostile-q");
    let f = dir.join("q.toml");
    std::fs::write(&f, sdof().replace("q = 10.0", "q = 1e300")).unwrap();
    let (code, out, err) = run_text(&["sine", f.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty() && err.contains("key `damping.q`"), "{err}");
}

#[test]
fn frf_with_a_dead_force_channel_is_refused_naming_the_channel() {
    // A constant force has Gxx = 0 on every line: H1 = 0/0 wrote NaN into frf.csv with exit 0.
    let dir = temp_dir("hostile-frf");
    let f = dir.join("dead.csv");
    let mut csv = String::from("time_s,force,acceleration\n");
    for i in 0..8192 {
        let t = i as f64 / 1000.0;
        csv.push_str(&format!("{t:.6},0.0,{:.6}\n", (40.0 * t).sin()));
    }
    std::fs::write(&f, csv).unwrap();
    let out = dir.join("out");
    let (code, _, err) = run_text(
        &[
            "frf",
            f.to_str().unwrap(),
            "--input",
            "force",
            "--output",
            "acceleration",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("dead.csv") && err.contains("channel `force` is constant"),
        "{err}"
    );
}

#[test]
fn separation_inputs_that_would_run_for_minutes_are_refused() {
    // Reported: a spring of 1e12 N/m or a stroke of 1e6 m ran for minutes with no progress.
    let cases = [
        (
            "stiffness_n_m = 607.1",
            "stiffness_n_m = 1e12",
            "separation.spring.stiffness_n_m",
            "[1e-3, 1e7] N/m",
        ),
        (
            "stroke_m = 0.0803",
            "stroke_m = 1e6",
            "separation.spring.stroke_m",
            "[1e-6, 1e1] m",
        ),
        (
            "runs = 59",
            "runs = 1000000000",
            "separation.dispersion.runs",
            "limit of 100000",
        ),
    ];
    let dir = temp_dir("hostile-separation");
    let base = paper_stack();
    for (from, to, key, needle) in cases {
        assert!(base.contains(from), "{from}");
        let f = dir.join("sep.toml");
        std::fs::write(&f, base.replacen(from, to, 1)).unwrap();
        let (code, _, err) = run_text(&["separate", f.to_str().unwrap(), "--json"], None);
        assert_eq!(code, 2, "{to}: {err}");
        assert!(
            err.contains(&format!("key `{key}`")) && err.contains(needle),
            "{err}"
        );
    }
}

/// A step budget that runs out, and a tolerance the contact cannot meet, each stop the run
/// with the scene key and the stiffest element with the step it implies (the bore contact of
/// the reference stack: K = 2.5e9 N/m^1.5 on a 130 kg satellite lasts about 4.9 ms at 0.1 m/s).
#[test]
fn separation_out_of_steps_names_the_key_and_the_stiffest_element() {
    let dir = temp_dir("hostile-steps");
    let f = dir.join("steps.toml");
    let text = paper_stack().replacen("tolerance = 1e-6", "tolerance = 1e-6\nmax_steps = 500", 1);
    std::fs::write(&f, &text).unwrap();
    let (code, _, err) = run_text(&["separate", f.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 2, "{err}");
    let line = crate::common::line_of(&text, "max_steps = 500");
    assert!(
        err.contains(&format!("steps.toml:{line}:"))
            && err.contains("key `separation.max_steps`")
            && err.contains("the stiffest element is the contact")
            && err.contains("contact time of about 4.851e-3 s"),
        "{err}"
    );
}

/// Every size limit is the scene's `[limits]`: lowered, a normal scene is refused naming the
/// key that drives the size and the one that raises the limit; raised, a larger model loads.
#[test]
fn limits_are_scene_keys() {
    let with = |base: String, limits: &str| format!("{base}\n[limits]\n{limits}\n");
    let refused = |text: &str| match satqual::spec::Scene::parse("bad.toml".as_ref(), text) {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    };
    let e = refused(&with(cantilever(), "model_elements = 19"));
    assert!(
        e.contains("key `beam[0].elements`")
            && e.contains("limit of 19")
            && e.contains("`limits.model_elements`"),
        "{e}"
    );
    let e = refused(&with(cantilever(), "grid_points = 0"));
    assert!(e.contains("key `limits.grid_points`"), "{e}");
    // 300 000 elements are above the default limit and load under a raised one (the scene is
    // only validated here: nothing is assembled).
    let big = cantilever().replacen("elements = 20", "elements = 300000", 1);
    assert!(refused(&big).contains("limit of 200000"));
    crate::common::parse(&with(big, "model_elements = 400000"));
    let dir = temp_dir("hostile-limits");
    let f = dir.join("grid.toml");
    std::fs::write(&f, with(sdof(), "grid_points = 10")).unwrap();
    let (code, _, err) = run_text(&["sine", f.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("above the limit of 10") && err.contains("key `limits.grid_points`"),
        "{err}"
    );
    let f = dir.join("runs.toml");
    std::fs::write(&f, with(paper_stack(), "monte_carlo_runs = 3")).unwrap();
    let args = [
        "separate",
        f.to_str().unwrap(),
        "--monte-carlo",
        "4",
        "--seed",
        "1",
        "--json",
    ];
    let (code, _, err) = run_text(&args, None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--monte-carlo 4 is above the limit of 3")
            && err.contains("key `limits.monte_carlo_runs`"),
        "{err}"
    );
}

/// A sampling rate outside [1e-6, 1e9] Hz is refused whatever states it, naming the file and
/// the source: a LabVIEW header's Delta_X of 1e-308 s (1e308 Hz), and `--fs 1e300`.
#[test]
fn an_implausible_sampling_rate_is_refused_naming_its_source() {
    let dir = temp_dir("hostile-fs");
    let lvm = std::fs::read_to_string("data/realdata/dialects/lvm_read/short.lvm").unwrap();
    let bad = lvm.replace(
        "Delta_X\t3,906250E-5\t3,906250E-5",
        "Delta_X\t1e-308\t1e-308",
    );
    assert_ne!(bad, lvm);
    let f = dir.join("tiny-step.lvm");
    std::fs::write(&f, bad).unwrap();
    let (code, _, err) = run_text(&["srs", f.to_str().unwrap(), "--fmax", "1000"], None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("tiny-step.lvm") && err.contains("Delta_X") && err.contains("plausible range"),
        "{err}"
    );
    let csv = "data/realdata/hrshm-pcb-shock/acc_base_a0_first5ms.csv";
    let args = [
        "psd",
        csv,
        "--fs",
        "1e300",
        "--fs-override",
        "--nperseg",
        "16",
    ];
    let (code, _, err) = run_text(&args, None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--fs") && err.contains("plausible range"),
        "{err}"
    );
}
