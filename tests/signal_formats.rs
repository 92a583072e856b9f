//! Log formats beside CSV: UFF58 binary (58b) and its full header, LabVIEW .lvm, MATLAB .mat,
//! and the corpus of third-party logs in data/realdata/, each read and checked against an
//! independent reader (pyuff, lvm_read, scipy.io.loadmat, numpy.loadtxt; references made by
//! data/format-refs/make_corpus_refs.py).

use crate::common::{repo_path, run_text};
use satqual::signal::ingest::{IngestOptions, Unit};
use satqual::signal::uff::read_uff58;
use satqual::signal::{LogFormat, read_log};
use std::path::Path;

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// Reads one channel in the file's own unit (no g conversion), as the peer reader gives it.
fn channel_as_is(path: &Path, channel: &str, fs: Option<f64>) -> Result<(Vec<f64>, f64), String> {
    let opts = IngestOptions {
        channels: Some(vec![channel.to_string()]),
        channel_units: vec![(channel.to_string(), Unit::AsIs)],
        fs,
        fs_override: fs.is_some(),
        ..IngestOptions::default()
    };
    let log = read_log(path, &opts).map_err(|e| e.to_string())?;
    Ok((log.data[0].clone(), log.info.fs_hz))
}

#[test]
fn every_corpus_log_matches_its_independent_reader() {
    let text = std::fs::read_to_string(repo_path("data/format-refs/corpus_refs.json")).unwrap();
    let refs: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut files = std::collections::BTreeSet::new();
    for r in refs["refs"].as_array().unwrap() {
        let file = r["file"].as_str().unwrap();
        let channel = r["channel"].as_str().unwrap();
        let path = repo_path(&format!("data/realdata/{file}"));
        let (values, fs) = if file.ends_with("_psd.uff") {
            // A spectrum record, not a time history: read it as a record.
            let recs = read_uff58(&path).unwrap();
            let rec = recs.iter().find(|r| r.id4 == channel).unwrap();
            (rec.re.clone(), f64::NAN)
        } else if file.ends_with(".mat") || file.ends_with("with_comments.lvm") {
            // MATLAB's sample arrays state no rate, and this LVM's X column is irregular (a
            // logger writing when it has a value): a stated rate reads them; the values must
            // still be the file's.
            channel_as_is(&path, channel, Some(1.0)).unwrap_or_else(|e| panic!("{file}: {e}"))
        } else {
            channel_as_is(&path, channel, None).unwrap_or_else(|e| panic!("{file}: {e}"))
        };
        assert_eq!(
            values.len() as u64,
            r["samples"].as_u64().unwrap(),
            "{file}"
        );
        // Same decimal text or the same binary numbers: only the summation order differs.
        let want = r["rms"].as_f64().unwrap();
        let got = rms(&values);
        assert!(
            (got - want).abs() <= 1e-12 * want,
            "{file} {channel}: {got} vs {want}"
        );
        if let Some(f) = r["fs_hz"].as_f64() {
            assert!((fs - f).abs() <= 1e-9 * f, "{file}: fs {fs} vs {f}");
        }
        files.insert(file.to_string());
    }
    assert!(files.len() >= 12, "{} files in the corpus", files.len());
}

#[test]
fn formats_are_told_by_content() {
    let f = |p: &str| satqual::signal::formats::detect(&repo_path(p));
    assert_eq!(
        f("data/realdata/dialects/lvm_read/short.lvm"),
        LogFormat::Lvm
    );
    assert_eq!(
        f("data/realdata/scipy-matlab/big_endian.mat"),
        LogFormat::Mat
    );
    assert_eq!(
        f("data/realdata/dialects/pyuff/Sample_UFF58b_bin.uff"),
        LogFormat::Uff
    );
    assert_eq!(f("data/realdata/pyfrf-impact/impact_1.csv"), LogFormat::Csv);
    assert_eq!(
        f("data/format-refs/tdms/handmade_big_endian.tdms"),
        LogFormat::Tdms
    );
    assert_eq!(f("data/format-refs/wav/wave_pcm24_2ch.wav"), LogFormat::Wav);
}

