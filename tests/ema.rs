//! Experimental modal analysis: the LSCF/LSFD identification against an analytic 3-DOF system,
//! against sdypy-EMA's LSCF on the repository's impact logs, and the `ema` command's outputs and
//! errors.

use crate::common::{rel, run_text, temp_dir};
use realfft::num_complex::Complex64;
use satqual::catalogue::analytic::three_dof;
use satqual::signal::PeakOptions;
use satqual::signal::ema::{Criteria, EmaOptions, FrfForm, Method, identify, indicators::mac};
use serde_json::Value;

fn options(method: Method) -> EmaOptions {
    EmaOptions {
        f_lo: 5.0,
        f_hi: 200.0,
        method,
        order_max: 40,
        order_max_is_default: false,
        form: FrfForm::Accelerance,
        criteria: Criteria::default(),
        peaks: PeakOptions::default(),
    }
}

/// The identified modes against the analytic ones: worst relative frequency and damping
/// errors and the smallest MAC against the mass-normalised shapes.
fn errors(m: &satqual::signal::ema::EmaModel) -> (f64, f64, f64) {
    let sys = three_dof();
    assert_eq!(m.modes.len(), 3, "{:#?}", m.modes);
    let (mut df, mut dz, mut mac_min) = (0.0f64, 0.0f64, 1.0f64);
    for (r, mode) in m.modes.iter().enumerate() {
        df = df.max(rel(mode.frequency_hz, sys.frequencies_hz[r]));
        dz = dz.max(rel(mode.damping_ratio, sys.damping[r]));
        let shape: Vec<Complex64> = mode
            .shape
            .iter()
            .map(|s| Complex64::new(s.re, s.im))
            .collect();
        let want: Vec<Complex64> = sys.shapes[r]
            .iter()
            .map(|&v| Complex64::new(v, 0.0))
            .collect();
        mac_min = mac_min.min(mac(&shape, &want));
        assert!(mode.mpc > 0.99 && mode.mpd < 5.0, "{mode:?}");
    }
    (df, dz, mac_min)
}

#[test]
fn ema_lscf_recovers_three_dof_without_noise() {
    // Reference: the analytic 3-DOF (catalogue::analytic::three_dof), whose accelerance is an
    // exact sum of three modal terms. Measured: frequency 4e-10, damping 5e-8, MAC 1 - 2e-16;
    // the tolerances leave the rounding of order-40 normal equations room.
    let m = identify(&three_dof().frf_set(0.0), &options(Method::Lscf)).unwrap();
    let (df, dz, mac_min) = errors(&m);
    assert!(df < 1e-7, "frequency error {df:e}");
    assert!(dz < 1e-5, "damping error {dz:e}");
    assert!(mac_min > 1.0 - 1e-9, "MAC {mac_min}");
    // The LSFD rebuild equals the measured FRF where the model is exact.
    let rec = m.reconstructed.as_ref().unwrap();
    let mut worst = 0.0f64;
    for (meas, rebuilt) in m.measured.iter().zip(rec) {
        for (a, b) in meas.iter().zip(rebuilt) {
            worst = worst.max((a - b).norm() / a.norm());
        }
    }
    eprintln!("noise-free 3-DOF: df {df:e} dz {dz:e} mac {mac_min} rebuild {worst:e}");
    // Measured 1.5e-6: the rebuild carries the 5e-8 damping error of the poles.
    assert!(worst < 1e-5, "LSFD rebuild off by {worst:e} of |H|");
}

#[test]
fn ema_lscf_recovers_three_dof_with_two_percent_noise() {
    // Same system, each line perturbed by uniform complex noise of up to ±2 % of |H| (seeded).
    // Measured: frequency 1.0e-4, damping 1.4 %, MAC 0.999993. Tolerances: 0.1 % in frequency and
    // 5 % in damping, the stabilization criteria's own thresholds.
    let m = identify(&three_dof().frf_set(0.02), &options(Method::Lscf)).unwrap();
    let (df, dz, mac_min) = errors(&m);
    eprintln!("noisy 3-DOF: df {df:e} dz {dz:e} mac {mac_min}");
    assert!(df < 1e-3, "frequency error {df:e}");
    assert!(dz < 0.05, "damping error {dz:e}");
    assert!(mac_min > 0.999, "MAC {mac_min}");
}

