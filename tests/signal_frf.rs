//! H1, coherence and resonance picking on measured impact-hammer data
//! (data/realdata/pyfrf-impact, 5 hits, fs = 25600 Hz, 1 s records; see its SOURCE.md).
//! SOURCE.md anchors (no windows, 5 linear averages, H1 = ΣX*Y/Σ|X|²): dominant H1 peaks near
//! 900, 2640, 3669/3690, 4128/4164, 4392, 5969 Hz; median coherence 0.999 over 20–2000 Hz.

use satqual::signal::{
    Detrend, IngestOptions, PeakOptions, WelchOptions, Window, frf, read_csv, resonances,
};
use std::path::PathBuf;

fn dir() -> PathBuf {
    crate::common::repo_path(satqual::catalogue::logs::IMPACT_DIR)
}

#[test]
fn impact_h1_finds_the_source_md_peaks_with_high_coherence() {
    let logs: Vec<_> = (1..=5)
        .map(|i| {
            read_csv(
                &dir().join(format!("impact_{i}.csv")),
                &IngestOptions::default(),
            )
            .unwrap()
        })
        .collect();
    // The time column (%.8f) gives fs; SOURCE.md states 25600 Hz. 1e-6 relative: rounding of
    // the printed times over a 1 s span.
    let fs = logs[0].info.fs_hz;
    assert!((fs - 25600.0).abs() < 25600.0 * 1e-6, "{fs}");
    let records: Vec<(&[f64], &[f64])> = logs
        .iter()
        .map(|l| {
            (
                l.channel("force").unwrap(),
                l.channel("acceleration").unwrap(),
            )
        })
        .collect();
    // One segment per hit, no window, no detrend: the averaging SOURCE.md describes.
    let opts = WelchOptions {
        nperseg: 25600,
        overlap: 0.0,
        window: Window::Boxcar,
        detrend: Detrend::None,
    };
    let h = frf(&records, 25600.0, &opts).unwrap();
    assert_eq!(h.segments, 5);
    let f = h.frequencies();
    let coh = h.coherence();
    let res = resonances(
        &f,
        &h.h1(),
        &coh,
        &PeakOptions {
            max_peaks: 10,
            f_min_hz: 20.0,
            ..Default::default()
        },
    );
    for r in &res {
        eprintln!(
            "{:8.1} Hz  |H1| {:9.3}  Q {:?}  coherence {:.5}",
            r.frequency_hz, r.magnitude, r.q, r.coherence
        );
    }
    for target in [900.0, 2640.0, 5969.0] {
        // "near": within 1% of the SOURCE.md frequency, which is given to the nearest line.
        let r = res
            .iter()
            .find(|r| (r.frequency_hz - target).abs() < 0.01 * target);
        let r = r.unwrap_or_else(|| panic!("no resonance near {target} Hz in {res:?}"));
        assert!(
            r.coherence > 0.99,
            "coherence {} at {}",
            r.coherence,
            r.frequency_hz
        );
        assert!(r.q.is_some_and(|q| q > 1.0), "{r:?}");
    }
    let mut band: Vec<f64> = f
        .iter()
        .zip(&coh)
        .filter(|(f, _)| (20.0..=2000.0).contains(*f))
        .map(|(_, c)| *c)
        .collect();
    band.sort_by(|a, b| a.total_cmp(b));
    let median = band[band.len() / 2];
    eprintln!("median coherence 20-2000 Hz: {median:.5}");
    // SOURCE.md: 0.999; three decimals as stated.
    assert!((median - 0.999).abs() < 0.0005, "{median}");
}

#[test]
fn the_same_channel_as_input_and_output_is_an_error_naming_it() {
    let log = dir().join("impact_1.csv");
    let (code, out, err) = crate::common::run_text(
        &[
            "frf",
            log.to_str().unwrap(),
            "--input",
            "force",
            "--output",
            "force",
        ],
        None,
    );
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("`force`") && err.contains("both --input and --output"),
        "{err}"
    );
}