#[test]
fn uff58b_header_is_read_in_full() {
    let recs = read_uff58(&repo_path(
        "data/realdata/dialects/pyuff/Sample_UFF58b_bin.uff",
    ))
    .unwrap();
    let r = &recs[0];
    // Values as pyuff 2.5.8 reads the same file.
    assert!(r.binary);
    assert_eq!(
        r.id4, "Mic 01",
        "ID line 4 is NONE: the response entity names the channel"
    );
    assert_eq!(
        (
            r.function.function_type,
            r.ordinate_type,
            r.function.response_direction
        ),
        (1, 2, 1)
    );
    assert_eq!(
        (r.abscissa_axis.data_type, r.abscissa_axis.unit.as_str()),
        (17, "s")
    );
    assert_eq!(r.ordinate_axis.data_type, 21);
    assert_eq!(r.ordinate_axis.label, "Pressure");
    assert_eq!(r.ordinate_label, "Pa");
    assert_eq!(r.re.len(), 79292);
    // First values: little-endian IEEE single, as pyuff gives them.
    assert_eq!(r.re[0] as f32, -0.014_755_26_f32);
}

#[test]
fn uff_without_dataset_58_and_broken_58b_are_located_errors() {
    let e = read_uff58(&repo_path(
        "data/realdata/dialects/pyuff/TestLab_161_164_18_15_82.uff",
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("datasets 151, 164, 18, 15, 82 only"), "{e}");
    let good = std::fs::read(repo_path(
        "data/realdata/dialects/pyuff/Sample_UFF58b_bin.uff",
    ))
    .unwrap();
    let dir = crate::common::temp_dir("formats-uff");
    let p = dir.join("cut.uff");
    std::fs::write(&p, &good[..5000]).unwrap();
    let e = read_uff58(&p).unwrap_err().to_string();
    assert!(e.contains("58b data block") && e.contains("line 14"), "{e}");
    // A byte count that disagrees with record 7 is refused, not read short.
    let text = String::from_utf8_lossy(&good[..200]).replace("317168", "317164");
    let mut bad = text.into_bytes();
    bad.extend_from_slice(&good[200..]);
    std::fs::write(&p, &bad).unwrap();
    let e = read_uff58(&p).unwrap_err().to_string();
    assert!(e.contains("317164") && e.contains("needs 317168"), "{e}");
    // Every truncation of the header region ends in an error or records, never a panic.
    for n in 0..1200 {
        let _ = satqual::signal::uff::parse_uff58(Path::new("t.uff"), &good[..n]);
    }
}

#[test]
fn lvm_header_decides_separator_decimal_units_and_rate() {
    let p = repo_path("data/realdata/dialects/lvm_read/short.lvm");
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.info.ingest.decimal, ",");
    assert_eq!(log.info.ingest.delimiter, "tab");
    // Delta_X 3.90625E-5 s.
    assert_eq!(log.info.fs_hz, 25600.0);
    // `Y_Unit_Label m/s^2`: reported in g (9.80665 m/s² per g).
    let resp = &log.info.channels[1];
    assert_eq!(
        (resp.name.as_str(), resp.unit),
        ("Response (Trigger)", Unit::MPerS2)
    );
    assert!((log.data[1][0] - 1.204792 / 9.80665).abs() < 1e-15);
    let p = repo_path("data/realdata/dialects/lvm_read/with_empty_fields.lvm");
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    let names: Vec<&str> = log.info.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["Dev0/Ai0", "Dev0/Ai2", "Dev0/Ai0 1"]);
    assert!(
        log.info
            .ingest
            .ignored_columns
            .iter()
            .any(|c| c.contains("Untitled 3"))
    );
    // An irregular X column is a located refusal that says what to pass.
    let p = repo_path("data/realdata/dialects/lvm_read/with_comments.lvm");
    let e = read_log(&p, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`X_Value`") && e.contains("sample 2") && e.contains("--fs-override"),
        "{e}"
    );
    // Latin-1 names decoded.
    let (_, fs) = channel_as_is(&p, "Temperatura (°C)", Some(1.0)).unwrap();
    assert_eq!(fs, 1.0);
}

