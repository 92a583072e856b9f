//! Log ingest: bad input gets one clear error naming file, line and column (library and CLI,
//! exit code 2, never a panic); resampling is reported; the streamed CSV path gives the same
//! spectra as the in-memory one; results do not depend on the number of threads.

use satqual::signal::ingest::{IngestOptions, read_csv};
use satqual::signal::{WelchOptions, psd_of_file, welch};
use std::path::{Path, PathBuf};

/// A folder per process and test thread: a thread runs one test at a time, so `cleanup` at the
/// end of a test removes only that test's files.
fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "satqual-sig-ingest-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn cleanup() {
    std::fs::remove_dir_all(dir()).ok();
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir().join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

use crate::common::run_text as cli;

/// A uniform CSV log: time + channels of deterministic pseudo-random data.
fn uniform_csv(n: usize, channels: &[&str]) -> String {
    let mut s = format!("time_s,{}\n", channels.join(","));
    let mut state = 12345u64;
    for i in 0..n {
        s.push_str(&format!("{:.9}", i as f64 / 1000.0));
        for c in 0..channels.len() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let v = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
                + (i as f64 * 0.05 * (c + 1) as f64).sin();
            s.push_str(&format!(",{v:.12e}"));
        }
        s.push('\n');
    }
    s
}

/// Expects an error from both the library and the CLI; returns the message.
fn expect_error(p: &Path, opts: &IngestOptions, extra: &[&str], needles: &[&str]) -> String {
    let e = read_csv(p, opts).unwrap_err().to_string();
    for n in needles {
        assert!(e.contains(n), "library message `{e}` lacks `{n}`");
    }
    assert!(
        e.contains(&p.display().to_string()),
        "message `{e}` does not name the file"
    );
    let mut args = vec!["psd", p.to_str().unwrap(), "--nperseg", "16"];
    args.extend(extra);
    let (code, _, err) = cli(&args, None);
    assert_eq!(code, 2, "CLI exit for {}: {err}", p.display());
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "CLI message `{err}` lacks `{n}`");
    }
    e
}

#[test]
fn bad_files_get_clear_errors() {
    let o = IngestOptions::default();
    expect_error(&write("empty.csv", b""), &o, &[], &["empty"]);
    expect_error(&write("blank.csv", b"\n \n"), &o, &[], &["empty"]);
    expect_error(
        &write("header.csv", b"time_s,a,b\n"),
        &o,
        &[],
        &["no data rows"],
    );
    expect_error(
        &write("onecol_time.csv", b"time_s\n0\n0.001\n"),
        &o,
        &[],
        &["no data channel", "time column"],
    );
    expect_error(
        &write("onecol_nofs.csv", b"accel\n1\n2\n"),
        &o,
        &[],
        &["no time column", "--fs"],
    );
    expect_error(
        &write("ragged.csv", b"time_s,a,b\n0,1,2\n0.001,1\n0.002,1,2\n"),
        &o,
        &[],
        &["line 3", "expected 3 fields", "found 2"],
    );
    expect_error(
        &write("noname.csv", b"time_s,,b\n0,1,2\n"),
        &o,
        &[],
        &["line 1", "column 2 has no channel name"],
    );
    expect_error(
        &write("dup.csv", b"time_s,a,a\n0,1,2\n"),
        &o,
        &[],
        &["`a` appears twice"],
    );
    expect_error(
        &write("nan.csv", b"time_s,a,b\n0,1,2\n0.001,NaN,2\n"),
        &o,
        &[],
        &["line 3", "column `a`", "not a number"],
    );
    expect_error(
        &write("inf.csv", b"time_s,a,b\n0,1,2\n0.001,1,inf\n"),
        &o,
        &[],
        &["line 3", "column `b`", "non-finite"],
    );
    expect_error(
        &write("text.csv", b"time_s,a,b\n0,1,2\n0.001,1,2\n0.002,1.2.3,2\n"),
        &o,
        &[],
        &["line 4", "column `a`", "cannot parse", "1.2.3"],
    );
    expect_error(
        &write("badtime.csv", b"time_s,a\n0,1\nx,2\n"),
        &o,
        &[],
        &["line 3", "column `time_s`"],
    );
    expect_error(
        &write("nonmono.csv", b"time_s,a\n0,1\n0.001,2\n0.003,1\n0.002,2\n"),
        &o,
        &[],
        &["line 5", "does not increase"],
    );
    expect_error(
        &write(
            "binary.csv",
            &[0x50, 0x4b, 0x03, 0x04, 0x00, 0x00, 0xff, 0xfe],
        ),
        &o,
        &[],
        &["binary", "byte 0x03 at offset 2"],
    );
    // Not UTF-8 and no NUL byte: read as Windows-1252 text, whose cell is then no number.
    expect_error(
        &write("latin1.csv", b"time_s,a\n0,\xb0\xff\xfe\n"),
        &o,
        &[],
        &["line 2", "column `a`", "cannot parse number `°ÿþ`"],
    );
    let sel = IngestOptions {
        channels: Some(vec!["zz".into()]),
        ..Default::default()
    };
    let p = write("sel.csv", b"time_s,a,b\n0,1,2\n0.001,1,2\n");
    let e = read_csv(&p, &sel).unwrap_err().to_string();
    assert!(
        e.contains("no channel named `zz`") && e.contains("available: a, b"),
        "{e}"
    );
    let (code, _, err) = cli(&["psd", p.to_str().unwrap(), "--channels", "zz"], None);
    assert!(code == 2 && err.contains("`zz`"), "{err}");
    cleanup();
}