#[test]
fn ema_peak_method_reads_three_dof_with_half_power_damping() {
    // Half-power bandwidth on 0.25 Hz lines: the 1 % mode at 23 Hz spans under two lines, so
    // peak picking is coarse. Tolerances: frequency within one line (0.25 Hz), damping within
    // 25 % (the bandwidth of the 1 % mode is 0.46 Hz, read by linear interpolation).
    let sys = three_dof();
    let m = identify(&three_dof().frf_set(0.0), &options(Method::Peak)).unwrap();
    assert_eq!(m.modes.len(), 3, "{:#?}", m.modes);
    for (r, mode) in m.modes.iter().enumerate() {
        assert!(
            (mode.frequency_hz - sys.frequencies_hz[r]).abs() < 0.25,
            "{mode:?}"
        );
        assert!(rel(mode.damping_ratio, sys.damping[r]) < 0.25, "{mode:?}");
    }
    // A half-power band under 3 lines is noted (signal::peaks::MIN_HALF_POWER_LINES): every
    // mode whose exact band 2ζ·fn spans under 2 lines has a note, none over 4 lines has one
    // (the margin covers the 25 % the coarse reading may miss by).
    let noted = |f: f64| {
        m.notes
            .iter()
            .any(|n| n.contains("half-power band") && n.contains(&format!("peak at {f:.3} Hz")))
    };
    for (r, mode) in m.modes.iter().enumerate() {
        let lines = 2.0 * sys.damping[r] * sys.frequencies_hz[r] / 0.25;
        if lines < 2.0 {
            assert!(noted(mode.frequency_hz), "{lines} lines: {:?}", m.notes);
        } else if lines > 4.0 {
            assert!(!noted(mode.frequency_hz), "{lines} lines: {:?}", m.notes);
        }
    }
}

const IMPACT_ARGS: [&str; 14] = [
    "ema",
    "data/realdata/pyfrf-impact/impact_1.csv",
    "data/realdata/pyfrf-impact/impact_2.csv",
    "data/realdata/pyfrf-impact/impact_3.csv",
    "data/realdata/pyfrf-impact/impact_4.csv",
    "data/realdata/pyfrf-impact/impact_5.csv",
    "--input=force",
    "--output=acceleration",
    "--nperseg=25600",
    "--window=boxcar",
    "--fmin=50",
    "--fmax=6400",
    "--order-max=100",
    "--json",
];

fn impact_ema(extra: &[&str]) -> (Value, String) {
    let mut args = IMPACT_ARGS.to_vec();
    args.extend_from_slice(extra);
    let (code, out, err) = run_text(&args, None);
    assert_eq!(code, 0, "{err}");
    (serde_json::from_str(&out).unwrap(), out)
}