/// An LVM file cut short: short.lvm (lvm_read's test data) announces `Samples 10` per channel
/// and holds 10 rows; with its header saying 8192, the 10 rows are still read, and a warning
/// names the segment's line and both counts. The file as published has no warning.
#[test]
fn an_lvm_file_holding_fewer_rows_than_its_header_announces_is_flagged() {
    let p = repo_path("data/realdata/dialects/lvm_read/short.lvm");
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert!(
        log.info.ingest.warnings.is_empty(),
        "{:?}",
        log.info.ingest.warnings
    );
    let text = std::fs::read(&p).unwrap();
    let cut = String::from_utf8_lossy(&text).replace("Samples\t10\t10", "Samples\t8192\t8192");
    assert_ne!(cut.as_bytes(), text.as_slice());
    let q = crate::common::temp_dir("lvm-cut").join("cut.lvm");
    std::fs::write(&q, cut).unwrap();
    let log = read_log(&q, &IngestOptions::default()).unwrap();
    assert_eq!(log.data[0].len(), 10);
    let w = log.info.ingest.warnings.join("\n");
    assert!(
        w.contains("line 15:")
            && w.contains("announces 8192 samples per channel, but 10 rows follow"),
        "{w}"
    );
    // The other way round, as LabVIEW's one-header mode writes it (lvm_read's
    // long_single_header_multi_ch.lvm: `Samples 8192` over 16 384 rows, two records): read
    // whole, with a note naming the writes, and no warning.
    let appended = String::from_utf8_lossy(&text).replace("Samples\t10\t10", "Samples\t5\t5");
    let q = crate::common::temp_dir("lvm-appended").join("appended.lvm");
    std::fs::write(&q, appended).unwrap();
    let log = read_log(&q, &IngestOptions::default()).unwrap();
    assert_eq!(log.data[0].len(), 10);
    assert!(log.info.ingest.warnings.is_empty());
    assert!(
        log.info.ingest.notes.iter().any(|n| n.contains("line 15:")
            && n.contains("announces 5 samples per channel and 10 rows follow (2 writes of 5")),
        "{:?}",
        log.info.ingest.notes
    );
}

/// A LabVIEW segment holding channels of two rates (uneven_comments.lvm: 24 channels at
/// Delta_X 0.5 s on every row, 5 at 1 s written on every fourth row and empty between): the
/// full channels are read at the X column's 2 Hz, each slower one is listed as not read with
/// its reason, and asking for one by name is an error giving that reason, not "no such channel".
#[test]
fn lvm_channels_of_a_slower_rate_are_named_not_read() {
    let p = repo_path("data/realdata/dialects/lvm_read/uneven_comments.lvm");
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.info.channels.len(), 24);
    assert_eq!(log.info.fs_hz, 2.0);
    let ignored = &log.info.ingest.ignored_columns;
    for slow in [
        "TotalWarmFlow",
        "ColdFlow",
        "MethaneFlow",
        "Lambda",
        "CDS Flow",
    ] {
        let entry = ignored
            .iter()
            .find(|c| c.starts_with(&format!("`{slow}`")))
            .unwrap_or_else(|| panic!("{slow} not listed: {ignored:?}"));
        assert!(
            entry.contains("empty in 12 of 16 rows, first at line 26")
                && entry.contains("Delta_X 1 s against the log's 0.5 s"),
            "{entry}"
        );
    }
    let opts = IngestOptions {
        channels: Some(vec!["ColdFlow".into()]),
        ..IngestOptions::default()
    };
    let e = read_log(&p, &opts).unwrap_err().to_string();
    assert!(
        e.contains("uneven_comments.lvm")
            && e.contains("`ColdFlow` cannot be read")
            && e.contains("empty in 12 of 16 rows"),
        "{e}"
    );
}

