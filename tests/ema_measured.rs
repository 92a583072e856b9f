//! `ema` on FRFs measured and exported by an acquisition system (UFF58 function type 4):
//! a roving-hammer file from pyuff's test data against sdypy-EMA reading it with pyuff, the
//! analytic 3-DOF written as a UFF, and the refusals.

use crate::common::{frf_record, rel, run_text, temp_dir};
use satqual::catalogue::analytic::three_dof;
use serde_json::Value;
use std::path::PathBuf;

const MEASUREMENT: &str = "data/realdata/dialects/pyuff/measurement.uff";

fn ema_json(args: &[&str]) -> Value {
    let mut all = vec!["ema"];
    all.extend_from_slice(args);
    all.push("--json");
    let (code, out, err) = run_text(&all, None);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

fn ema_error(args: &[&str]) -> String {
    let mut all = vec!["ema"];
    all.extend_from_slice(args);
    let (code, _, err) = run_text(&all, None);
    assert_eq!(code, 2, "{err}");
    err
}

#[test]
fn measured_frfs_of_a_roving_hammer_match_sdypy_pole_for_pole() {
    // Reference: data/ema-refs/pyuff-measurement-sdypy.json, `same_order`: sdypy-EMA 0.31.0's
    // LSCF on the same FRFs read by pyuff 2.5.8 (made by data/ema-refs/sdypy_lscf.py --uff),
    // its pole of the order satqual chose, nearest in frequency. Measured: frequency 3e-14,
    // damping 1.4e-10 (two readers of the same digits, the same normal equations); the
    // tolerances, 1e-9 and 1e-6, leave the order-60 normal equations' rounding room.
    let v = ema_json(&[MEASUREMENT, "--fmin", "1", "--fmax", "999"]);
    let m = &v["measured_frfs"];
    assert_eq!(m["layout"], "common_response");
    assert_eq!(m["common_point"], "TestCase:1:+X");
    assert_eq!(
        v["outputs"],
        serde_json::json!(["TestCase:1:+X", "TestCase:2:+X", "TestCase:3:+X"])
    );
    assert_eq!(v["frf_form"], "accelerance", "record 9's data type 12");
    assert_eq!(v["lines"], 999);
    // The |H| peaks of the file (52, 142, 279, 460, 687, 959 Hz, read off its records) are the
    // six modes: the comparison is not over an empty set.
    assert_same_poles_as_sdypy(&v, "data/ema-refs/pyuff-measurement-sdypy.json", 6);
    assert!(v["notes"][0].as_str().unwrap().contains("reciprocity"));
}

/// Each mode of `ema`'s JSON `v` against sdypy's pole of the same order nearest in frequency
/// (`same_order` of the reference file): frequency 1e-9, damping 1e-6, `count` modes.
fn assert_same_poles_as_sdypy(v: &Value, reference: &str, count: usize) {
    let text = std::fs::read_to_string(reference).unwrap();
    let refs: Value = serde_json::from_str(&text).unwrap();
    let modes = v["modes"].as_array().unwrap();
    let same = refs["same_order"].as_array().unwrap();
    assert_eq!(modes.len(), count, "{modes:?}");
    assert_eq!(same.len(), count);
    let outputs = v["outputs"].as_array().unwrap().len();
    for (m, r) in modes.iter().zip(same) {
        assert_eq!(m["order"], r["order"]);
        let f = m["frequency_hz"].as_f64().unwrap();
        let z = m["damping_ratio"].as_f64().unwrap();
        assert!(
            rel(f, r["frequency_hz"].as_f64().unwrap()) < 1e-9,
            "{f} Hz: {r}"
        );
        assert!(
            rel(z, r["damping_ratio"].as_f64().unwrap()) < 1e-6,
            "ζ {z}: {r}"
        );
        assert_eq!(m["shape"].as_array().unwrap().len(), outputs);
    }
}

#[test]
fn measured_frfs_of_a_dam_match_sdypy_pole_for_pole() {
    // Reference: data/ema-refs/uff-dam-sdypy.json, `same_order` (sdypy-EMA 0.31.0's LSCF on
    // the 26 FRFs of data/realdata/dialects/uff-dam/dam0.unv read by pyuff 2.5.8). Measured:
    // frequency 3e-14, damping 2.6e-12 at worst. (`sdypy_selection` is not compared: seeded
    // with these frequencies, sdypy's own choice returns 0 Hz for every seed, no pole it
    // counts stable at orders up to 60 on these records.) The summed |H| of the file peaks
    // at 2.47, 2.94, 3.47, 4.16, 4.63 and 11.8 Hz (pyuff): each has a mode within 1.5%.
    let v = ema_json(&[
        "data/realdata/dialects/uff-dam/dam0.unv",
        "--fmin",
        "0.5",
        "--fmax",
        "12.46875",
    ]);
    assert_eq!(v["measured_frfs"]["layout"], "common_reference");
    assert_eq!(v["measured_frfs"]["common_point"], "3:+X");
    assert_eq!(v["outputs"].as_array().unwrap().len(), 26);
    assert_same_poles_as_sdypy(&v, "data/ema-refs/uff-dam-sdypy.json", 11);
    let modes = v["modes"].as_array().unwrap();
    for peak in [2.47, 2.94, 3.47, 4.16, 4.63, 11.8] {
        assert!(
            modes
                .iter()
                .any(|m| rel(m["frequency_hz"].as_f64().unwrap(), peak) < 0.015),
            "no mode near {peak} Hz"
        );
    }
}

/// The analytic 3-DOF's accelerances (0–200 Hz, 0.25 Hz lines, force at mass 1) as a UFF of
/// three FRFs; mass 3's in g/N, the others in m/s2/N.
fn three_dof_uff(dir: &std::path::Path) -> PathBuf {
    let freqs: Vec<f64> = (0..=800).map(|k| k as f64 * 0.25).collect();
    let h = three_dof().accelerance(&freqs);
    let g = 9.80665;
    let in_g: Vec<(f64, f64)> = h[2].iter().map(|&(a, b)| (a / g, b / g)).collect();
    let text = frf_record("m1", 1, 1, "m/s2", &h[0])
        + &frf_record("m2", 2, 1, "m/s2", &h[1])
        + &frf_record("m3", 3, 1, "g", &in_g);
    let p = dir.join("three_dof.uff");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn measured_frfs_of_the_analytic_three_dof_give_its_modes() {
    // Reference: the analytic 3-DOF (catalogue::analytic::three_dof). The FRFs hold 12
    // significant digits (E20.11); the tolerances are those of the same fit on the exact
    // FRFs in tests/ema.rs (frequency 1e-7, damping 1e-5, MAC 1 - 1e-9). Mass 3's FRF is
    // stored in g/N: converted to g/N with the others (1 g = 9.80665 m/s², ISO 80000-3), the
    // shapes are the analytic ones.
    let dir = temp_dir("ema-three-dof-uff");
    let p = three_dof_uff(&dir);
    let v = ema_json(&[p.to_str().unwrap(), "--fmin", "5", "--order-max", "40"]);
    assert_eq!(v["measured_frfs"]["layout"], "common_reference");
    assert_eq!(v["measured_frfs"]["unit"], "g/N");
    assert_eq!(v["outputs"], serde_json::json!(["m1", "m2", "m3"]));
    let sys = three_dof();
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 3, "{modes:?}");
    for (r, m) in modes.iter().enumerate() {
        let f = m["frequency_hz"].as_f64().unwrap();
        let z = m["damping_ratio"].as_f64().unwrap();
        assert!(rel(f, sys.frequencies_hz[r]) < 1e-7, "mode {r}: {f} Hz");
        assert!(rel(z, sys.damping[r]) < 1e-5, "mode {r}: ζ {z}");
        let shape: Vec<f64> = m["shape"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["re"].as_f64().unwrap())
            .collect();
        let want = sys.shapes[r];
        let dot: f64 = shape.iter().zip(want).map(|(a, b)| a * b).sum();
        let n2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        let mac = dot * dot / (n2(&shape) * n2(&want));
        assert!(mac > 1.0 - 1e-9, "mode {r}: MAC {mac}");
    }
}

/// A band of 21 lines (35–40 Hz of the 3-DOF's 0.25 Hz lines) cannot carry the default model
/// order 60 (LSCF needs order + 2 lines): without --order-max the orders are lowered to 18
/// with a note, and to the orders the lines carry; an --order-max 60 the user gave is refused,
/// naming the band's line count.
#[test]
fn a_narrow_band_lowers_the_default_model_order_not_a_stated_one() {
    let dir = temp_dir("ema-narrow-band");
    let p = three_dof_uff(&dir);
    let path = p.to_str().unwrap();
    let v = ema_json(&[path, "--fmin", "35", "--fmax", "40"]);
    let notes = v["notes"].to_string();
    assert!(
        notes.contains("the band holds 21 lines: model orders up to 18"),
        "{notes}"
    );
    // Order 12 already leaves LSCF's basis matrix singular on these lines: the default fit
    // stops at the orders below it, and says so.
    assert!(
        notes.contains("model orders up to 10: LSCF order 12"),
        "{notes}"
    );
    let e = ema_error(&[path, "--fmin", "35", "--fmax", "40", "--order-max", "60"]);
    assert!(
        e.contains("the band holds 21 lines, fewer than order + 2"),
        "{e}"
    );
}

#[test]
fn measured_frfs_that_cannot_be_fitted_together_are_refused() {
    let dir = temp_dir("ema-uff-refusals");
    let p = three_dof_uff(&dir);
    let path = p.to_str().unwrap();
    let e = ema_error(&[path, "--frf-form", "mobility"]);
    assert!(
        e.contains("--frf-form mobility") && e.contains("accelerance"),
        "{e}"
    );
    let e = ema_error(&[path, "--output", "m4"]);
    assert!(e.contains("m4") && e.contains("m1, m2, m3"), "{e}");
    let e = ema_error(&[path, "--input", "7:+Z"]);
    assert!(e.contains("mass:1:+Z"), "the references are listed: {e}");
    // Another reference and another response: which FRFs belong together is not the reader's
    // guess; `--input` picks them.
    let freqs: Vec<f64> = (0..=800).map(|k| k as f64 * 0.25).collect();
    let h = three_dof().accelerance(&freqs);
    let text = std::fs::read_to_string(&p).unwrap() + &frf_record("x", 4, 2, "m/s2", &h[0]);
    let mixed = dir.join("mixed.uff");
    std::fs::write(&mixed, text).unwrap();
    let e = ema_error(&[mixed.to_str().unwrap()]);
    assert!(
        e.contains("line 2") && e.contains("2 references") && e.contains("--input"),
        "{e}"
    );
    let v = ema_json(&[mixed.to_str().unwrap(), "--input", "1:+Z", "--fmin", "5"]);
    assert_eq!(v["outputs"], serde_json::json!(["m1", "m2", "m3"]));
    // A real-valued FRF and one on other lines are refused at their record's line.
    // 8 complex points rewritten as 16 real doubles (ordinate type 4).
    let real = frf_record("m1", 1, 1, "m/s2", &h[0][..8])
        .replace("         6         8", "         4        16");
    let cut = dir.join("real.uff");
    std::fs::write(&cut, &real).unwrap();
    let e = ema_error(&[cut.to_str().unwrap()]);
    assert!(e.contains("line 2") && e.contains("real values"), "{e}");
    let short = std::fs::read_to_string(&p).unwrap() + &frf_record("m9", 9, 1, "g", &h[0][..400]);
    let other = dir.join("lines.uff");
    std::fs::write(&other, short).unwrap();
    let e = ema_error(&[other.to_str().unwrap()]);
    assert!(
        e.contains("other frequency lines") && e.contains("400 lines"),
        "{e}"
    );
    let empty = dir.join("empty.uff");
    std::fs::write(&empty, frf_record("m1", 1, 1, "g", &[])).unwrap();
    let e = ema_error(&[empty.to_str().unwrap()]);
    assert!(
        e.contains("line 2") && e.contains("no frequency line"),
        "{e}"
    );
    // The commands that read time histories point measured FRFs to `ema`.
    let (code, _, e) = run_text(&["frf", MEASUREMENT, "--input", "a", "--output", "b"], None);
    assert!(code == 2 && e.contains("satqual ema FILE"), "{e}");
    // Time logs still need their force channel.
    let e = ema_error(&[
        "data/realdata/pyfrf-impact/impact_1.csv",
        "--output",
        "acceleration",
    ]);
    assert!(e.contains("--input"), "{e}");
}

/// `--export-frf` writes the FRFs as a table (frequency, then `X_re, X_im`); read back, the
/// same lines give the same modes to the last digit of the JSON (the CSV holds 17 significant
/// digits, a double's round trip). A magnitude/phase table of the same FRFs, phase in degrees,
/// gives them to 1e-9 (the polar form's rounding). References: the time-log run itself.
#[test]
fn an_frf_table_round_trips_through_ema() {
    let dir = temp_dir("ema-frf-table");
    let table = dir.join("frf.csv");
    let table_arg = table.to_str().unwrap();
    let logs = ema_json(&[
        "data/realdata/pyfrf-impact/impact_1.csv",
        "--input",
        "force",
        "--output",
        "acceleration",
        "--fmin",
        "50",
        "--fmax",
        "6400",
        "--export-frf",
        table_arg,
    ]);
    let read_back = ema_json(&[table_arg, "--fmin", "50", "--fmax", "6400"]);
    assert_eq!(
        read_back["measured_frfs"]["records"][0]["channel"],
        "acceleration"
    );
    assert!(!logs["modes"].as_array().unwrap().is_empty());
    assert_eq!(logs["modes"], read_back["modes"]);
    let text = std::fs::read_to_string(&table).unwrap();
    let mut polar = String::from("Frequency [Hz];acc magnitude;acc phase [deg]\n");
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        let (m, p) = (v[1].hypot(v[2]), v[2].atan2(v[1]).to_degrees());
        polar.push_str(&format!("{:.17e};{m:.17e};{p:.17e}\n", v[0]));
    }
    let polar_path = dir.join("polar.csv");
    std::fs::write(&polar_path, &polar).unwrap();
    let p = ema_json(&[
        polar_path.to_str().unwrap(),
        "--fmin",
        "50",
        "--fmax",
        "6400",
    ]);
    let (a, b) = (
        logs["modes"].as_array().unwrap(),
        p["modes"].as_array().unwrap(),
    );
    assert_eq!(a.len(), b.len());
    // The semicolon table's dialect is in the notes, as a log's would be.
    assert!(
        p["notes"]
            .to_string()
            .contains("fields separated by semicolon"),
        "{}",
        p["notes"]
    );
    for (x, y) in a.iter().zip(b) {
        let f = |m: &Value, k: &str| m[k].as_f64().unwrap();
        assert!(
            rel(f(y, "frequency_hz"), f(x, "frequency_hz")) < 1e-9,
            "{x} {y}"
        );
        assert!(
            rel(f(y, "damping_ratio"), f(x, "damping_ratio")) < 1e-6,
            "{x} {y}"
        );
    }
    // A magnitude in dB, or a phase without its unit, is not read as a guess.
    let db = polar.replace("acc magnitude", "acc magnitude [dB]");
    std::fs::write(&polar_path, db).unwrap();
    let e = ema_error(&[polar_path.to_str().unwrap()]);
    assert!(e.contains("line 1") && e.contains("dB"), "{e}");
    let bare = polar.replace("acc phase [deg]", "acc phase");
    std::fs::write(&polar_path, bare).unwrap();
    let e = ema_error(&[polar_path.to_str().unwrap()]);
    assert!(e.contains("line 1") && e.contains("phase's unit"), "{e}");
}

/// The file's one record is a PSD (its `58` marker on line 2): named at its line, by its
/// function type and name, as the other readers name a record they cannot use.
#[test]
fn a_uff_of_spectra_is_no_input_for_ema() {
    let e = ema_error(&["data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff"]);
    assert!(
        e.contains("sample_dataset58_psd.uff: line 2: record `Channel 1` is function type 9 (power spectral density)")
            && e.contains("no record is an FRF"),
        "{e}"
    );
}
