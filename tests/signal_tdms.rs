//! NI TDMS logs: read against an independent reader (npTDMS 1.13) on files written by two
//! independent writers (npTDMS's TdmsWriter, and a segment builder written from NI's format
//! description for what TdmsWriter never writes: big-endian, interleaved, reused metadata, an
//! unfinished last segment). Files and references: data/format-refs/tdms/make_tdms.py.

use crate::common::{exact, mutate_bytes, psd_error, repo_path, run_text};
use satqual::signal::formats::tdms::read_tdms;
use satqual::signal::ingest::{IngestOptions, Log, Unit};
use satqual::signal::read_log;
use std::path::{Path, PathBuf};

fn tdms(name: &str) -> PathBuf {
    repo_path(&format!("data/format-refs/tdms/{name}"))
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// One channel in the file's own unit, at the rate the channel itself states.
fn channel_as_is(path: &Path, channel: &str) -> (Vec<f64>, f64) {
    let opts = IngestOptions {
        channels: Some(vec![channel.to_string()]),
        channel_units: vec![(channel.to_string(), Unit::AsIs)],
        ..IngestOptions::default()
    };
    let log = read_log(path, &opts).unwrap_or_else(|e| panic!("{channel}: {e}"));
    (log.data[0].clone(), log.info.fs_hz)
}

#[test]
fn every_real_channel_reads_as_nptdms_reads_it() {
    let text = std::fs::read_to_string(tdms("expected.json")).unwrap();
    let refs: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut checked = 0;
    for (file, channels) in refs["files"].as_object().unwrap() {
        for (name, r) in channels.as_object().unwrap() {
            let Some(want_rms) = r["rms"].as_f64() else {
                continue;
            };
            let (v, fs) = channel_as_is(&tdms(file), name);
            // The same bits read by two readers: count, first and last value exact; the RMS to
            // the summation order (numpy's pairwise sum against a running sum).
            assert_eq!(
                v.len() as u64,
                r["count"].as_u64().unwrap(),
                "{file} {name}"
            );
            assert_eq!(v[0], exact(&r["first"]), "{file} {name}");
            assert_eq!(*v.last().unwrap(), exact(&r["last"]), "{file} {name}");
            assert!(
                (rms(&v) - want_rms).abs() <= 1e-13 * want_rms,
                "{file} {name}: {} against {want_rms}",
                rms(&v)
            );
            if let Some(dt) = r["wf_increment"].as_f64() {
                assert_eq!(fs, 1.0 / dt, "{file} {name}");
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 11, "channels compared");
}

fn names_and_units(log: &Log) -> Vec<(&str, Unit)> {
    log.info
        .channels
        .iter()
        .map(|c| (c.name.as_str(), c.unit))
        .collect()
}

#[test]
fn units_rate_and_what_is_not_read_come_from_the_properties() {
    let log = read_log(&tdms("nptdms_writer.tdms"), &IngestOptions::default()).unwrap();
    assert_eq!(
        names_and_units(&log),
        [
            ("Acc ctrl", Unit::G),
            ("Acc resp", Unit::MPerS2),
            ("Force", Unit::AsIs)
        ]
    );
    assert_eq!(log.info.fs_hz, 2048.0);
    let ignored = log.info.ingest.ignored_columns.join("; ");
    assert!(ignored.contains("`Comment` (strings)"), "{ignored}");
    assert!(
        ignored.contains("`Temperature` (sampled at its own rate: wf_increment 0.5 s"),
        "{ignored}"
    );
    // The slow channel alone is read at its own rate.
    let (t, fs) = channel_as_is(&tdms("nptdms_writer.tdms"), "Temperature");
    assert_eq!((t.len(), fs), (20, 2.0));
}

#[test]
fn a_timestamp_channel_is_the_time_vector() {
    let log = read_log(&tdms("nptdms_timestamps.tdms"), &IngestOptions::default()).unwrap();
    assert_eq!(log.info.time_column.as_deref(), Some("Time"));
    // 999 steps of exactly 1 ms (npTDMS wrote microsecond datetimes).
    assert!((log.info.fs_hz - 1000.0).abs() < 1e-9, "{}", log.info.fs_hz);
    assert_eq!(log.info.channels.len(), 1);
}

#[test]
fn big_endian_interleaved_and_unfinished_segments_are_noted() {
    let log = read_log(&tdms("handmade_big_endian.tdms"), &IngestOptions::default()).unwrap();
    let names: Vec<&str> = log.info.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["acc 'x'", "load"]);
    let notes = log.info.ingest.notes.join("\n");
    assert!(notes.contains("big-endian, 4 segment(s)"), "{notes}");
    assert!(
        notes.contains("segment 4 (byte 5200) is the last and its length was never written"),
        "{notes}"
    );
}

#[test]
fn daqmx_channels_are_scaled_by_the_chain_in_their_properties() {
    let log = read_log(&tdms("handmade_daqmx.tdms"), &IngestOptions::default()).unwrap();
    assert_eq!(
        names_and_units(&log),
        [("ai0", Unit::G), ("ai1", Unit::AsIs), ("ai2", Unit::G)]
    );
    assert_eq!(log.info.fs_hz, 25600.0);
    let notes = log.info.ingest.notes.join("\n");
    assert!(notes.contains("3 channel(s) of DAQmx raw data"), "{notes}");
    assert!(
        notes.contains("`ai0` (DAQmx raw → Polynomial → Linear)"),
        "{notes}"
    );
    let (code, out, err) = run_text(
        &[
            "psd",
            tdms("handmade_daqmx.tdms").to_str().unwrap(),
            "--json",
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["channels"].as_array().unwrap().len(), 3);
}

fn with_bytes(name: &str, file: &str, edit: impl Fn(&mut Vec<u8>)) -> PathBuf {
    crate::common::edited_copy(&tdms(file), name, edit)
}

#[test]
fn misflagged_segments_index_files_broken_segments_and_nan_are_located_errors() {
    // The table of contents' DAQmx flag (bit 7) on a segment of plain channels.
    let daqmx = with_bytes("daqmx", "handmade_big_endian.tdms", |b| b[4] |= 0x80);
    let e = psd_error(&daqmx);
    assert!(
        e.contains("segment 1 (byte 0): DAQmx raw data, but `/'Rig'/'acc ''x'''` has a plain"),
        "{e}"
    );
    let index = with_bytes("index", "handmade_big_endian.tdms", |b| b[3] = b'h');
    assert!(psd_error(&index).contains("`.tdms_index`"));
    let cut = with_bytes("cut", "handmade_big_endian.tdms", |b| b.truncate(100));
    let e = psd_error(&cut);
    assert!(
        e.contains("segment 1 (byte 0): its metadata would end at byte"),
        "{e}"
    );
    // The first value of the first segment's interleaved data (raw data offset at bytes 20..28,
    // big-endian, counted from the end of the 28-byte lead-in) made a NaN.
    let nan = with_bytes("nan", "handmade_big_endian.tdms", |b| {
        let raw = u64::from_be_bytes(b[20..28].try_into().unwrap()) as usize;
        b[28 + raw..36 + raw].copy_from_slice(&f64::NAN.to_be_bytes());
    });
    let e = psd_error(&nan);
    assert!(
        e.contains("channel `acc 'x'`: sample 1 of 500 is NaN"),
        "{e}"
    );
}

#[test]
fn mutated_files_give_a_log_or_an_error_never_a_panic() {
    // Every byte of the handmade files set to 0x00, 0xFF and its value + 1, and the file cut at
    // every 13th length: each read ends in a table or an error message.
    for file in ["handmade_big_endian.tdms", "handmade_daqmx.tdms"] {
        mutate_every_byte(&std::fs::read(tdms(file)).unwrap());
    }
}

fn mutate_every_byte(original: &[u8]) {
    let path = Path::new("mutant.tdms");
    let (mut read, mut refused) = (0, 0);
    let mut run = |b: &[u8]| match read_tdms(path, b, None) {
        Ok(t) => {
            read += 1;
            assert!(t.series.iter().all(|s| !s.values.is_empty()));
        }
        Err(e) => {
            refused += 1;
            assert!(e.to_string().contains("TDMS: "), "{e}");
        }
    };
    mutate_bytes(original, original.len(), (0, 13), &mut run);
    assert!(read > 0 && refused > 0, "read {read}, refused {refused}");
}

/// npTDMS's test folder, where npTDMS is installed.
fn nptdms_test_folder() -> Result<PathBuf, String> {
    let out = std::process::Command::new("python3")
        .args([
            "-c",
            "import nptdms, os; print(os.path.join(os.path.dirname(nptdms.__file__), 'test', 'data'))",
        ])
        .output()
        .map_err(|e| format!("python3 not runnable: {e}"))?;
    if !out.status.success() {
        return Err("npTDMS is not installed (pip install npTDMS==1.13.0)".into());
    }
    Ok(PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
}

#[test]
fn files_labview_and_daqmx_wrote_read_as_nptdms_reads_them() {
    // Four TDMS files written by LabVIEW, SignalExpress and NI-DAQmx, shipped (LGPL-3.0) in
    // npTDMS's test folder; npTDMS's readings in data/format-refs/tdms/nptdms_testdata.json.
    let folder = match nptdms_test_folder() {
        Ok(f) => f,
        Err(why) => {
            eprintln!("skipped: {why}");
            return;
        }
    };
    let text = std::fs::read_to_string(tdms("nptdms_testdata.json")).unwrap();
    let refs: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut checked = 0;
    for (file, r) in refs["files"].as_object().unwrap() {
        let path = folder.join(file);
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        if size != r["bytes"].as_u64().unwrap() {
            eprintln!(
                "skipped {file}: {size} bytes, not the {} read for the reference (another npTDMS version)",
                r["bytes"]
            );
            continue;
        }
        for (name, c) in r["channels"].as_object().unwrap() {
            let (v, fs) = channel_as_is(&path, name);
            assert_eq!(
                v.len() as u64,
                c["count"].as_u64().unwrap(),
                "{file} {name}"
            );
            assert_eq!(v[0], exact(&c["first"]), "{file} {name}");
            assert_eq!(*v.last().unwrap(), exact(&c["last"]), "{file} {name}");
            let want = c["rms"].as_f64().unwrap();
            assert!((rms(&v) - want).abs() <= 1e-13 * want, "{file} {name}");
            // DAQmx writes each channel's increment with its own last bits; increments within
            // 1e-9 share one rate, the first channel's.
            if let Some(dt) = c["wf_increment"].as_f64() {
                assert!((fs * dt - 1.0).abs() < 1e-9, "{file} {name}: {fs} Hz");
            }
            checked += 1;
        }
    }
    assert!(checked > 0, "no channel compared");
    eprintln!("{checked} channels of npTDMS's test files compared");
}