/// A LabVIEW file written block by block: short_new_line_end.lvm's segment twice. The second
/// segment continues the first (10 samples at Delta_X 3.90625e-5 s = 3.90625e-4 s later) by
/// its header clock with X0 reset to 0, or by its X0 with the same clock: one 20-sample record,
/// the first segment's values then the second's. A second segment 1 s late, or with other
/// columns, is refused at its header line (line 35).
#[test]
fn lvm_segments_that_continue_one_another_are_one_record() {
    let text = std::fs::read_to_string(repo_path(
        "data/realdata/dialects/lvm_read/short_new_line_end.lvm",
    ))
    .unwrap();
    let text = format!("{}\n", text.trim_end());
    let cut = text.find("***End_of_Header***\t\n").unwrap() + "***End_of_Header***\t\n".len();
    let (file_header, segment) = text.split_at(cut);
    let dir = crate::common::temp_dir("formats-lvm-segments");
    let read = |name: &str, second: &str| {
        let p = dir.join(name);
        std::fs::write(&p, format!("{file_header}{segment}{second}")).unwrap();
        read_log(&p, &IngestOptions::default()).map_err(|e| e.to_string())
    };
    let clock = "09:51:40,7271890640258789063";
    let by_clock = segment.replace(clock, "09:51:40,7275796890258789063");
    let zero = "X0\t0,0000000000000000E+0\t0,0000000000000000E+0";
    let by_x0 = segment.replace(zero, "X0\t3,9062500000000000E-4\t3,9062500000000000E-4");
    let single = read("one.lvm", "").unwrap();
    for (name, second) in [("clock.lvm", &by_clock), ("x0.lvm", &by_x0)] {
        let log = read(name, second).unwrap();
        assert_eq!(log.info.samples, 20, "{name}");
        assert_eq!(log.info.fs_hz, 25600.0);
        let twice: Vec<f64> = single.data[0]
            .iter()
            .chain(&single.data[0])
            .copied()
            .collect();
        assert_eq!(log.data[0], twice, "{name}");
        assert!(
            log.info
                .ingest
                .notes
                .iter()
                .any(|n| n.contains("2 segments joined"))
        );
    }
    let late = segment.replace(clock, "09:51:41,7271890640258789063");
    let e = read("gap.lvm", &late).unwrap_err();
    assert!(
        e.contains("line 35")
            && e.contains("segment 2 does not start where segment 1 ends")
            && e.contains("by the header clock +0.999609 s"),
        "{e}"
    );
    let other = segment.replace("Response (Trigger)", "Response 2");
    let e = read("other.lvm", &other).unwrap_err();
    assert!(e.contains("line 35") && e.contains("other columns"), "{e}");
}

/// The 4-sample LabVIEW file from the command line: `srs` reads it at the rate of its header
/// (Delta_X 0.000250 s = 4000 Hz) and names its channels; `psd` refuses it, since no Welch
/// segment of the 16-sample minimum fits in 4 samples, naming the count.
#[test]
fn lvm_from_the_command_line_is_read_by_its_header() {
    let p = repo_path("data/realdata/dialects/lvm_read/no_decimal_separator.lvm");
    let path = p.to_str().unwrap();
    let (code, out, err) = run_text(&["srs", path, "--fmax", "1000", "--json"], None);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!((v["fs_hz"].as_f64().unwrap() - 4000.0).abs() < 1e-9);
    let names = crate::common::channel_names(&v);
    assert_eq!(names, ["ax", "ay", "az"]);
    // The reader's decisions, in the JSON and on stderr: tab-separated, the header states no
    // decimal separator so the point is taken, time from the X column.
    assert_eq!(v["ingest"]["delimiter"], "tab");
    assert_eq!(v["ingest"]["decimal"], ".");
    assert_eq!(v["ingest"]["time_column"], "X_Value");
    assert!(err.contains("LabVIEW .lvm"), "{err}");
    let (code, _, err) = run_text(&["psd", path, "--json"], None);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("has 4 samples, fewer than the 16") && err.contains("channel `ax"),
        "{err}"
    );
}

#[test]
fn mat_struct_of_vectors_with_a_time_vector() {
    // data/format-refs/lab_struct_v7.mat (scipy.io.savemat, compressed): run.t at 2048 Hz,
    // run.accel_g = 2 sin(2π·100 t), run.force_N = 5 cos(2π·50 t), run.operator text.
    let p = repo_path("data/format-refs/lab_struct_v7.mat");
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    let names: Vec<&str> = log.info.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["run.accel_g", "run.force_N"]);
    assert_eq!(log.info.channels[0].unit, Unit::G);
    assert_eq!(log.info.time_column.as_deref(), Some("run.t"));
    // 2047 steps of 1/2048 s span 2047/2048 s: the rate to rounding of the times.
    assert!((log.info.fs_hz - 2048.0).abs() < 1e-9, "{}", log.info.fs_hz);
    // Whole periods: RMS of A sin is A/√2 (to the summation error of 2048 terms).
    assert!((rms(&log.data[0]) - 2f64.sqrt()).abs() < 1e-12);
    assert!((rms(&log.data[1]) - 5.0 / 2f64.sqrt()).abs() < 1e-12);
    assert!(
        log.info
            .ingest
            .ignored_columns
            .iter()
            .any(|c| c.contains("run.operator"))
    );
}

