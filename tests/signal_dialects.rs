//! Log dialects as labs export them: each rule of the reader on a synthetic file holding a
//! 50 Hz sine of amplitude 2 sampled at 1000 Hz for exactly 1 s (50 whole periods), so the
//! reference values are analytic: RMS = 2/√2 and fs = 1000 Hz. Values are written with 9
//! decimals, so the RMS must match to 1e-6 relative and the rate to 1e-9 relative.

use satqual::signal::ingest::{IngestOptions, TimeUnit, Unit, read_csv};
use std::path::PathBuf;

const FS: f64 = 1000.0;
const N: usize = 1000;

fn sample(i: usize) -> f64 {
    2.0 * (2.0 * std::f64::consts::PI * 50.0 * i as f64 / FS).sin()
}

/// Writes `text` to a fresh file called `name`.
fn write(name: &str, text: &str) -> PathBuf {
    let dir = crate::common::temp_dir(&format!("dialect-{name}"));
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Rows `time<sep>value`, times scaled by `time_scale` (1 for seconds, 1e3 for ms, ...).
fn rows(sep: &str, time_scale: f64, time_offset: f64, decimal_comma: bool) -> String {
    let mut s = String::new();
    for i in 0..N {
        let t = format!("{:.9}", time_offset + i as f64 / FS * time_scale);
        let v = format!("{:.9}", sample(i));
        let (t, v) = if decimal_comma {
            (t.replace('.', ","), v.replace('.', ","))
        } else {
            (t, v)
        };
        s.push_str(&format!("{t}{sep}{v}\n"));
    }
    s
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// The reader's error for a log it must refuse, as text.
fn read_error(p: &std::path::Path) -> String {
    read_csv(p, &IngestOptions::default())
        .unwrap_err()
        .to_string()
}

/// Asserts that one of the reader's notes contains `needle`.
fn assert_note(log: &satqual::signal::Log, needle: &str) {
    let notes = &log.info.ingest.notes;
    assert!(
        notes.iter().any(|n| n.contains(needle)),
        "`{needle}` not in {notes:?}"
    );
}

/// The analytic checks: 1000 Hz (1e-9 relative), RMS 2/√2 (1e-6 relative), N samples.
fn check(p: &std::path::Path, opts: &IngestOptions, channel: &str) -> satqual::signal::Log {
    let log = read_csv(p, opts).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        (log.info.fs_hz - FS).abs() < FS * 1e-9,
        "fs {}",
        log.info.fs_hz
    );
    let x = log.channel(channel).unwrap();
    assert_eq!(x.len(), N);
    let want = 2.0 / 2f64.sqrt();
    assert!((rms(x) - want).abs() < want * 1e-6, "rms {}", rms(x));
    log
}

#[test]
fn semicolon_with_decimal_comma() {
    let p = write(
        "semi.csv",
        &format!("time;acc_g\n{}", rows(";", 1.0, 0.0, true)),
    );
    let log = check(&p, &IngestOptions::default(), "acc_g");
    assert_eq!(log.info.ingest.delimiter, "semicolon");
    assert_eq!(log.info.ingest.decimal, ",");
}

#[test]
fn tab_separated_headerless_needs_columns() {
    let p = write("tab.txt", &rows("\t", 1.0, 0.0, false));
    let err = read_error(&p);
    assert!(
        err.contains("tab.txt") && err.contains("line 1") && err.contains("--columns"),
        "{err}"
    );
    let opts = IngestOptions {
        columns: Some(vec!["time".into(), "acc_g".into()]),
        ..Default::default()
    };
    let log = check(&p, &opts, "acc_g");
    assert_eq!(log.info.ingest.delimiter, "tab");
}

#[test]
fn whitespace_separated_with_blank_first_line_and_comments() {
    let text = format!(
        "\n# exported by a logger\n# channel 1: accelerometer\ntime   acc_g\n{}",
        rows("   ", 1.0, 0.0, false)
    );
    let p = write("ws.dat", &text);
    let log = check(&p, &IngestOptions::default(), "acc_g");
    assert_eq!(log.info.ingest.delimiter, "whitespace");
    assert_eq!(log.info.ingest.skipped_lines, 2);
}

#[test]
fn key_value_preamble_units_row_bom_crlf_and_quotes() {
    let body = rows(",", 1.0, 0.0, false).replace('\n', "\r\n");
    let text = format!(
        "\u{feff}Device: DAQ-9\r\nDate: 2024-05-01\r\n\"time\",\"acc\"\r\n\"s\",\"g\"\r\n{body}"
    );
    let p = write("preamble.csv", &text);
    let log = check(&p, &IngestOptions::default(), "acc");
    assert_eq!(log.info.ingest.skipped_lines, 2);
    // The units row states g for `acc`, whose name states none.
    assert_eq!(log.info.channels[0].unit, satqual::signal::Unit::G);
}

#[test]
fn trailing_delimiter_and_sample_rate_in_first_row_only() {
    // The benchmark layout: header ends with a delimiter, `Fs` filled only in the first row,
    // no time column: the rate comes from the metadata column.
    let mut text = String::from("\"a\",\"b\",\"Fs\",\n");
    for i in 0..N {
        let fs = if i == 0 { "1000" } else { "" };
        text.push_str(&format!("{:.9},{:.9},{fs},\n", sample(i), -sample(i)));
    }
    let p = write("bench.csv", &text);
    let opts = IngestOptions {
        channels: Some(vec!["a".into(), "b".into()]),
        ..Default::default()
    };
    let log = check(&p, &opts, "a");
    assert_eq!(log.info.ingest.metadata, vec![("Fs".to_string(), 1000.0)]);
    assert!(
        log.info
            .ingest
            .ignored_columns
            .contains(&"column 4".to_string())
    );
    // Without --channels the empty and metadata columns are not channels either.
    let log = check(&p, &IngestOptions::default(), "b");
    assert_eq!(log.info.channels.len(), 2);
}

#[test]
fn time_in_milliseconds_and_epoch_nanoseconds() {
    let p = write(
        "ms.csv",
        &format!("time_ms,acc_g\n{}", rows(",", 1e3, 0.0, false)),
    );
    let log = check(&p, &IngestOptions::default(), "acc_g");
    assert_eq!(log.info.ingest.time_unit, Some(TimeUnit::Ms));
    assert_eq!(log.info.channels.len(), 1);
    // Epoch timestamps in s, ms, µs and ns (2023: 1.7e9 s). A bare `timestamp` name states no
    // unit; the size does (the four ranges of the years 2001–2286 are three decades apart),
    // and a note says so. f64 holds 1.7e18 to 256 ns: the rate over the span is good to 1e-6.
    for (unit, per_s) in [
        (TimeUnit::S, 1u64),
        (TimeUnit::Ms, 1_000),
        (TimeUnit::Us, 1_000_000),
        (TimeUnit::Ns, 1_000_000_000),
    ] {
        let mut text = String::from("timestamp,acc_g\n");
        for i in 0..N {
            let t = 1_700_000_000.0 + i as f64 / FS;
            // Seconds with their fraction written out, the other units as integers.
            let digits = if per_s == 1 { 3 } else { 0 };
            text.push_str(&format!(
                "{:.*},{:.9}\n",
                digits,
                t * per_s as f64,
                sample(i)
            ));
        }
        let p = write(&format!("epoch_{per_s}.csv"), &text);
        let log = read_csv(&p, &IngestOptions::default()).unwrap();
        assert_eq!(log.info.ingest.time_unit, Some(unit));
        assert_note(&log, "epoch");
        assert!(
            (log.info.fs_hz - FS).abs() < FS * 1e-6,
            "{}",
            log.info.fs_hz
        );
    }
    // Between the ranges (1.7e17: neither µs nor ns of a plausible date) the unit cannot be
    // told: a located error asks for it.
    let p = write(
        "epoch_odd.csv",
        "timestamp,acc_g\n170000000000000000,0\n170000000001000000,1\n",
    );
    let err = read_error(&p);
    assert!(
        err.contains("line 2") && err.contains("--time-unit"),
        "{err}"
    );
}

#[test]
fn fs_disagreeing_with_the_time_column_is_an_error() {
    let p = write(
        "t.csv",
        &format!("time,acc_g\n{}", rows(",", 1.0, 0.0, false)),
    );
    // 0.3% off, as 3210 Hz on a 3200 Hz log.
    let opts = IngestOptions {
        fs: Some(1003.0),
        ..Default::default()
    };
    let err = read_csv(&p, &opts).unwrap_err().to_string();
    assert!(
        err.contains("1003") && err.contains("1000") && err.contains("--fs-override"),
        "{err}"
    );
    let opts = IngestOptions {
        fs: Some(1003.0),
        fs_override: true,
        ..Default::default()
    };
    let log = read_csv(&p, &opts).unwrap();
    assert_eq!(log.info.fs_hz, 1003.0);
    assert_eq!(log.info.time_column, None);
}

#[test]
fn psd_json_carries_the_ingest_record_and_stderr_the_decisions() {
    let p = write(
        "semi-cli.csv",
        &format!("time;acc_g\n{}", rows(";", 1.0, 0.0, true)),
    );
    let (v, err) = psd_with(&p, &[]);
    assert_eq!(v["ingest"]["delimiter"], "semicolon");
    assert_eq!(v["ingest"]["decimal"], ",");
    assert_eq!(err.matches("decimal comma").count(), 1, "{err}");
}

/// A UFF58 time history (function type 1, real single, 1 ms step) whose record 9 holds the
/// axis label `axis` and the units label `unit`.
fn uff58(axis: &str, unit: &str, scale: f64) -> String {
    let mut s = String::from("    -1\n    58\nsine\nNONE\nNONE\nAcc 1\nNONE\n");
    s.push_str(
        "    1         0    0         0 sine               1   3 NONE               0   0\n",
    );
    s.push_str(&format!(
        "         2{N:10}         1 0.00000E+00 1.00000E-03 0.00000E+00\n"
    ));
    s.push_str("        17    0    0    0 Time                 s                   \n");
    s.push_str(&format!(
        "         0    0    0    0 {axis:<20} {unit:<20}\n"
    ));
    s.push_str("         0    0    0    0 NONE                 NONE                \n");
    s.push_str("         0    0    0    0 NONE                 NONE                \n");
    for chunk in (0..N).collect::<Vec<_>>().chunks(6) {
        for &i in chunk {
            s.push_str(&format!("{:13.5E}", sample(i) * scale));
        }
        s.push('\n');
    }
    s.push_str("    -1\n");
    s
}

#[test]
fn uff58_unit_comes_from_the_units_field_not_the_axis_label() {
    // 2 g amplitude written in m/s2 (9.80665 m/s2 per g, ISO 80000-3): reported RMS 2/√2 g to
    // the 6 significant digits of the E13.5 values (1e-5 relative).
    let p = write("acc.uff", &uff58("Acceleration", "m/s2", 9.80665));
    let v = psd_json(&p);
    let ch = &v["channels"][0];
    assert_eq!(ch["unit"], "g");
    let want = 2.0 / 2f64.sqrt();
    let rms = ch["rms"].as_f64().unwrap();
    assert!((rms - want).abs() < want * 1e-5, "{rms}");
    // The same units field as a Windows exporter writes it: `m/s²` with ² as the Windows-1252
    // byte 0xB2 (a catman export in pyuff's test data has such a header).
    let text = uff58("Acceleration", "m/s²", 9.80665);
    let bytes: Vec<u8> = text
        .replace('²', "\u{1}")
        .bytes()
        .map(|b| if b == 1 { 0xB2 } else { b })
        .collect();
    let p = write("acc-cp1252.uff", "");
    std::fs::write(&p, bytes).unwrap();
    let v = psd_json(&p);
    assert_eq!(v["channels"][0]["unit"], "g", "{v}");
    let rms = v["channels"][0]["rms"].as_f64().unwrap();
    assert!((rms - want).abs() < want * 1e-5, "{rms}");
    // A pressure channel labelled `General` is not in g.
    let p = write("pa.uff", &uff58("General", "Pa", 1.0));
    let v = psd_json(&p);
    // Kept as it is, and said to be in the file's unit.
    assert_eq!(v["channels"][0]["unit"], "Pa");
}

#[test]
fn uff58_with_id_line_4_none_is_named_by_its_response_entity() {
    let text = uff58("Acceleration", "g", 1.0).replace("\nAcc 1\n", "\nNONE\n");
    let p = write("none.uff", &text);
    let v = psd_json(&p);
    assert_eq!(v["channels"][0]["name"], "sine");
}

/// Three records named alike (ID line 4 `NONE`, one response entity, nodes 1–3 in +Z), as a
/// roving test exports them: each channel gains its point (`sine:2:+Z`), the shared name alone
/// is an error listing them (never the first record, silently), and the point name selects
/// its record (record k scaled by k: RMS k·2/√2 to the E13.5 values' 1e-5).
#[test]
fn uff58_records_sharing_a_name_are_told_apart_by_their_point() {
    let record = |node: u32, scale: f64| {
        uff58("Acceleration", "g", scale)
            .replace("\nAcc 1\n", "\nNONE\n")
            .replace(
                "sine               1   3",
                &format!("sine               {node}   3"),
            )
    };
    let text: String = (1..=3).map(|k| record(k, k as f64)).collect();
    let p = write("roving.uff", &text);
    let path = p.to_str().unwrap();
    let (code, out, err) =
        crate::common::run_text(&["psd", path, "--nperseg", "500", "--json"], None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let names: Vec<&str> = (0..3)
        .map(|i| v["channels"][i]["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["sine:1:+Z", "sine:2:+Z", "sine:3:+Z"]);
    let (code, _, err) = crate::common::run_text(
        &["psd", path, "--nperseg", "500", "--channels", "sine"],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("no channel named `sine`") && err.contains("sine:3:+Z"),
        "{err}"
    );
    let (code, out, err) = crate::common::run_text(
        &[
            "psd",
            path,
            "--nperseg",
            "500",
            "--channels",
            "sine:2:+Z",
            "--json",
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let want = 2.0 * 2.0 / 2f64.sqrt();
    let rms = v["channels"][0]["rms"].as_f64().unwrap();
    assert!((rms - want).abs() < want * 1e-5, "{rms}");
}

/// Two UFF time histories at 1000 and 2000 Hz: `srs` analyses one rate per run, so the second
/// is refused at its line (it was analysed at the last record's rate); `--channels` picks one.
#[test]
fn srs_refuses_uff_records_of_two_rates() {
    let slow = uff58("Acceleration", "g", 1.0);
    let fast = slow
        .replace("\nAcc 1\n", "\nAcc 2\n")
        .replace("1.00000E-03 0.00000E+00", "5.00000E-04 0.00000E+00");
    let p = write("two-rates.uff", &(slow.clone() + &fast));
    let path = p.to_str().unwrap();
    let (code, _, err) = crate::common::run_text(&["srs", path], None);
    assert_eq!(code, 2, "{err}");
    let second = slow.lines().count() + 2;
    assert!(
        err.contains(&format!("line {second}"))
            && err.contains("2000 Hz")
            && err.contains("1000 Hz"),
        "{err}"
    );
    let (code, out, err) =
        crate::common::run_text(&["srs", path, "--channels", "Acc 2", "--json"], None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["fs_hz"], 2000.0);
}

#[test]
fn a_bad_first_row_is_reported_not_taken_for_a_header_or_units_row() {
    let p = write(
        "bad-row.csv",
        &format!("time,acc_g\n0,x\n{}", rows(",", 1.0, 0.001, false)),
    );
    let err = read_error(&p);
    assert!(err.contains("line 2") && err.contains("`x`"), "{err}");
    let p = write(
        "nan-row.csv",
        &format!("time,acc_g\nNaN,x\n{}", rows(",", 1.0, 0.001, false)),
    );
    let err = read_error(&p);
    assert!(err.contains("line 2"), "{err}");
}

/// An HBM catman-style ASCII export: a preamble, a numbered time channel
/// (`Time  1 - default sample rate`) and a units row in milli-g and in/s² (2 g written as
/// 2000 mg and as 2·9.80665/0.0254 in/s²): both read back as 2 g amplitude, RMS 2/√2 g.
#[test]
fn catman_export_with_a_numbered_time_channel_and_units_row_in_mg_and_in_s2() {
    let mut text = String::from("File: C:\\data\\run1.bin\nCreated: 27.11.2026 10:00:00\n\n");
    text.push_str("Time  1 - default sample rate\tAcc X\tAcc Y\ns\tmg\tin/s^2\n");
    for i in 0..N {
        let (t, a) = (i as f64 / FS, sample(i));
        text.push_str(&format!(
            "{t:.9}\t{:.9}\t{:.9}\n",
            a * 1e3,
            a * 9.80665 / 0.0254
        ));
    }
    let p = write("catman.txt", &text);
    let log = check(&p, &IngestOptions::default(), "Acc X");
    let y = log.channel("Acc Y").unwrap();
    let want = 2.0 / 2f64.sqrt();
    assert!((rms(y) - want).abs() < want * 1e-6, "rms {}", rms(y));
    assert_eq!(log.info.channels[1].unit, Unit::InPerS2);
}

/// A log without a time column whose preamble states the rate (`Sample rate: 1000 Hz`): read
/// at that rate with a note naming the line; `--fs` that disagrees by more than 0.1% is an
/// error naming both rates, as against a time column; `--fs-override` uses `--fs`.
#[test]
fn a_rate_stated_in_the_preamble_is_the_logs_rate() {
    let mut text = String::from("Operator: test\nSample rate: 1000 Hz\nacc_g\n");
    for i in 0..N {
        text.push_str(&format!("{:.9}\n", sample(i)));
    }
    let p = write("preamble-rate.csv", &text);
    let log = check(&p, &IngestOptions::default(), "acc_g");
    assert_note(&log, "sampling rate 1000 Hz read from line 2");
    let opts = IngestOptions {
        fs: Some(2000.0),
        ..IngestOptions::default()
    };
    let e = read_csv(&p, &opts).unwrap_err().to_string();
    assert!(
        e.contains("--fs 2000 Hz disagrees with the 1000 Hz that line 2"),
        "{e}"
    );
    let opts = IngestOptions {
        fs: Some(2000.0),
        fs_override: true,
        ..IngestOptions::default()
    };
    assert_eq!(read_csv(&p, &opts).unwrap().info.fs_hz, 2000.0);
}

/// A unit stated once above the header (`# Units: m/s^2`) is the unit of every channel whose
/// header states none, with a note naming its line; a channel naming its own unit keeps it.
/// Reference: the same written values in both columns, so the m/s² channel reads 1/9.80665
/// of the g channel in g (standard gravity, exact); 1e-12 relative allows for round-off.
#[test]
fn a_unit_stated_in_the_preamble_is_the_unit_of_unlabelled_channels() {
    let mut text = String::from("# Units: m/s^2\ntime,a1,a2 [g]\n");
    for i in 0..N {
        let v = format!("{:.9}", sample(i));
        text.push_str(&format!("{:.9},{v},{v}\n", i as f64 / FS));
    }
    let p = write("preamble-unit.csv", &text);
    let log = read_csv(&p, &IngestOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let units: Vec<Unit> = log.info.channels.iter().map(|c| c.unit).collect();
    assert_eq!(units, [Unit::MPerS2, Unit::G]);
    let (a1, a2) = (
        rms(log.channel("a1").unwrap()),
        rms(log.channel("a2 [g]").unwrap()),
    );
    assert!((a1 * 9.80665 / a2 - 1.0).abs() < 1e-12, "{a1} {a2}");
    assert_note(&log, "unit m/s2 read from line 1");
}

/// Excel's "Unicode text" (UTF-16LE with a byte-order mark, tab, CRLF), the same in UTF-16BE
/// and without the mark, a Windows-1252 export whose unit `m/s²` is the byte 0xB2 (semicolon,
/// decimal comma), and a file whose lines end with CR alone: each reads as the UTF-8 original
/// (the analytic rate and RMS of `check`), with the channel's unit taken from the decoded header and
/// a note naming the encoding.
#[test]
fn utf16_windows_1252_and_cr_only_logs_read_as_their_utf8_original() {
    let tab = format!(
        "Time [s]\tAccel [m/s²]\r\n{}",
        rows("\t", 1.0, 0.0, false).replace('\n', "\r\n")
    );
    let semi = format!("Time [s];Accel [m/s²]\n{}", rows(";", 1.0, 0.0, true));
    let utf16 = |be: bool, bom: bool| -> Vec<u8> {
        let mark: &[u16] = if bom { &[0xFEFF] } else { &[] };
        mark.iter()
            .copied()
            .chain(tab.encode_utf16())
            .flat_map(|u| if be { u.to_be_bytes() } else { u.to_le_bytes() })
            .collect()
    };
    let cp1252: Vec<u8> = semi
        .chars()
        .map(|c| if c == '²' { 0xB2 } else { c as u8 })
        .collect();
    let cases: [(&str, Vec<u8>, &str); 5] = [
        (
            "utf16le.txt",
            utf16(false, true),
            "UTF-16LE (byte-order mark)",
        ),
        (
            "utf16be.txt",
            utf16(true, true),
            "UTF-16BE (byte-order mark)",
        ),
        (
            "utf16le-nobom.txt",
            utf16(false, false),
            "UTF-16LE (no byte-order mark",
        ),
        ("ansi.csv", cp1252, "Windows-1252"),
        (
            "cr.txt",
            tab.replace("\r\n", "\r").into_bytes(),
            "carriage return alone",
        ),
    ];
    for (name, bytes, note) in cases {
        let dir = crate::common::temp_dir(&format!("dialect-{name}"));
        let p = dir.join(name);
        std::fs::write(&p, &bytes).unwrap();
        // The channel is reported in g: m/s² over standard gravity (9.80665, ISO 80000-3).
        let log = read_csv(&p, &IngestOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(log.info.channels[0].unit, Unit::MPerS2, "{name}");
        assert!(
            (log.info.fs_hz - FS).abs() < FS * 1e-9,
            "{name}: fs {}",
            log.info.fs_hz
        );
        let x = log.channel("Accel [m/s²]").unwrap();
        assert_eq!(x.len(), N, "{name}");
        let want = 2.0 / 2f64.sqrt();
        assert!(
            (rms(x) * 9.80665 - want).abs() < want * 1e-6,
            "{name}: rms {}",
            rms(x)
        );
        assert!(
            log.info.ingest.notes.iter().any(|n| n.contains(note)),
            "{name}: {:?}",
            log.info.ingest.notes
        );
    }
}

/// Time columns as locales and loggers write them: a German export (`28.11.2026
/// 10:15:30,125`, semicolon, decimal comma), Excel's US form (`11/28/2026 10:15:30.125 AM`),
/// a time of day alone and an elapsed clock (`0:00:00.125`), each one millisecond apart. The
/// rate comes from the column (analytic 1000 Hz within 1e-9) and the sine is read whole.
#[test]
fn locale_date_times_and_clock_times_are_time_columns() {
    // 10:15:30 + i ms, as hh:mm:ss.fff with the given decimal mark.
    let clock = |i: usize, mark: &str| {
        let ms = 36_930_000 + i;
        let (h, m, s) = (ms / 3_600_000, ms / 60_000 % 60, ms / 1000 % 60);
        format!("{h:02}:{m:02}:{s:02}{mark}{:03}", ms % 1000)
    };
    let elapsed = |i: usize| format!("0:00:{:02}.{:03}", i / 1000, i % 1000);
    type Form = fn(usize, &dyn Fn(usize, &str) -> String, &dyn Fn(usize) -> String) -> String;
    let cases: [(&str, &str, &str, bool, Form); 4] = [
        ("german.csv", "Datum/Uhrzeit;A [g]", ";", true, |i, c, _| {
            format!("28.11.2026 {}", c(i, ","))
        }),
        ("excel-us.csv", "Date/Time,A [g]", ",", false, |i, c, _| {
            format!("11/28/2026 {} AM", c(i, "."))
        }),
        ("time-of-day.csv", "Time,A [g]", ",", false, |i, c, _| {
            c(i, ".")
        }),
        ("elapsed.csv", "Time,A [g]", ",", false, |i, _, e| e(i)),
    ];
    for (name, header, sep, comma, form) in cases {
        let mut text = format!("{header}\n");
        for i in 0..N {
            let v = format!("{:.9}", sample(i));
            let v = if comma { v.replace('.', ",") } else { v };
            text.push_str(&format!("{}{sep}{v}\n", form(i, &clock, &elapsed)));
        }
        let p = write(name, &text);
        let log = check(&p, &IngestOptions::default(), "A [g]");
        assert!(
            log.info
                .ingest
                .notes
                .iter()
                .any(|n| n.contains("read as date-times or clock times")),
            "{name}: {:?}",
            log.info.ingest.notes
        );
    }
}

/// A logger's time of day that runs past midnight (`23:59:59.500` … `00:00:00.499`, one row per
/// millisecond): the rows after midnight are counted on into the next day, with a note, so the
/// rate is 1000 Hz (analytic, 1e-9) and the sine is read whole. A step back of less than half
/// a day is still refused as a non-increasing time, at its line. The log ends with a trailer line.
#[test]
fn a_time_of_day_running_past_midnight_counts_on() {
    let stamp = |ms: usize| {
        let ms = ms % 86_400_000;
        let (h, m, s) = (ms / 3_600_000, ms / 60_000 % 60, ms / 1000 % 60);
        format!("{h:02}:{m:02}:{s:02}.{:03}", ms % 1000)
    };
    let start = 86_400_000 - 500;
    let mut text = String::from("Time,A [g]\n");
    for i in 0..N {
        text.push_str(&format!("{},{:.9}\n", stamp(start + i), sample(i)));
    }
    text.push_str("End of data\n");
    let p = write("midnight.csv", &text);
    let log = check(&p, &IngestOptions::default(), "A [g]");
    assert_note(&log, "line 502: the time of day passes midnight");
    // The trailer at the end of so short a file is inside the head the dialect is told from,
    // and must not hide the clock column from it.
    assert_note(&log, "line 1002: the data ends; 1 trailing line(s)");
    // Two rows swapped one second apart are not a midnight.
    let mut back = String::from("Time,A [g]\n");
    for i in 0..N {
        let ms = 36_000_000 + i + if i == 10 { 1000 } else { 0 };
        back.push_str(&format!("{},{:.9}\n", stamp(ms), sample(i)));
    }
    let p = write("clock-back.csv", &back);
    let e = read_error(&p);
    assert!(
        e.contains("line 13: time") && e.contains("does not increase"),
        "{e}"
    );
}

/// A logger that ends its export with text (`End of data`, a blank line, `Stopped by
/// operator;;`, CRLF, semicolons and decimal commas): the data ends before it, with a note
/// naming the line, and the sine is read whole (analytic rate and RMS in `check`). The same
/// text line with data after it is an unreadable row, refused at its line.
#[test]
fn a_text_trailer_after_the_data_ends_the_log() {
    let body = rows(";", 1.0, 0.0, true).replace('\n', "\r\n");
    let text = format!("time;A [g]\r\n{body}End of data\r\n\r\nStopped by operator;;\r\n");
    let p = write("trailer.csv", &text);
    let log = check(&p, &IngestOptions::default(), "A [g]");
    let line = N + 2;
    assert_note(
        &log,
        &format!("line {line}: the data ends; 2 trailing line(s)"),
    );
    let inside = format!(
        "time;A [g]\n{body}End of data\n{}",
        rows(";", 1.0, 2.0, true)
    );
    let p = write("text-inside.csv", &inside);
    let e = read_error(&p);
    assert!(
        e.contains(&format!("line {line}: expected 2 fields")),
        "{e}"
    );
}

/// A Tektronix oscilloscope's spreadsheet CSV (TDS/TBS layout: 18 setting rows `key,value,unit`
/// in columns 1–3 beside the samples in columns 4–5, a trailing comma, CRLF, trigger at t = 0
/// so the times start negative): the channel is named by `Source`, its unit taken from
/// `Vertical Units`, the rate from the time column: 1000 Hz (analytic, 1e-9) and RMS 2/√2.
#[test]
fn a_tektronix_spreadsheet_csv_is_read_by_its_layout() {
    let settings = [
        "Record Length,1.000000e+03,Points",
        "Sample Interval,1.000000e-03,s",
        "Trigger Point,5.000000e+02,Samples",
        ",,",
        ",,",
        ",,",
        "Source,CH1,",
        "Vertical Units,g,",
        "Vertical Scale,1.000000e+00,",
        "Vertical Offset,0.000000e+00,",
        "Horizontal Units,s,",
        "Horizontal Scale,1.000000e-01,",
        "Pt Fmt,Y,",
        "Yzero,0.000000e+00,",
        "Probe Atten,1.000000e+00,",
        "Model Number,TBS1052B,",
        "Serial Number,C000000,",
        "Firmware Version,FV:v4.00,",
    ];
    let mut text = String::new();
    for i in 0..N {
        let left = settings.get(i).copied().unwrap_or(",,");
        let t = (i as f64 - 500.0) / FS;
        text.push_str(&format!("{left},{t:.12},{:.9},\r\n", sample(i)));
    }
    let p = write("tek0000.csv", &text);
    let log = satqual::signal::formats::read_log(&p, &IngestOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        (log.info.fs_hz - FS).abs() < FS * 1e-9,
        "{}",
        log.info.fs_hz
    );
    assert_eq!(log.info.channels[0].name, "CH1");
    assert_eq!(log.info.channels[0].unit, satqual::signal::ingest::Unit::G);
    let want = 2.0 / 2f64.sqrt();
    let x = &log.data[0];
    assert_eq!(x.len(), N);
    assert!((rms(x) - want).abs() < want * 1e-6, "rms {}", rms(x));
}

/// A newer Tektronix scope's CSV (MSO 4/5/6 layout): `key,value` settings, empty `,` lines and
/// a `Label,` line above the `TIME,CH1` header. `TIME,CH1` is not taken for a units row under
/// `Label,`, `Vertical Units,g` states the unit, and the rate and RMS are the analytic ones
/// (`check`).
#[test]
fn a_scope_csv_with_a_settings_preamble_and_a_label_line() {
    let mut text = String::from(
        "Model,MSO54\nFirmware Version,1.24.4.1178\nWaveform Type,ANALOG\nPoint Format,Y\n\
         Horizontal Units,s\nSample Interval,0.001\nRecord Length,1000\n\
         Gating,0.0% to 100.0%\nVertical Units,g\nVertical Scale,0.1\n,\n,\n,\nLabel,\nTIME,CH1\n",
    );
    text.push_str(&rows(",", 1.0, -0.5, false));
    let p = write("mso.csv", &text);
    let log = check(&p, &IngestOptions::default(), "CH1");
    assert_eq!(log.info.channels[0].unit, Unit::G);
}

/// A catman export of two channel groups (1000 Hz and 100 Hz, tab-separated, a units row),
/// 5 s long, past the 64 KB head the dialect is told from: the slow group's cells end after
/// its 500 samples. Read whole, the first empty cell is an error at its line that says how to
/// leave the group out; with `--channels` naming the fast channel, the log reads at 1000 Hz
/// (analytic, 1e-9) with RMS 2/√2 (50 Hz sine over whole periods, 1e-6).
#[test]
fn a_slower_channel_group_is_left_out_by_naming_the_others() {
    let rows = 5 * N;
    let mut text = String::from(
        "File name:\tC:\\test.bin\n\nTime  1 - default sample rate\tA\tTime  2 - slow sample rate\tTemp\ns\tg\ts\t°C\n",
    );
    for i in 0..rows {
        let slow = if i < rows / 10 {
            format!("{:.3}\t{:.3}", i as f64 / 100.0, 20.0 + i as f64 * 1e-3)
        } else {
            "\t".to_string()
        };
        text.push_str(&format!("{:.9}\t{:.9}\t{slow}\n", i as f64 / FS, sample(i)));
    }
    let p = write("catman-groups.txt", &text);
    let e = read_error(&p);
    let line = 4 + rows / 10 + 1;
    assert!(
        e.contains(&format!(
            "line {line}, column `Time  2 - slow sample rate`: empty cell"
        )) && e.contains("--channels"),
        "{e}"
    );
    let fast = IngestOptions {
        channels: Some(vec!["A".into()]),
        ..Default::default()
    };
    let log = read_csv(&p, &fast).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        (log.info.fs_hz - FS).abs() < FS * 1e-9,
        "{}",
        log.info.fs_hz
    );
    let x = log.channel("A").unwrap();
    assert_eq!(x.len(), rows);
    let want = 2.0 / 2f64.sqrt();
    assert!((rms(x) - want).abs() < want * 1e-6, "rms {}", rms(x));
}

/// A PicoQuake-style IMU export (its documented layout: `# Config: data_rate = 2000.0 Hz,
/// filter = 488 Hz, ...`, a `count` column, accelerations and gyro rates at rest), 10 000
/// samples of a 100 Hz sine of amplitude 1: the rate comes from the clause that names it (not
/// the filter's 488 Hz), `count` is not a channel, the default segment is shortened so that
/// at least 7 segments are averaged, and the constant gyro channel reports no peaks but a
/// warning. RMS of the sine: 1/√2 (analytic, 1e-4 for the 4-decimal values).
#[test]
fn an_imu_export_with_its_rate_among_other_settings_and_a_sample_counter() {
    let mut text = String::from(
        "# PLab PicoQuake Data\n# Num. samples: 10000, Duration: 5.0 s\n\
         # Config: data_rate = 2000.0 Hz, filter = 488 Hz, acc_range = 4 g, gyro_range = 250.0 dps\n\
         count,a_x,g_x\n",
    );
    for i in 0..10_000 {
        let a = (2.0 * std::f64::consts::PI * 100.0 * i as f64 / 2000.0).sin();
        text.push_str(&format!("{},{a:.4},19.70\n", i + 1));
    }
    let p = write("picoquake.csv", &text);
    let (code, out, err) = crate::common::run_text(&["psd", p.to_str().unwrap(), "--json"], None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["fs_hz"].as_f64(), Some(2000.0));
    let names = crate::common::channel_names(&v);
    assert_eq!(names, ["a_x", "g_x"]);
    assert!(err.contains("column `count` numbers the samples"), "{err}");
    assert!(v["segments"].as_u64().unwrap() >= 7, "{}", v["segments"]);
    let rms = v["channels"][0]["rms"].as_f64().unwrap();
    assert!((rms - 0.5f64.sqrt()).abs() < 1e-4, "{rms}");
    assert_eq!(v["channels"][1]["peaks"].as_array().map(Vec::len), Some(0));
    assert!(err.contains("channel `g_x` is constant"), "{err}");
}

/// A spreadsheet's date-time column: serial days since 1899-12-30 (46000 = 2025-12-09),
/// written with 12 decimals, one row per millisecond. Read as seconds it would be an
/// 86.4 MHz log; it is read as days, with a note. Each stamp is rounded to 0.5e-12 day
/// (43 ns), so the rate over the 1 s span is 1000 Hz within 1e-7 relative; the sine is whole.
#[test]
fn spreadsheet_serial_days_in_a_time_column_are_days() {
    let mut text = String::from("Time,A [g]\n");
    for i in 0..N {
        let day = 46_000.0 + i as f64 / FS / 86_400.0;
        text.push_str(&format!("{day:.12},{:.9}\n", sample(i)));
    }
    let p = write("serial-days.csv", &text);
    let log = read_csv(&p, &IngestOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        (log.info.fs_hz - FS).abs() < FS * 1e-7,
        "fs {}",
        log.info.fs_hz
    );
    let x = log.channel("A [g]").unwrap();
    assert_eq!(x.len(), N);
    let want = 2.0 / 2f64.sqrt();
    assert!((rms(x) - want).abs() < want * 1e-6, "rms {}", rms(x));
    assert_note(&log, "spreadsheet serial days");
    // Stated as seconds, the column is taken at its word, and the rate is refused only by
    // the plausible range (86.4 MHz is inside it): the note is the guard, not an error.
    let secs = IngestOptions {
        time_unit: Some(TimeUnit::S),
        ..Default::default()
    };
    let log = read_csv(&p, &secs).unwrap();
    assert!(log.info.fs_hz > 8e7, "{}", log.info.fs_hz);
}

/// An FRF's unit is stated: a German hammer export (Windows-1252, semicolon, decimal comma)
/// whose response `Beschleunigung [m/s²]` is exactly 9.80665 × `Kraft [N]` of a seeded random
/// force. The response is read in g, so it equals the force to the 7 written digits (H = 1
/// g/N), and the JSON says `g/N`.
#[test]
fn an_frf_states_its_unit_from_the_channels_as_read() {
    let mut state = 7u64;
    let mut text = String::from("Zeit [s];Kraft [N];Beschleunigung [m/s²]\r\n");
    for i in 0..8192 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let f = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let row = format!("{:.6};{f:.6e};{:.6e}\r\n", i as f64 / 1000.0, f * 9.80665);
        text.push_str(&row.replace('.', ","));
    }
    let bytes: Vec<u8> = text
        .chars()
        .map(|c| if c == '²' { 0xB2 } else { c as u8 })
        .collect();
    let dir = crate::common::temp_dir("dialect-hammer");
    let p = dir.join("hammer.csv");
    std::fs::write(&p, bytes).unwrap();
    let args = [
        "frf",
        p.to_str().unwrap(),
        "--input",
        "Kraft [N]",
        "--output",
        "Beschleunigung [m/s²]",
    ];
    let (code, out, err) =
        crate::common::run_text(&[&args[..], &["--json", "--nperseg", "512"]].concat(), None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["h_unit"], "g/N");
    let (code, out, err) =
        crate::common::run_text(&[&args[..], &["--nperseg", "512"]].concat(), None);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("H1 = Beschleunigung [m/s²]/Kraft [N]"),
        "{out}"
    );
    let lib = satqual::signal::frf::read_frf_logs(
        std::slice::from_ref(&p),
        "Kraft [N]",
        "Beschleunigung [m/s²]",
        &IngestOptions::default(),
    )
    .unwrap();
    let (force, accel) = (
        lib[0].channel("Kraft [N]").unwrap(),
        lib[0].channel("Beschleunigung [m/s²]").unwrap(),
    );
    for (f, a) in force.iter().zip(accel) {
        assert!((a - f).abs() <= 1e-6 * f.abs().max(1e-3), "{a} g for {f} N");
    }
}

/// A channel that is not an acceleration keeps its values and is reported in the unit the file
/// states for it, from a units row (`N`) or the name's brackets (`p [kPa]`); a channel with no
/// stated unit stays `as-is`. The band RMS of a 2-amplitude sine is 2/√2 whatever the unit
/// (analytic, 1e-3: Welch's band integral over 50 Hz with a Hann window).
#[test]
fn a_channel_kept_as_it_is_is_reported_in_the_files_unit() {
    let mut text = String::from("time,force,p [kPa],raw\ns,N,,\n");
    for i in 0..N {
        let (t, v) = (i as f64 / FS, sample(i));
        text.push_str(&format!("{t:.9},{v:.9},{v:.9},{v:.9}\n"));
    }
    let p = write("kept-units.csv", &text);
    let log = check(&p, &IngestOptions::default(), "force");
    let labels: Vec<String> = log
        .info
        .channels
        .iter()
        .map(|c| c.reported_unit())
        .collect();
    assert_eq!(labels, ["N", "kPa", "as-is"]);
    let (v, err) = psd_with(&p, &[]);
    let want = 2.0 / 2f64.sqrt();
    for (ch, unit) in v["channels"]
        .as_array()
        .unwrap()
        .iter()
        .zip(["N", "kPa", "as-is"])
    {
        assert_eq!(ch["unit"], unit, "{ch}");
        let band = ch["grms"].as_f64().unwrap();
        assert!((band - want).abs() < want * 1e-3, "{band}");
    }
    assert!(err.contains("band RMS") && !err.contains("Grms"), "{err}");
}

/// A UFF58 file cut short inside its data block (as a partial download or a head excerpt of
/// pyuff's `Sample_UFF58_ascii.uff` is): the error says the file ends inside the dataset and
/// how many of the announced values it holds (13 header lines, then 8 data lines of 6 values:
/// 48 of 1000).
#[test]
fn a_uff58_file_cut_inside_its_data_says_how_much_it_holds() {
    let full = uff58("Acceleration", "g", 1.0);
    let cut: String = full
        .lines()
        .take(13 + 8)
        .map(|l| format!("{l}\n"))
        .collect();
    let p = write("cut.uff", &cut);
    let e = crate::common::psd_error(&p);
    assert!(
        e.contains("line 21: dataset 58 is not closed by `-1`")
            && e.contains(&format!(
                "after 48 of the {N} values record 7 (line 9) announces"
            )),
        "{e}"
    );
}

/// Runs `psd --json` on `p` and returns the JSON; panics with stderr on failure.
fn psd_json(p: &std::path::Path) -> serde_json::Value {
    psd_with(p, &[]).0
}

/// The abscissa's units label (record 8) gives its unit: the same 1000 Hz time history with
/// its increment written in ms (`1.00000E+00` ms) reads at 1000 Hz, not 1 Hz. A label that
/// is no time or frequency unit leaves its record unread, naming record 8's line (line 10),
/// never taken as s; the file's other records would still be read.
#[test]
fn uff58_abscissa_in_ms_is_converted_and_an_unknown_unit_refused() {
    let seconds = uff58("Acceleration", "g", 1.0);
    let in_ms = seconds
        .replace(
            "        17    0    0    0 Time                 s                   \n",
            "        17    0    0    0 Time                 ms                  \n",
        )
        .replace("1.00000E-03", "1.00000E+00");
    assert_ne!(in_ms, seconds);
    let v = psd_json(&write("x-ms.uff", &in_ms));
    // By construction: 1 ms steps, 1000 Hz, exactly representable in the E13.5 field.
    assert_eq!(v["fs_hz"].as_f64(), Some(FS));
    let rms = v["channels"][0]["rms"].as_f64().unwrap();
    let want = 2.0 / 2f64.sqrt();
    assert!((rms - want).abs() < want * 1e-5, "{rms}");
    let odd = in_ms.replace(" ms                  \n", " furlong             \n");
    let e = crate::common::psd_error(&write("x-furlong.uff", &odd));
    assert!(
        e.contains(
            "x-furlong.uff: line 2: record 8 (the abscissa, line 10) gives the units label `furlong`"
        ),
        "{e}"
    );
}

/// A time history of complex values (ordinate data type 5) is refused at record 7's line,
/// never read as its real part.
#[test]
fn uff58_complex_time_history_is_refused() {
    let text = uff58("Acceleration", "g", 1.0).replace(
        &format!("         2{N:10}         1 "),
        &format!("         5{N:10}         1 "),
    );
    let e = crate::common::psd_error(&write("complex-time.uff", &text));
    assert!(
        e.contains("complex-time.uff: line 9: the record at line 2 is a time history (record 6 function type 1) with complex values (record 7 ordinate data type 5)"),
        "{e}"
    );
    assert!(e.contains("export it as real values"), "{e}");
}

/// A record of function type 2 (auto spectrum, UFF58 record 6 field 1) is not a time history:
/// the commands that read time histories and `psd` refuse it naming the file and the line of
/// its `58` marker. The layout of `uff58` puts the first marker on line 2 and, after 11 header
/// lines, 167 data lines (1000 values, 6 a line) and `-1`, the second on line 2 + 181 = 183.
#[test]
fn uff58_auto_spectrum_is_refused_at_its_line() {
    let time = uff58("Acceleration", "g", 1.0);
    let spectrum = time
        .replacen("    1         0    0", "    2         0    0", 1)
        .replace(
            "        17    0    0    0 Time                 s                   \n",
            "        18    0    0    0 Frequency            Hz                  \n",
        )
        .replace("sine               1   3", "spec               2   3");
    assert_ne!(spectrum, time);
    let alone = write("auto-spectrum.uff", &spectrum);
    let e = satqual::signal::formats::read_log(&alone, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "auto-spectrum.uff: line 2: no real, evenly spaced time history (UFF58 function type \
             1) to read: `Acc 1` (line 2: function type 2 (auto spectrum), not a time history)"
        ),
        "{e}"
    );
    let e = crate::common::psd_error(&alone);
    assert!(
        e.contains("auto-spectrum.uff: line 2: record `Acc 1` is function type 2 (auto spectrum)"),
        "{e}"
    );
    // Beside a time history, the spectrum named by ID line 4 `Acc 2` is the error, at line 183.
    let both = format!("{time}{}", spectrum.replace("Acc 1", "Acc 2"));
    let e = crate::common::psd_error(&write("time-and-auto.uff", &both));
    assert!(
        e.contains(
            "time-and-auto.uff: line 183: record `Acc 2` is function type 2 (auto spectrum)"
        ),
        "{e}"
    );
}

/// An uneven abscissa (record 7 spacing 0) written as pyuff writes it, `%13.5e` (six digits):
/// a 2048 Hz time history's x values are rounded to 1e-9 s and less, so its steps differ by
/// rounding only and it is evenly spaced. A real gap is refused naming the point and the
/// size of the deviation.
#[test]
fn uff58_uneven_abscissa_rounded_to_six_digits_is_uniform() {
    let n = 2048;
    let fs = 2048.0;
    let record = |shift_at: Option<usize>| {
        let mut s = String::from("    -1\n    58\nacc1\nNONE\nNONE\nacc1\nNONE\n");
        s.push_str(
            "    1         0    0         0       acc1         1   3       NONE         0   0\n",
        );
        s.push_str(&format!(
            "         4{n:10}         0  0.00000e+00  0.00000e+00  0.00000e+00\n"
        ));
        s.push_str("        17    0    0    0 NONE                 s                   \n");
        s.push_str("        12    0    0    0 NONE                 g                   \n");
        s.push_str("         0    0    0    0 NONE                 NONE                \n");
        s.push_str("         0    0    0    0 NONE                 NONE                \n");
        for i in 0..n {
            let t = i as f64 / fs + if shift_at == Some(i) { 1e-4 } else { 0.0 };
            // By construction: 64 Hz sine of amplitude 2, 64 whole periods in 2048 samples.
            let y = 2.0 * (2.0 * std::f64::consts::PI * 64.0 * i as f64 / fs).sin();
            s.push_str(&format!("{t:13.5e}{y:20.11e}"));
            if i % 2 == 1 {
                s.push('\n');
            }
        }
        s.push_str("    -1\n");
        // Rust writes `4.88281e-4`; pyuff (C printf) `4.88281e-04`: both are 6 digits.
        s
    };
    let v = psd_json(&write("uneven-6digits.uff", &record(None)));
    let fs_read = v["fs_hz"].as_f64().unwrap();
    // The mean step comes from the last x, 9.99512e-01 for 2047/2048 s: 2048 Hz to its 6
    // digits (5e-7 relative).
    assert!((fs_read - fs).abs() < fs * 5e-7, "{fs_read}");
    let rms = v["channels"][0]["rms"].as_f64().unwrap();
    let want = 2.0 / 2f64.sqrt();
    assert!((rms - want).abs() < want * 1e-9, "{rms}");
    // Point 1001 (index 1000) moved 0.1 ms late: a fifth of a step, not rounding.
    let e = crate::common::psd_error(&write("uneven-gap.uff", &record(Some(1000))));
    assert!(
        e.contains("uneven-gap.uff: line 2: the abscissa is not evenly spaced: the step from point 1000 (x = "),
        "{e}"
    );
    assert!(e.contains("off the mean step"), "{e}");
}

/// `psd --json` of `p` with `args`, and stderr.
fn psd_with(p: &std::path::Path, args: &[&str]) -> (serde_json::Value, String) {
    let mut all = vec!["psd", p.to_str().unwrap(), "--nperseg", "500", "--json"];
    all.extend(args);
    json_run(&all)
}

/// Runs satqual with `args`, which must succeed, and returns its JSON and its stderr.
fn json_run(args: &[&str]) -> (serde_json::Value, String) {
    let (code, out, err) = crate::common::run_text(args, None);
    assert_eq!(code, 0, "{err}");
    (serde_json::from_str(&out).unwrap(), err)
}

/// An oscilloscope's vertical unit is the channel's: an MSO export's preamble `Vertical
/// Units,V` (above `TIME,CH1`, read as delimited text) labels the channel V, a Tektronix
/// spreadsheet's `Vertical Units,mV` and a Rigol's `Volt` keep theirs, and `--units g` for all
/// channels does not turn volts into g (a note says so); `--units CH1=g` does, as asked, with
/// a note on the sensitivity that means (1 V/g). The values are this file's sine, 2 V
/// amplitude: RMS 2/√2 V, or 1000 times that in mV written to 6 decimals (both to 1e-6
/// relative).
#[test]
fn a_scopes_vertical_unit_is_kept_and_volts_are_not_taken_as_g() {
    let mv_rows = |sep: &str| -> String {
        (0..N)
            .map(|i| format!("{:.9}{sep}{:.6}\n", i as f64 / FS, 1000.0 * sample(i)))
            .collect()
    };
    let mso = format!(
        "Model,MSO58\nFirmware Version,1.20.4\n\nWaveform Type,ANALOG\nPoint Format,Y\n\
         Horizontal Units,s\nSample Interval,0.001\nRecord Length,{N}\nVertical Units,V\n\
         Vertical Offset,0\nVertical Scale,0.5\nLabel,\nTIME,CH1\n{}",
        rows(",", 1.0, 0.0, false)
    );
    let settings = [
        "Record Length,1000,Points",
        "Sample Interval,0.001,s",
        "Source,CH1,",
        "Vertical Units,mV,",
    ];
    let tek: String = mv_rows(",")
        .lines()
        .enumerate()
        .map(|(i, row)| format!("{},{row},\r\n", settings.get(i).unwrap_or(&",,")))
        .collect();
    let rigol = format!(
        "X,CH1,Start,Increment,\nSequence,Volt,0,1.000000e-03\n{}",
        (0..N)
            .map(|i| format!("{i},{:.9},\n", sample(i)))
            .collect::<String>()
    );
    let one = 2.0 / 2f64.sqrt();
    for (name, text, unit, rms) in [
        ("mso-volts.csv", mso, "V", one),
        ("tek-millivolts.csv", tek, "mV", 1000.0 * one),
        ("rigol-volts.csv", rigol, "Volt", one),
    ] {
        let p = write(name, &text);
        for args in [&[][..], &["--units", "g"]] {
            let (v, err) = psd_with(&p, args);
            let ch = &v["channels"][0];
            assert_eq!(ch["unit"], unit, "{name} {args:?}: {err}");
            let got = ch["rms"].as_f64().unwrap();
            assert!((got - rms).abs() < 1e-6 * rms, "{name}: {got}");
            if !args.is_empty() {
                let note = format!(
                    "channel `CH1` is in {unit} as the file states, an electrical unit: kept in {unit}, not taken as g by --units g"
                );
                assert!(err.contains(&note), "{name}: {err}");
            }
        }
        // Named as g, the volts are read unchanged, and the note says at what sensitivity.
        let (v, err) = psd_with(&p, &["--units", "CH1=g"]);
        assert_eq!(v["channels"][0]["unit"], "g", "{name}");
        let note = format!(
            "channel `CH1` is in {unit} as the file states; --units \"CH1=g\" reads its values as g unchanged, i.e. at a sensitivity of 1 {unit}/g"
        );
        assert!(err.contains(&note), "{name}: {err}");
    }
}

/// A UFF58 time history whose units field (record 9) is `V` keeps its volts under `--units g`
/// as the scope readers do, in `psd` (with the note) and in the commands reading through
/// `read_log`; `--units "Acc 1=g"` takes it as g, with a note on the sensitivity that means. RMS 2/√2 V to the 6 digits of E13.5 (1e-5).
#[test]
fn uff58_volts_are_not_taken_as_g() {
    let p = write("volts.uff", &uff58("Voltage", "V", 1.0));
    let (v, err) = psd_with(&p, &["--units", "g"]);
    assert_eq!(v["channels"][0]["unit"], "V", "{err}");
    let rms = v["channels"][0]["rms"].as_f64().unwrap();
    let want = 2.0 / 2f64.sqrt();
    assert!((rms - want).abs() < want * 1e-5, "{rms}");
    assert!(
        err.contains("channel `Acc 1` is in V as the file states"),
        "{err}"
    );
    let opts = IngestOptions {
        default_unit: Some(Unit::G),
        ..IngestOptions::default()
    };
    let log = satqual::signal::formats::read_log(&p, &opts).unwrap();
    assert_eq!(log.info.channels[0].unit, Unit::AsIs);
    assert_eq!(log.info.channels[0].unit_label, "V");
    let (v, err) = psd_with(&p, &["--units", "Acc 1=g"]);
    assert_eq!(v["channels"][0]["unit"], "g");
    assert!(
        err.contains("reads its values as g unchanged, i.e. at a sensitivity of 1 V/g"),
        "{err}"
    );
    // `srs` keeps the volts too and says so on stderr, as `psd` does.
    let (v, err) = json_run(&["srs", p.to_str().unwrap(), "--units", "g", "--json"]);
    assert_eq!(v["channels"][0]["unit"], "V", "{err}");
    assert!(
        err.contains("channel `Acc 1` is in V as the file states"),
        "{err}"
    );
}

/// Siglent oscilloscope CSV: `Second` names the time column (bin2csv writes `Second,Volt`
/// under its preamble), and the SDS2000X+'s last preamble line `Software Version,1.3.7R5,`
/// is not the header over a units row `Second,Value`. Rows: the 1000 Hz sine of this file,
/// times from -0.5 s.
#[test]
fn siglent_csv_second_is_time_and_preamble_is_not_a_header() {
    let bin2csv = format!(
        "Record Length,Analog:{N}\nSample Rate,1000.0\nVertical Scale,CH1: 0.50\n\
         Vertical Offset,CH1:0.00000\nHorizontal Scale, 0.050000000\nSecond,Volt\n{}",
        rows(",", 1.0, -0.5, false)
    );
    let sds = format!(
        "Record Length,Analog:{N},\nSample Interval,Analog:1.000000E-03,\nVertical Units,CH3:V,,\n\
         Vertical Scale,CH3:5.00E-01,,\nVertical Offset,CH3:0.00E+00,,\nHorizontal Units,S,\n\
         Horizontal Scale,5.00E-02,\nModel Number,SDS2104X Plus,\nSerial Number,SDS2PDD1234567,\n\
         Software Version,1.3.7R5,\nSecond,Value\n{}",
        rows(",", 1.0, -0.5, false)
    );
    for (name, text, channel) in [
        ("siglent-bin2csv.csv", bin2csv, "Volt"),
        ("siglent-sds2000xp.csv", sds, "Value"),
    ] {
        let v = psd_json(&write(name, &text));
        let channels = v["channels"].as_array().unwrap();
        assert_eq!(channels.len(), 1, "{name}: {v}");
        assert_eq!(channels[0]["name"], channel, "{name}");
        assert_eq!(
            v["ingest"]["time_column"], "Second",
            "{name}: {}",
            v["ingest"]
        );
        let fs = v["fs_hz"].as_f64().unwrap();
        assert!((fs - FS).abs() < FS * 1e-9, "{name}: {fs}");
        let rms = channels[0]["rms"].as_f64().unwrap();
        let want = 2.0 / 2f64.sqrt();
        assert!((rms - want).abs() < want * 1e-6, "{name}: {rms}");
    }
}
