//! Property tests over the CSV and UFF58 readers: whatever the bytes, they return a value or an
//! error, never panic; valid logs round-trip exactly. Case counts are modest so the suite stays
//! fast; a longer run is `PROPTEST_CASES=20000 cargo test --release --test integration signal_proptest`.

use proptest::prelude::*;
use satqual::signal::ingest::{IngestOptions, read_csv};
use satqual::signal::uff::parse_uff58;
use std::path::{Path, PathBuf};

fn tmpfile(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!(
        "satqual-sig-prop-{}-{tag}-{:?}.csv",
        std::process::id(),
        std::thread::current().id()
    ))
}

fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|v| format!("{v}")),
        (-1e6f64..1e6).prop_map(|v| format!("{v:e}")),
        Just(String::new()),
        Just("NaN".to_string()),
        Just("-inf".to_string()),
        Just("1e999".to_string()),
        Just("\"3.5\"".to_string()),
        Just(" 2 ".to_string()),
        "[a-z]{1,4}",
        Just("1,2".to_string()),
        Just("\u{feff}".to_string()),
    ]
}

fn header() -> impl Strategy<Value = Vec<String>> {
    prop::collection::vec(
        prop_oneof![
            Just("time_s".to_string()),
            Just("t".to_string()),
            Just(String::new()),
            "[a-c]{1,2}"
        ],
        1..5,
    )
}

fn read_bytes(
    bytes: &[u8],
    opts: &IngestOptions,
) -> Result<satqual::signal::Log, satqual::error::SignalError> {
    let p = tmpfile("bytes");
    std::fs::write(&p, bytes).unwrap();
    let r = read_csv(&p, opts);
    std::fs::remove_file(&p).ok();
    r
}

proptest! {
    #![proptest_config(ProptestConfig { cases: std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(300), ..ProptestConfig::default() })]

    #[test]
    fn csv_reader_never_panics_on_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400), fs in prop::option::of(0.5f64..1e4)) {
        let _ = read_bytes(&bytes, &IngestOptions { fs, ..Default::default() });
        let _ = read_bytes(&bytes, &IngestOptions { fs, resample: true, ..Default::default() });
    }

    #[test]
    fn csv_reader_never_panics_on_csv_like_text(h in header(), rows in prop::collection::vec(prop::collection::vec(cell(), 0..6), 0..40), resample in any::<bool>(), fs in prop::option::of(1.0f64..100.0)) {
        let mut s = h.join(",");
        s.push('\n');
        for r in &rows {
            s.push_str(&r.join(","));
            s.push('\n');
        }
        match read_bytes(s.as_bytes(), &IngestOptions { fs, resample, ..Default::default() }) {
            Ok(log) => {
                prop_assert!(log.info.fs_hz.is_finite() && log.info.fs_hz > 0.0);
                prop_assert!(log.data.iter().all(|c| c.len() as u64 == log.info.samples && c.iter().all(|v| v.is_finite())));
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }

    #[test]
    fn valid_logs_round_trip(values in prop::collection::vec(prop::collection::vec(-1e12f64..1e12, 3), 2..60), dt in 1e-5f64..1.0) {
        let mut s = String::from("time_s,a,b,c\n");
        for (i, r) in values.iter().enumerate() {
            s.push_str(&format!("{:e},{:e},{:e},{:e}\n", i as f64 * dt, r[0], r[1], r[2]));
        }
        let log = read_bytes(s.as_bytes(), &IngestOptions::default()).unwrap();
        prop_assert_eq!(log.info.samples as usize, values.len());
        for (i, r) in values.iter().enumerate() {
            for (col, v) in log.data.iter().zip(r) {
                prop_assert_eq!(col[i], *v);
            }
        }
        prop_assert!((log.info.fs_hz * dt - 1.0).abs() < 1e-9);
    }

    #[test]
    fn extreme_time_columns_end_in_a_value_or_an_error(times in prop::collection::vec(prop_oneof![any::<f64>(), 0.0f64..1.0, Just(1e-300), Just(1e300)], 1..40), resample in any::<bool>()) {
        let mut s = String::from("t,a\n");
        for t in &times {
            s.push_str(&format!("{t:e},1\n"));
        }
        if let Ok(log) = read_bytes(s.as_bytes(), &IngestOptions { resample, ..Default::default() }) {
            prop_assert!(log.info.fs_hz.is_finite() && log.info.fs_hz > 0.0);
            // Resampling never bridges more than 100 intervals per input step.
            prop_assert!(log.info.samples <= 100 * times.len() as u64 + 1);
        }
    }

    #[test]
    fn fast_and_careful_row_paths_agree(rows in prop::collection::vec((prop::collection::vec((-1e9f64..1e9, 0usize..4), 2), any::<bool>()), 2..80)) {
        // Cells in several spellings: plain rows take the in-place fast path, rows with blanks
        // the careful one; both must give exactly the values Rust's own parser gives.
        let mut s = String::from("time_s,a,b\n");
        for (i, (cells, crlf)) in rows.iter().enumerate() {
            s.push_str(&format!("{:e}", i as f64 * 0.001));
            for (v, style) in cells {
                let c = match style { 0 => format!("{v}"), 1 => format!("{v:e}"), 2 => format!(" {v}"), _ => format!("{v:e} ") };
                s.push(',');
                s.push_str(&c);
            }
            s.push_str(if *crlf { "\r\n" } else { "\n" });
        }
        let log = read_bytes(s.as_bytes(), &IngestOptions::default()).unwrap();
        for (i, (cells, _)) in rows.iter().enumerate() {
            for (c, (v, style)) in cells.iter().enumerate() {
                let text = if *style % 2 == 0 { format!("{v}") } else { format!("{v:e}") };
                prop_assert_eq!(log.data[c][i], text.parse::<f64>().unwrap());
            }
        }
    }

    #[test]
    fn uff_reader_never_panics_on_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = parse_uff58(Path::new("fuzz.uff"), &bytes);
        let mut b = b"    -1\n    58\n".to_vec();
        b.extend(&bytes);
        let _ = parse_uff58(Path::new("fuzz.uff"), &b);
    }

    #[test]
    fn uff_reader_never_panics_on_mutated_records(cut in 0usize..3300, drop in 0usize..3300, edit in 0usize..3300, token in "[-+.0-9EeDd ]{0,14}|-1|58b?") {
        let src = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff")).unwrap();
        let text = String::from_utf8_lossy(&src).into_owned();
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        if edit < lines.len() { lines[edit] = token.clone(); }
        if drop < lines.len() { lines.remove(drop); }
        lines.truncate(cut.max(1));
        match parse_uff58(Path::new("mutated.uff"), lines.join("\n").as_bytes()) {
            Ok(recs) => prop_assert!(recs.iter().all(|r| r.abscissa.len() == r.re.len())),
            Err(e) => prop_assert!(e.to_string().contains("mutated.uff")),
        }
    }
}