#[test]
fn mat_vectors_with_a_rate_scalar_and_fs_checks() {
    // data/format-refs/lab_vectors_v6.mat (uncompressed): fs = 2048, accel_g 2048x1, force_N
    // 1x2048.
    let p = repo_path("data/format-refs/lab_vectors_v6.mat");
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.info.fs_hz, 2048.0);
    assert_eq!(log.info.channels.len(), 2);
    let opts = |fs: f64, over: bool| IngestOptions {
        fs: Some(fs),
        fs_override: over,
        ..IngestOptions::default()
    };
    let e = read_log(&p, &opts(2000.0, false)).unwrap_err().to_string();
    assert!(
        e.contains("2000") && e.contains("variable `fs`") && e.contains("--fs-override"),
        "{e}"
    );
    assert_eq!(
        read_log(&p, &opts(2000.0, true)).unwrap().info.fs_hz,
        2000.0
    );
    // Within 0.1%: --fs is taken.
    assert_eq!(
        read_log(&p, &opts(2049.0, false)).unwrap().info.fs_hz,
        2049.0
    );
}

/// One Level 4 matrix as `save -v4` and `scipy.io.savemat(format='4')` write it (MathWorks,
/// "MAT-File Format", Level 4): MOPT, mrows, ncols, imagf, namlen as 32-bit integers in the
/// byte order MOPT's M digit names, the name with its NUL, the values column by column.
fn mat4_matrix(
    big: bool,
    mopt: i32,
    dims: (i32, i32),
    imagf: i32,
    name: &str,
    data: &[u8],
) -> Vec<u8> {
    let int = |v: i32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let mut out = Vec::new();
    for v in [mopt, dims.0, dims.1, imagf, name.len() as i32 + 1] {
        out.extend(int(v));
    }
    out.extend(name.as_bytes());
    out.push(0);
    out.extend(data);
    out
}

