//! PSDs exported as text tables by random-vibration controllers: read as they are, as a UFF58
//! PSD record is. The controller's record in data/realdata/pyuff-vibcontrol-psd/ exists both as
//! UFF58 and as a plain CSV conversion (its SOURCE.md): both must give the same spectrum.

use crate::common::{repo_path, run_text, temp_dir};
use satqual::signal::ingest::IngestOptions;
use satqual::signal::logpsd::PsdSource;
use satqual::signal::{WelchOptions, psd_of_file};
use std::path::PathBuf;

fn table(name: &str, text: &str) -> PathBuf {
    let p = temp_dir(&format!("psd-table-{name}")).join(format!("{name}.csv"));
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn a_controller_table_reads_as_its_uff58_record() {
    let d = |f: &str| repo_path(&format!("data/realdata/pyuff-vibcontrol-psd/{f}"));
    let opts = (IngestOptions::default(), WelchOptions::default());
    let csv = psd_of_file(&d("vibcontrol_random_pilot_psd.csv"), &opts.0, &opts.1).unwrap();
    let uff = psd_of_file(&d("sample_dataset58_psd.uff"), &opts.0, &opts.1).unwrap();
    assert_eq!(csv.source, PsdSource::TablePsd);
    let (a, b) = (&csv.channels[0], &uff.channels[0]);
    assert_eq!(a.psd.df, b.psd.df);
    assert_eq!(a.psd.values.len(), b.psd.values.len());
    // The CSV prints 7 significant digits of the UFF's values.
    for (x, y) in a.psd.values.iter().zip(&b.psd.values) {
        assert!((x - y).abs() <= 5e-7 * y.abs(), "{x} against {y}");
    }
    // SOURCE.md: Grms = sqrt(trapz(PSD, f)) = 0.5595 g (scipy).
    assert!((a.grms - 0.5595).abs() < 5e-5, "{}", a.grms);
    assert!((a.grms - b.grms).abs() < 1e-6 * b.grms);
}

#[test]
fn dialects_units_and_a_start_above_zero() {
    // Semicolons and decimal commas, a units row (each noted on stderr), 0.5 Hz lines printed to one decimal from
    // 20 Hz, a flat 0.04 g²/Hz and the same level in (m/s²)²/Hz, to 2000 Hz.
    let mut text = String::from(
        "# exported by a controller\nFrequency;Control;Reference\nHz;g^2/Hz;(m/s^2)^2/Hz\n",
    );
    let g2 = 9.80665f64 * 9.80665;
    for k in 0..=3960 {
        let f = 20.0 + 0.5 * k as f64;
        let line = format!("{f:.1};0,04;{}\n", 0.04 * g2);
        text.push_str(&line.replacen('.', ",", 1).replace('.', ","));
    }
    let p = table("dialect", &text);
    let (code, out, err) = run_text(&["psd", p.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["source"], "table-psd");
    // Trapezoid over the lines, zero below the first (as for a UFF58 PSD record): the flat
    // level over 20–2000 Hz plus the ramp from 19.5 Hz: 0.04 · (1980 + 0.25) g².
    let want = (0.04f64 * 1980.25).sqrt();
    for c in v["channels"].as_array().unwrap() {
        let grms = c["grms"].as_f64().unwrap();
        assert!((grms - want).abs() < 1e-9 * want, "{}: {grms}", c["name"]);
        assert_eq!(c["unit"], "g");
    }
    // The reader says how it read the table, as for a time log.
    for note in [
        "separated by semicolon",
        "decimal comma",
        "line 3: units row read",
    ] {
        assert!(err.contains(note), "`{note}` not in {err}");
    }
}

fn psd_error(name: &str, text: &str, extra: &[&str]) -> String {
    let p = table(name, text);
    let mut args = vec!["psd", p.to_str().unwrap()];
    args.extend_from_slice(extra);
    let (code, _, err) = run_text(&args, None);
    assert_eq!(code, 2, "{name}: {err}");
    err
}

#[test]
fn uneven_lines_negative_levels_and_unstated_units_are_located() {
    let e = psd_error(
        "log-spaced",
        "freq_Hz,ctrl_g2_per_Hz\n10,0.01\n20,0.01\n40,0.01\n80,0.01\n",
        &[],
    );
    assert!(e.contains("line 3:") && e.contains("evenly spaced"), "{e}");
    let e = psd_error(
        "negative",
        "freq_Hz,ctrl_g2_per_Hz\n0,0.01\n1,0.01\n2,-0.01\n3,0.01\n",
        &[],
    );
    assert!(
        e.contains("line 4:") && e.contains("negative level -0.01"),
        "{e}"
    );
    let plain = "Frequency [Hz],ch1\n0,0.01\n1,0.01\n2,0.01\n";
    let e = psd_error("no-unit", plain, &[]);
    assert!(e.contains("line 1:") && e.contains("pass --units g"), "{e}");
    let p = table("units-given", plain);
    let (code, _, err) = run_text(&["psd", p.to_str().unwrap(), "--units", "g"], None);
    assert_eq!(code, 0, "{err}");
    let e = psd_error("frf", "f,acc_re,acc_im\n0,1,0\n1,1,0\n", &[]);
    assert!(e.contains("satqual ema FILE"), "{e}");
}

#[test]
fn a_drive_density_beside_the_accelerations_is_kept_as_it_is() {
    // A controller's columns: demand and control in G²/Hz, the drive in V²/Hz (units row).
    let text = "Frequency,Demand,Control,Drive\nHz,G²/Hz,G²/Hz,V²/Hz\n\
                20,0.01,0.01,0.0001\n20.5,0.01,0.01,0.0001\n21,0.01,0.01,0.0001\n";
    let p = table("drive", text);
    let (code, out, err) = run_text(&["psd", p.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let units: Vec<&str> = v["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["unit"].as_str().unwrap())
        .collect();
    assert_eq!(units, ["g", "g", "as-is"]);
}