fn reference() -> Value {
    let text = std::fs::read_to_string("data/ema-refs/pyfrf-impact-sdypy.json").unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The dominant H1 peaks of data/realdata/pyfrf-impact/SOURCE.md (900, 2640, 3669, 4128,
/// 4392, 5969 Hz) are all among the modes, each within 0.2%.
fn assert_dominant_peaks_found(modes: &[Value]) {
    for f in [900.0, 2640.0, 3669.0, 4128.0, 4392.0, 5969.0] {
        assert!(
            modes
                .iter()
                .any(|m| rel(m["frequency_hz"].as_f64().unwrap(), f) < 2e-3),
            "no mode near {f} Hz: {modes:?}"
        );
    }
}

#[test]
fn ema_impact_logs_match_sdypy_lscf_pole_for_pole() {
    // Reference: data/ema-refs/pyfrf-impact-sdypy.json, `same_order` (sdypy-EMA 0.31.0's LSCF
    // on the FRFs `--export-frf` writes, made by data/ema-refs/sdypy_lscf.py): sdypy's pole of
    // the model order satqual chose, nearest in frequency. Tolerances of the acceptance:
    // frequency 0.1 %, damping 10 %. Measured: 9e-11 and 1.3e-8 at worst (the same normal
    // equations, solved by other libraries).
    let (ours, _) = impact_ema(&[]);
    let refs = reference();
    let modes = ours["modes"].as_array().unwrap();
    let same = refs["same_order"].as_array().unwrap();
    // The dominant H1 peaks of data/realdata/pyfrf-impact/SOURCE.md (900, 2640, 3669, 4128,
    // 4392, 5969 Hz) are all among the modes: the comparison is not over an empty set.
    assert_dominant_peaks_found(modes);
    assert_eq!(modes.len(), same.len());
    for (m, r) in modes.iter().zip(same) {
        assert_eq!(m["order"], r["order"]);
        let (f, fr) = (
            m["frequency_hz"].as_f64().unwrap(),
            r["frequency_hz"].as_f64().unwrap(),
        );
        let (z, zr) = (
            m["damping_ratio"].as_f64().unwrap(),
            r["damping_ratio"].as_f64().unwrap(),
        );
        assert!(rel(f, fr) < 1e-3, "{f} Hz against sdypy {fr} Hz");
        assert!(rel(z, zr) < 0.1, "ζ {z} against sdypy {zr} at {f} Hz");
    }
}

/// Without Welch flags `ema` detects the hammer input as `frf` does and uses the impact
/// options (one force-windowed boxcar segment per hit; these records have decayed, so no
/// exponential window). Default Welch segments on these 1 s records find no stable pole at
/// all. Reference: the dominant H1 peaks of data/realdata/pyfrf-impact/SOURCE.md, each within
/// 0.2% (the tolerance of the sdypy comparison above).
#[test]
fn ema_on_hammer_logs_uses_the_impact_options_by_default() {
    let args: Vec<&str> = IMPACT_ARGS
        .iter()
        .copied()
        .filter(|a| !a.starts_with("--nperseg") && !a.starts_with("--window"))
        .collect();
    let (code, out, err) = run_text(&args, None);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let w = &v["impact_windows"];
    assert_eq!(w["segment_samples"], 25600, "{w}");
    assert_eq!(w["force_window"], true);
    assert!(w["exponential_tau_s"].is_null());
    assert_eq!(v["window"], "boxcar");
    let modes = v["modes"].as_array().unwrap();
    assert_dominant_peaks_found(modes);
}

#[test]
fn ema_impact_frequencies_match_sdypy_own_selection() {
    // Reference: the same file, `sdypy_selection` (sdypy's select_closest_poles seeded with our
    // frequencies: its stable pole nearest each, of whatever order). Frequency within 0.1 %
    // (measured 0.018 % at worst, the 810 Hz mode). The damping is NOT compared here: the two
    // selections take the pole from different model orders, and for these modes (ζ of 0.02 to
    // 0.2 %, a half-power band of 0.3 to 2.5 lines at 1 Hz) ζ moves by up to 36 % from one
    // stable order to another (810 Hz: 0.00141 against 0.00089); docs/signal.md states it.
    let (ours, _) = impact_ema(&[]);
    let refs = reference();
    let modes = ours["modes"].as_array().unwrap();
    let sel = refs["sdypy_selection"].as_array().unwrap();
    assert_eq!(modes.len(), sel.len());
    for (m, r) in modes.iter().zip(sel) {
        let (f, fr) = (
            m["frequency_hz"].as_f64().unwrap(),
            r["frequency_hz"].as_f64().unwrap(),
        );
        assert!(
            rel(f, fr) < 1e-3,
            "{f} Hz against sdypy's selection {fr} Hz"
        );
    }
}

#[test]
fn ema_cli_is_deterministic_and_writes_its_figures() {
    let dir = temp_dir("ema-figures");
    let out = dir.to_str().unwrap();
    let frf = dir.join("frf.csv");
    let (a, text_a) = impact_ema(&["--out", out, "--export-frf", frf.to_str().unwrap()]);
    let (_, text_b) = impact_ema(&[]);
    assert_eq!(text_a, text_b, "same input, different JSON");
    for f in ["stabilization.svg", "reconstruction.svg"] {
        let svg = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("</svg>") && !svg.contains("NaN"),
            "{f}"
        );
    }
    let csv = std::fs::read_to_string(&frf).unwrap();
    assert!(csv.starts_with("frequency_hz,acceleration_re,acceleration_im\n"));
    // 25600-sample segments: lines 0..=12800.
    assert_eq!(csv.lines().count(), 1 + 12801);
    let m0 = &a["modes"][0];
    assert_eq!(m0["shape"][0]["channel"], "acceleration");
    assert_eq!(m0["shape"][0]["re"], 1.0);
    assert_eq!(a["method"], "lscf");
    assert_eq!(
        a["band_hz"][1].as_f64().map(|f| (f - 6400.0).abs() < 0.01),
        Some(true)
    );
}

#[test]
fn ema_peak_method_on_impact_logs() {
    // `--method peak`: the same dominant resonances, with half-power damping.
    let (ours, _) = impact_ema(&["--method=peak"]);
    assert_eq!(ours["method"], "peak");
    let modes = ours["modes"].as_array().unwrap();
    assert!(!modes.is_empty());
    for m in modes {
        let z = m["damping_ratio"].as_f64().unwrap();
        assert!(z > 0.0 && z < 0.2, "{m}");
    }
}

#[test]
fn ema_bad_inputs_are_located_errors() {
    let cases: [(&[&str], &str); 5] = [
        (&["--order-max=7"], "order-max"),
        (&["--order-max=100000"], "order-max"),
        (&["--method=svd"], "--method `svd`"),
        (&["--frf-form=strain"], "--frf-form `strain`"),
        (&["--output=nope"], "no channel named `nope`"),
    ];
    for (extra, want) in cases {
        let mut args = IMPACT_ARGS.to_vec();
        args.extend_from_slice(extra);
        let (code, _, err) = run_text(&args, None);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert!(err.contains(want), "{extra:?}: {err}");
    }
    // A band with fewer lines than the order asks.
    let mut args: Vec<&str> = IMPACT_ARGS
        .iter()
        .copied()
        .filter(|a| !a.starts_with("--fm"))
        .collect();
    args.extend_from_slice(&["--fmin=100", "--fmax=120"]);
    let (code, _, err) = run_text(&args, None);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("fewer than order + 2"), "{err}");
}