#[test]
fn one_data_column_with_fs_is_fine() {
    let p = write("onecol_fs.csv", b"accel_g\n1\n2\n3\n4\n5\n6\n7\n8\n");
    let log = read_csv(
        &p,
        &IngestOptions {
            fs: Some(100.0),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(log.info.fs_hz, 100.0);
    assert_eq!(log.data[0], vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
    cleanup();
}

#[test]
fn welch_parameter_errors_from_the_cli() {
    let p = write("short.csv", uniform_csv(100, &["a"]).as_bytes());
    let (code, _, err) = cli(&["psd", p.to_str().unwrap(), "--nperseg", "256"], None);
    assert_eq!(code, 2);
    assert!(
        err.contains("nperseg = 256") && err.contains("100 samples") && err.contains("short.csv"),
        "{err}"
    );
    for ov in ["1", "1.5", "-0.2"] {
        let (code, _, err) = cli(
            &[
                "psd",
                p.to_str().unwrap(),
                "--nperseg",
                "16",
                &format!("--overlap={ov}"),
            ],
            None,
        );
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("overlap") && err.contains("[0, 1)"), "{err}");
    }
    let (code, _, err) = cli(
        &[
            "psd",
            p.to_str().unwrap(),
            "--nperseg",
            "16",
            "--window",
            "kaiser",
        ],
        None,
    );
    assert!(code == 2 && err.contains("kaiser"), "{err}");
    cleanup();
}

#[test]
fn non_uniform_time_names_the_row_unless_resampled() {
    let mut s = String::from("time_s,a\n");
    let mut t = 0.0;
    for i in 0..200 {
        // A gap: one step of 3 ms instead of 1 ms at data row 120 (file line 122).
        t += if i == 120 {
            0.003
        } else if i == 0 {
            0.0
        } else {
            0.001
        };
        s.push_str(&format!("{t:.6},{}\n", (i as f64 * 0.3).sin()));
    }
    let p = write("gap.csv", s.as_bytes());
    expect_error(
        &p,
        &IngestOptions::default(),
        &[],
        &["line 122", "time step", "--resample"],
    );
    let log = read_csv(
        &p,
        &IngestOptions {
            resample: true,
            ..Default::default()
        },
    )
    .unwrap();
    let r = log.info.resampled.clone().expect("a resampling report");
    assert_eq!(
        (r.irregular_rows, r.first_irregular_line, r.input_rows),
        (1, 122, 200)
    );
    // 200 rows spanning 0.201 s at 1 ms: 202 grid points (the gap is filled by 2).
    assert_eq!(r.output_samples, 202);
    assert!((log.info.fs_hz - 1000.0).abs() < 1e-6);
    let (code, out, err) = cli(
        &[
            "psd",
            p.to_str().unwrap(),
            "--nperseg",
            "64",
            "--resample",
            "--json",
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["resampled"]["irregular_rows"], 1);
    assert!(err.contains("resampled"), "{err}");
    // A gap of 500 intervals is not bridged, even with --resample.
    let p = write(
        "biggap.csv",
        b"time_s,a\n0,1\n0.001,2\n0.002,3\n0.502,4\n0.503,5\n",
    );
    let e = read_csv(
        &p,
        &IngestOptions {
            resample: true,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("line 5") && e.contains("100 sampling intervals"),
        "{e}"
    );
    cleanup();
}

#[test]
fn streamed_psd_equals_in_memory_welch_and_units_convert() {
    let p = write(
        "multi.csv",
        uniform_csv(20000, &["a_g", "b_m_s2", "c"]).as_bytes(),
    );
    let o = WelchOptions {
        nperseg: 1000,
        ..Default::default()
    };
    let streamed = psd_of_file(&p, &IngestOptions::default(), &o).unwrap();
    let log = read_csv(&p, &IngestOptions::default()).unwrap();
    // Time column printed to 1e-9 s over 20 s: fs within 1e-9 relative of 1000 Hz.
    assert!((log.info.fs_hz - 1000.0).abs() < 1e-6);
    for (c, ch) in streamed.channels.iter().enumerate() {
        let mem = welch(&log.data[c], log.info.fs_hz, &o).unwrap();
        // Same block code and summation order: bit-identical.
        assert_eq!(ch.psd.values, mem.values, "channel {}", ch.name);
    }
    // b is in m/s² (its name says so) and reported in g: its values were divided by g0.
    let raw = read_csv(
        &p,
        &IngestOptions {
            channel_units: vec![("b_m_s2".into(), satqual::signal::Unit::AsIs)],
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(streamed.channels[1].unit, "g");
    assert!((raw.data[1][5] / satqual::units::G - log.data[1][5]).abs() < 1e-15);
    cleanup();
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let p = write(
        "threads.csv",
        uniform_csv(60000, &["a", "b", "c", "d"]).as_bytes(),
    );
    let args = ["psd", p.to_str().unwrap(), "--nperseg", "512", "--json"];
    let (c1, o1, e1) = cli(&args, Some("1"));
    let (c2, o2, e2) = cli(&args, Some("2"));
    let (c3, o3, _) = cli(&args, Some("3"));
    assert_eq!((c1, c2, c3), (0, 0, 0), "{e1}{e2}");
    assert!(o1.contains("\"grms\""));
    assert_eq!(o1, o2, "RAYON_NUM_THREADS=1 and 2 differ");
    assert_eq!(o1, o3, "RAYON_NUM_THREADS=1 and 3 differ");
    // The reader cuts its blocks into 4 pieces per thread: the line an error names must not
    // depend on that either. A bad cell on file line 150 002 of a 5 MB file:
    let mut rows: Vec<String> = uniform_csv(200_000, &["a"])
        .lines()
        .map(str::to_string)
        .collect();
    let t = rows[150_001].split(',').next().unwrap().to_string();
    rows[150_001] = format!("{t},1..2");
    let p = write("threads_err.csv", rows.join("\n").as_bytes());
    let args = ["psd", p.to_str().unwrap(), "--nperseg", "512"];
    let errs: Vec<String> = ["1", "2", "5"]
        .iter()
        .map(|n| {
            let (code, _, err) = cli(&args, Some(n));
            assert_eq!(code, 2);
            err
        })
        .collect();
    assert!(
        errs[0].contains("line 150002") && errs[0].contains("`1..2`"),
        "{}",
        errs[0]
    );
    assert!(errs.iter().all(|e| *e == errs[0]), "{errs:?}");
    cleanup();
}

#[test]
fn uff_bad_inputs_are_errors() {
    let good = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff"
    ))
    .unwrap_or_else(|_| {
        String::from_utf8_lossy(
            &std::fs::read(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff"
            ))
            .unwrap(),
        )
        .into_owned()
    });
    let lines: Vec<&str> = good.lines().collect();
    let truncated = lines[..200].join("\n");
    let p = write("trunc.uff", truncated.as_bytes());
    let e = satqual::signal::read_uff58(&p).unwrap_err().to_string();
    assert!(e.contains("not closed"), "{e}");
    let mut short: Vec<&str> = lines.clone();
    short.remove(100);
    let p = write("short.uff", short.join("\n").as_bytes());
    let e = satqual::signal::read_uff58(&p).unwrap_err().to_string();
    assert!(
        e.contains("announces 3201 points") && e.contains("line 9"),
        "{e}"
    );
    let mut bad: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    bad[50] = bad[50].replacen("E", "Q", 1);
    let p = write("badnum.uff", bad.join("\n").as_bytes());
    let e = satqual::signal::read_uff58(&p).unwrap_err().to_string();
    assert!(e.contains("line 51") && e.contains("cannot parse"), "{e}");
    let p = write(
        "b.uff",
        b"    -1\n    58b     1     1          11        1000     0     0     0     0\n",
    );
    let e = satqual::signal::read_uff58(&p).unwrap_err().to_string();
    assert!(e.contains("58b"), "{e}");
    let (code, _, err) = cli(&["psd", p.to_str().unwrap()], None);
    assert!(code == 2 && err.contains("58b"), "{err}");
    cleanup();
}

#[test]
fn errors_deep_in_a_multi_block_file_name_the_right_line() {
    // 300 000 rows (~9 MB, more than two 4 MiB read blocks, each cut into parallel pieces).
    let mut s = uniform_csv(300_000, &["a"]);
    let lines: Vec<&str> = s.lines().collect();
    let target = 250_001; // file line 250 002 (header is line 1)
    let mut parts: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let t = parts[target].split(',').next().unwrap().to_string();
    parts[target] = format!("{t},nan");
    s = parts.join("\n");
    let p = write("deep.csv", s.as_bytes());
    let e = read_csv(&p, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 250002") && e.contains("column `a`"), "{e}");
    parts[target] = format!("{t},0.5");
    parts.insert(100_000, String::new());
    parts.insert(100_000, " ".into());
    let p = write("deep_ok.csv", parts.join("\r\n").as_bytes());
    let log = read_csv(&p, &IngestOptions::default()).unwrap();
    assert_eq!(
        log.info.samples, 300_000,
        "blank lines are skipped, CRLF accepted"
    );
    assert_eq!(log.data[0][target - 1], 0.5);
    cleanup();
}

#[test]
fn quoted_cells_are_read_through_the_csv_parser() {
    let p = write(
        "quoted.csv",
        b"\"time_s\",\"a\"\n0,\"1.5\"\n0.001,2\n0.002,\"x\"\n",
    );
    let e = read_csv(&p, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 4") && e.contains("column `a`") && e.contains("`x`"),
        "{e}"
    );
    let p = write(
        "quoted_ok.csv",
        b"\"time_s\",\"a\"\n0,\"1.5\"\n0.001,2\n0.002,\" 3 \"\n",
    );
    let log = read_csv(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.data[0], vec![1.5, 2.0, 3.0]);
    cleanup();
}

#[test]
fn absurd_parameters_are_errors_not_allocations() {
    // nperseg far beyond the log (and beyond memory) must be refused before anything is sized
    // by it; so must a sweep block longer than the record.
    let p = write("tiny.csv", uniform_csv(50, &["a"]).as_bytes());
    let (code, _, err) = cli(
        &["psd", p.to_str().unwrap(), "--nperseg", "1000000000000000"],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("nperseg = 1000000000000000") && err.contains("50 samples"),
        "{err}"
    );
    let e = welch(
        &[1.0; 10],
        1.0,
        &WelchOptions {
            nperseg: usize::MAX,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("has 10 samples, fewer than the 16"),
        "{e}"
    );
    let o = satqual::signal::SweepOptions {
        block_s: 1e300,
        hop_s: 1e300,
        ..Default::default()
    };
    let e = satqual::signal::track_sweep(&[0.0; 64], &[&[0.0; 64]], 1000.0, &o).unwrap_err();
    assert!(e.to_string().contains("longer than the signal"), "{e}");
    cleanup();
}