/// A lab's `save log.mat fs acc_g units -v4`: `fs` 1000 (1x1 double), `acc_g` a 2 g, 50 Hz
/// sine over 1 s (1x1000), `units` the text 'g' (MOPT 51, as scipy writes text). Read as a
/// level 5 file is: the vector is the channel, `fs` the rate, the text listed as not read.
/// Doubles: RMS 2/√2 to the summation error of 1000 terms (1e-12); the big-endian single
/// precision file (MOPT 1010) to f32's 24-bit significand (6e-8 relative, 1e-7 taken).
#[test]
fn mat_level_4_files_read_like_level_5() {
    let n: i32 = 1000;
    let sine: Vec<f64> = (0..n)
        .map(|i| 2.0 * (2.0 * std::f64::consts::PI * 50.0 * i as f64 / 1000.0).sin())
        .collect();
    let dir = crate::common::temp_dir("formats-mat4");
    let le = |v: &[f64]| -> Vec<u8> { v.iter().flat_map(|x| x.to_le_bytes()).collect() };
    let mut file = mat4_matrix(false, 0, (1, 1), 0, "fs", &le(&[1000.0]));
    file.extend(mat4_matrix(false, 0, (1, n), 0, "acc_g", &le(&sine)));
    file.extend(mat4_matrix(false, 51, (1, 1), 0, "units", b"g"));
    let p = dir.join("le.mat");
    std::fs::write(&p, &file).unwrap();
    assert_eq!(satqual::signal::formats::detect(&p), LogFormat::Mat);
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.info.fs_hz, 1000.0);
    assert_eq!(log.info.channels[0].name, "acc_g");
    assert_eq!(log.info.channels[0].unit, Unit::G);
    let want = 2.0 / 2f64.sqrt();
    assert!(
        (rms(&log.data[0]) - want).abs() < 1e-12,
        "{}",
        rms(&log.data[0])
    );
    let ignored = log.info.ingest.ignored_columns.join("; ");
    assert!(
        ignored.contains("`units` (text matrix (MOPT type 1))"),
        "{ignored}"
    );
    // Big-endian single precision, the channel a column (1000x1), the rate from `--fs`.
    let be: Vec<u8> = sine
        .iter()
        .flat_map(|x| (*x as f32).to_be_bytes())
        .collect();
    let p = dir.join("be.mat");
    std::fs::write(&p, mat4_matrix(true, 1010, (n, 1), 0, "acc_g", &be)).unwrap();
    let fs = IngestOptions {
        fs: Some(1000.0),
        ..IngestOptions::default()
    };
    let log = read_log(&p, &fs).unwrap();
    assert!(
        (rms(&log.data[0]) - want).abs() < 1e-7 * want,
        "{}",
        rms(&log.data[0])
    );
    // A complex matrix alone: nothing to read, and the message says why.
    let p = dir.join("complex.mat");
    std::fs::write(
        &p,
        mat4_matrix(false, 0, (1, 2), 1, "z", &le(&[1.0, 2.0, 3.0, 4.0])),
    )
    .unwrap();
    let e = read_log(&p, &fs).unwrap_err().to_string();
    assert!(
        e.contains("complex.mat: no channel to read")
            && e.contains("`z` (complex matrix (imagf 1)"),
        "{e}"
    );
    // Cut inside the values of `acc_g`: an error naming the matrix, never a short channel.
    let p = dir.join("cut.mat");
    std::fs::write(&p, &file[..file.len() - 100]).unwrap();
    let e = read_log(&p, &fs).unwrap_err().to_string();
    // `fs` takes 20 + 3 + 8 = 31 bytes; the cut takes the 27 of `units` and 73 of `acc_g`.
    assert!(
        e.contains(
            "cut.mat: MATLAB level 4 MAT-file: matrix 2 (byte 31): `acc_g` (1x1000) needs 8000 \
             bytes of values, but the file ends 7927 bytes after its name"
        ),
        "{e}"
    );
}

#[test]
fn mat_files_matlab_wrote_are_read_or_refused_by_name() {
    let d = |f: &str| repo_path(&format!("data/realdata/scipy-matlab/{f}"));
    let fs = IngestOptions {
        fs: Some(100.0),
        ..IngestOptions::default()
    };
    let log = read_log(&d("testmulti_7.4_GLNX86.mat"), &fs).unwrap();
    let names: Vec<&str> = log.info.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["a(1,:)", "a(2,:)", "a(3,:)"]);
    assert!(
        log.info
            .ingest
            .ignored_columns
            .iter()
            .any(|c| c.contains("`theta` (9 samples"))
    );
    let log = read_log(&d("big_endian.mat"), &fs).unwrap();
    assert_eq!(
        log.data[1],
        [3.0, 4.0],
        "scipy.io.loadmat: floats = [[2, 3], [3, 4]]"
    );
    let e = read_log(&d("testhdf5_7.4_GLNX86.mat"), &fs)
        .unwrap_err()
        .to_string();
    assert!(e.contains("v7.3") && e.contains("-v7"), "{e}");
    let e = read_log(&d("corrupted_zlib_data.mat"), &fs)
        .unwrap_err()
        .to_string();
    assert!(e.contains("variable 3") && e.contains("inflate"), "{e}");
    let e = read_log(&d("testdouble_7.4_GLNX86.mat"), &IngestOptions::default()).unwrap_err();
    assert!(e.to_string().contains("no --fs"), "{e}");
    // Every truncation and every single-byte change of a MAT-file ends in a log or an error.
    for f in [
        "teststruct_7.4_GLNX86.mat",
        "big_endian.mat",
        "testmatrix_6.5.1_GLNX86.mat",
    ] {
        let bytes = std::fs::read(d(f)).unwrap();
        for n in 0..bytes.len() {
            let _ = satqual::signal::formats::mat::read_mat(Path::new(f), &bytes[..n]);
            let mut b = bytes.clone();
            b[n] ^= 0xa5;
            let _ = satqual::signal::formats::mat::read_mat(Path::new(f), &b);
        }
    }
}