#[test]
fn ema_write_damping_edits_the_scene_and_keeps_its_comments() {
    let dir = temp_dir("ema-write-damping");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("shaker.toml");
    let original = std::fs::read_to_string("test-specs/shaker-2sat.toml").unwrap();
    std::fs::write(&scene, &original).unwrap();
    let (ours, _) = impact_ema(&["--write-damping", scene.to_str().unwrap()]);
    let edited = std::fs::read_to_string(&scene).unwrap();
    // Every comment line of the original survives.
    for line in original.lines().filter(|l| l.trim_start().starts_with('#')) {
        assert!(edited.contains(line), "lost comment {line:?}");
    }
    assert!(edited.contains(
        "# replaced by `satqual ema --write-damping`: table = [[29.1, 0.03319], [31.2, 0.03505]"
    ));
    let loaded = satqual::spec::Scene::parse(&scene, &edited).unwrap();
    let d = loaded.file.damping.unwrap();
    let table = d.table.unwrap();
    let modes = ours["modes"].as_array().unwrap();
    assert_eq!(table.len(), modes.len());
    for (p, m) in table.iter().zip(modes) {
        // Written to 4 decimals in f and 6 in ζ.
        assert!((p[0] - m["frequency_hz"].as_f64().unwrap()).abs() <= 5e-5);
        assert!((p[1] - m["damping_ratio"].as_f64().unwrap()).abs() <= 5e-7);
    }
    assert_eq!(d.q, None);
    assert_eq!(
        edited.matches("# satqual ema --method lscf").count(),
        modes.len()
    );
}
