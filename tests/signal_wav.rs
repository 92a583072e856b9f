//! WAV logs, read against an independent reader (scipy.io.wavfile 1.17) on files written by
//! two writers (Python's `wave` module for PCM of 8, 16, 24 and 32 bits; scipy for floats).
//! Files and references: data/format-refs/wav/make_wav.py.

use crate::common::{exact, mutate_bytes, psd_error, repo_path};
use satqual::signal::formats::wav::read_wav;
use satqual::signal::ingest::IngestOptions;
use satqual::signal::read_log;
use std::path::{Path, PathBuf};

fn wav(name: &str) -> PathBuf {
    repo_path(&format!("data/format-refs/wav/{name}"))
}

#[test]
fn every_channel_reads_as_scipy_reads_it() {
    let text = std::fs::read_to_string(wav("expected.json")).unwrap();
    let refs: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut checked = 0;
    for (file, r) in refs["files"].as_object().unwrap() {
        let log = read_log(&wav(file), &IngestOptions::default()).unwrap();
        assert_eq!(log.info.fs_hz, r["fs_hz"].as_f64().unwrap(), "{file}");
        for (name, c) in r["channels"].as_object().unwrap() {
            let k = log.info.channels.iter().position(|ch| &ch.name == name);
            let v = &log.data[k.unwrap_or_else(|| panic!("{file}: no {name}"))];
            // The same integers scaled by the same power of two: exact.
            assert_eq!(
                v.len() as u64,
                c["count"].as_u64().unwrap(),
                "{file} {name}"
            );
            assert_eq!(v[0], exact(&c["first"]), "{file} {name}");
            assert_eq!(*v.last().unwrap(), exact(&c["last"]), "{file} {name}");
            let rms = (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
            let want = c["rms"].as_f64().unwrap();
            assert!((rms - want).abs() <= 1e-13 * want, "{file} {name}: {rms}");
            checked += 1;
        }
    }
    assert_eq!(checked, 10, "channels compared");
}

fn edited(name: &str, edit: impl Fn(&mut Vec<u8>)) -> PathBuf {
    crate::common::edited_copy(&wav("wave_pcm16_2ch.wav"), name, edit)
}

#[test]
fn cut_compressed_and_inconsistent_files_are_located_errors() {
    // `wave` writes the 16-byte `fmt ` chunk at byte 12 and the `data` chunk header at 36.
    let cut = edited("cut", |b| b.truncate(2000));
    let e = psd_error(&cut);
    assert!(
        e.contains("chunk `data` at byte 36 announces 8000 bytes"),
        "{e}"
    );
    let mu_law = edited("mu-law", |b| b[20] = 7);
    assert!(psd_error(&mu_law).contains("format tag 7 (compressed audio"));
    let frames = edited("frames", |b| b[32] = 3);
    let e = psd_error(&frames);
    assert!(
        e.contains("2 channel(s) at 8000 Hz with 3-byte frames"),
        "{e}"
    );
}

/// A `data` chunk whose size field was never written (0, the recorder stopped before going
/// back to it) with the samples after it: the error says so, and never prints sample bytes
/// as a chunk id (the probe's file printed `\xEF\xBF\xBD\x06\0\0`).
#[test]
fn a_data_chunk_declared_empty_with_samples_after_it_is_named() {
    // `wave` writes the `data` chunk header at byte 36: its size field is bytes 40..44.
    let unfinished = edited("datasize0", |b| b[40..44].copy_from_slice(&[0; 4]));
    let e = psd_error(&unfinished);
    assert!(
        e.contains(
            "the `data` chunk at byte 36 is declared empty (size 0) but 8000 bytes follow it"
        ),
        "{e}"
    );
    assert!(!e.contains('\u{FFFD}') && !e.contains('\0'), "{e:?}");
    // A chunk id that is not text is printed with its bytes escaped.
    let garbage = edited("garbage-id", |b| {
        b[36..40].copy_from_slice(&[0xBD, 0x06, 0, 0]);
        b[40..44].copy_from_slice(&u32::MAX.to_le_bytes());
    });
    let e = psd_error(&garbage);
    assert!(e.contains("chunk `\\xBD\\x06\\x00\\x00` at byte 36"), "{e}");
}

#[test]
fn mutated_files_give_a_log_or_an_error_never_a_panic() {
    let original = std::fs::read(wav("wave_pcm24_2ch.wav")).unwrap();
    let (mut read, mut refused) = (0, 0);
    let mut run = |b: &[u8]| match read_wav(Path::new("mutant.wav"), b) {
        Ok(_) => read += 1,
        Err(e) => {
            refused += 1;
            assert!(e.to_string().contains("WAV: "), "{e}");
        }
    };
    // The header and the first frames mutated, the file cut at every 97th length.
    mutate_bytes(&original, 200, (12, 97), &mut run);
    assert!(read > 0 && refused > 0, "read {read}, refused {refused}");
}