/// A 2 g, 100 Hz sine at 1 kHz for 4 s, each row's time an ISO 8601 date-time written by
/// `stamp(k)` for sample k, the value by `value(v)`, the fields joined by `sep`.
fn iso_log(
    name: &str,
    header: &str,
    sep: &str,
    stamp: impl Fn(usize) -> String,
    value: impl Fn(f64) -> String,
) -> std::path::PathBuf {
    let mut s = format!("{header}\n");
    for k in 0..4000 {
        let v = 2.0 * (2.0 * std::f64::consts::PI * 100.0 * k as f64 / 1000.0).sin();
        s.push_str(&format!("{}{sep}{}\n", stamp(k), value(v)));
    }
    let p = crate::common::temp_dir(&format!("formats-{name}")).join(name);
    std::fs::write(&p, s).unwrap();
    p
}

/// Across 2024-02-29 23:59:58 to 2024-03-01 00:00:02 (a leap day and a month end).
fn leap_stamp(k: usize, sep: char, frac: char, zone: &str) -> String {
    let (s, ms) = (k / 1000, k % 1000);
    if s < 2 {
        format!("2024-02-29{sep}23:59:{:02}{frac}{ms:03}{zone}", 58 + s)
    } else {
        format!("2024-03-01{sep}00:00:{:02}{frac}{ms:03}{zone}", s - 2)
    }
}

#[test]
fn iso8601_time_columns_give_the_rate() {
    let p = iso_log(
        "iso.csv",
        "timestamp,accel_g",
        ",",
        |k| leap_stamp(k, 'T', '.', ""),
        |v| format!("{v:.12}"),
    );
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.info.ingest.time_unit.map(|u| u.name()), Some("iso8601"));
    // 1 ms steps across the day and month change: 1000 Hz to rounding of the fractions.
    assert!((log.info.fs_hz - 1000.0).abs() < 1e-9, "{}", log.info.fs_hz);
    // 400 whole periods of 2 sin: RMS 2/√2 to the 12 written decimals.
    assert!((rms(&log.data[0]) - 2f64.sqrt()).abs() < 1e-11);
    // Semicolons, decimal commas, a blank between date and time, a zone, a name that is not
    // a time word: the cells say it is time.
    let p = iso_log(
        "iso-semi.csv",
        "Zeit;Beschleunigung_g",
        ";",
        |k| leap_stamp(k, ' ', ',', "+01:00"),
        |v| format!("{v:.12}").replace('.', ","),
    );
    let log = read_log(&p, &IngestOptions::default()).unwrap();
    assert_eq!(log.info.time_column.as_deref(), Some("Zeit"));
    assert_eq!(log.info.ingest.decimal, ",");
    assert!((log.info.fs_hz - 1000.0).abs() < 1e-9);
    assert!((rms(&log.data[0]) - 2f64.sqrt()).abs() < 1e-11);
    // --fs that disagrees with the date-times is refused as for numeric times.
    let opts = IngestOptions {
        fs: Some(1010.0),
        ..IngestOptions::default()
    };
    let e = read_log(&p, &opts).unwrap_err().to_string();
    assert!(e.contains("1010") && e.contains("--fs-override"), "{e}");
}

#[test]
fn iso8601_bad_or_irregular_rows_are_located() {
    let p = iso_log(
        "iso-bad.csv",
        "time,accel_g",
        ",",
        |k| {
            if k == 1500 {
                "2024-02-30T00:00:00".into()
            } else {
                leap_stamp(k, 'T', '.', "Z")
            }
        },
        |v| format!("{v:.6}"),
    );
    let e = read_log(&p, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    // Sample 1500 is line 1502 (header on line 1); 30 February is no date.
    assert!(
        e.contains("line 1502") && e.contains("`time`") && e.contains("2024-02-30"),
        "{e}"
    );
    let p = iso_log(
        "iso-gap.csv",
        "time,accel_g",
        ",",
        |k| leap_stamp(if k >= 2500 { k + 7 } else { k }, 'T', '.', "Z"),
        |v| format!("{v:.6}"),
    );
    let e = read_log(&p, &IngestOptions::default())
        .unwrap_err()
        .to_string();
    // An 8 ms step after sample 2499: line 2502.
    assert!(e.contains("line 2502") && e.contains("0.008"), "{e}");
}
