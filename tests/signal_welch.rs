//! Welch PSD, CSD and coherence against scipy.signal on the same data and parameters.
//! Reference: data/signal-refs/welch_refs.json, made by `python3 data/signal-refs/make_refs.py`
//! (scipy 1.17). Tolerance: 1e-9 relative per line (the acceptance
//! limit against scipy), on every line whose reference is
//! above 1e-12 of the spectrum maximum; lines below that are rounding residue (e.g. the DC line
//! after mean removal, ~1e-30) and are checked in absolute terms against 1e-12·max instead.

use satqual::signal::{Detrend, WelchOptions, Window, csd, welch};
use serde_json::Value;

fn refs() -> Value {
    let s = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/signal-refs/welch_refs.json"
    ))
    .expect("reference file");
    serde_json::from_str(&s).expect("reference json")
}

fn vec(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Max relative error over significant lines; panics if an insignificant line is off by more
/// than 1e-12 of the maximum.
fn max_rel(got: &[f64], want: &[f64]) -> f64 {
    assert_eq!(got.len(), want.len());
    let peak = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (g, w) in got.iter().zip(want) {
        if w.abs() > 1e-12 * peak {
            worst = worst.max((g - w).abs() / w.abs());
        } else {
            assert!((g - w).abs() <= 1e-12 * peak, "residue line: {g} vs {w}");
        }
    }
    worst
}

fn opts(case: &Value) -> WelchOptions {
    WelchOptions {
        nperseg: case["nperseg"].as_u64().unwrap() as usize,
        overlap: case["overlap"].as_f64().unwrap(),
        window: Window::parse(case["window"].as_str().unwrap()).unwrap(),
        detrend: Detrend::parse(case["detrend"].as_str().unwrap()).unwrap(),
    }
}

#[test]
fn welch_matches_scipy_to_1e9() {
    let r = refs();
    let fs = r["fs"].as_f64().unwrap();
    let x = vec(&r["x"]);
    let mut overall = 0.0f64;
    for case in r["welch"].as_array().unwrap() {
        let o = opts(case);
        assert_eq!(o.noverlap() as u64, case["noverlap"].as_u64().unwrap());
        let p = welch(&x, fs, &o).unwrap();
        let f = vec(&case["f"]);
        let fr = p.frequencies();
        assert_eq!(fr.len(), f.len());
        for (a, b) in fr.iter().zip(&f) {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "frequency {a} vs {b}"
            );
        }
        let e = max_rel(&p.values, &vec(&case["pxx"]));
        eprintln!(
            "welch {} {} nperseg={} overlap={}: max rel err {e:.3e}",
            o.window.name(),
            o.detrend.name(),
            o.nperseg,
            o.overlap
        );
        assert!(e < 1e-9, "{case:?}: {e}");
        overall = overall.max(e);
    }
    eprintln!("welch: worst relative error over all cases {overall:.3e}");
}

#[test]
fn csd_and_coherence_match_scipy_to_1e9() {
    let r = refs();
    let fs = r["fs"].as_f64().unwrap();
    let x = vec(&r["x"]);
    let y = vec(&r["y"]);
    for case in r["csd"].as_array().unwrap() {
        let o = opts(case);
        let (gxx, gyy, gxy) = csd(&x, &y, fs, &o).unwrap();
        let e_yy = max_rel(&gyy.values, &vec(&case["pyy"]));
        let re: Vec<f64> = gxy.values.iter().map(|z| z.re).collect();
        let im: Vec<f64> = gxy.values.iter().map(|z| z.im).collect();
        // Real and imaginary parts are compared against the |Gxy| scale: a part can cross zero,
        // where a per-part relative error means nothing.
        let mag: Vec<f64> = vec(&case["pxy_re"])
            .iter()
            .zip(vec(&case["pxy_im"]))
            .map(|(a, b)| a.hypot(b))
            .collect();
        let peak = mag.iter().fold(0.0f64, |m, v| m.max(*v));
        let mut e_xy = 0.0f64;
        for k in 0..mag.len() {
            if mag[k] > 1e-12 * peak {
                let d = (re[k] - vec(&case["pxy_re"])[k]).hypot(im[k] - vec(&case["pxy_im"])[k]);
                e_xy = e_xy.max(d / mag[k]);
            }
        }
        let coh: Vec<f64> = (0..gxx.values.len())
            .map(|k| gxy.values[k].norm_sqr() / (gxx.values[k] * gyy.values[k]))
            .collect();
        let want_coh = vec(&case["coh"]);
        // Coherence on the DC line after detrending is 0/0 residue in both tools: skip it there.
        let skip_dc = o.detrend != Detrend::None;
        let mut e_coh = 0.0f64;
        for k in usize::from(skip_dc)..coh.len() {
            e_coh = e_coh.max((coh[k] - want_coh[k]).abs() / want_coh[k].abs());
        }
        eprintln!(
            "csd {} {}: Gyy {e_yy:.2e}, Gxy {e_xy:.2e}, coherence {e_coh:.2e}",
            o.window.name(),
            o.detrend.name()
        );
        assert!(
            e_yy < 1e-9 && e_xy < 1e-9 && e_coh < 1e-9,
            "{e_yy} {e_xy} {e_coh}"
        );
    }
}

#[test]
fn nperseg_longer_than_signal_and_bad_overlap_are_errors() {
    let x = vec![0.0; 100];
    let o = WelchOptions {
        nperseg: 101,
        ..Default::default()
    };
    let e = welch(&x, 1.0, &o).unwrap_err().to_string();
    assert!(
        e.contains("nperseg = 101") && e.contains("100 samples"),
        "{e}"
    );
    for bad in [1.0, 1.5, -0.1, f64::NAN] {
        let o = WelchOptions {
            nperseg: 16,
            overlap: bad,
            ..Default::default()
        };
        let e = welch(&x, 1.0, &o).unwrap_err().to_string();
        assert!(e.contains("overlap"), "{e}");
    }
}

#[test]
fn h1_h2_coherence_are_consistent_with_the_scipy_spectra() {
    // H1 = Gxy/Gxx and H2 = Gyy/Gyx from the scipy reference spectra of the hann/constant case;
    // identity γ² = H1/H2 (both sides from the same spectra), 1e-12.
    let r = refs();
    let fs = r["fs"].as_f64().unwrap();
    let x = vec(&r["x"]);
    let y = vec(&r["y"]);
    let case = &r["csd"][0];
    let o = opts(case);
    let h = satqual::signal::frf(&[(&x, &y)], fs, &o).unwrap();
    let pxx = vec(&r["welch"][0]["pxx"]);
    let (re, im) = (vec(&case["pxy_re"]), vec(&case["pxy_im"]));
    let pyy = vec(&case["pyy"]);
    let (h1, h2, coh) = (h.h1(), h.h2(), h.coherence());
    for k in 1..pxx.len() {
        let want_h1 = realfft::num_complex::Complex64::new(re[k], im[k]) / pxx[k];
        let want_h2 = pyy[k] / realfft::num_complex::Complex64::new(re[k], -im[k]);
        // Ratios of spectra that each match scipy to ~1e-14: 1e-9 relative.
        assert!(
            (h1[k] - want_h1).norm() <= 1e-9 * want_h1.norm(),
            "H1 line {k}"
        );
        assert!(
            (h2[k] - want_h2).norm() <= 1e-9 * want_h2.norm(),
            "H2 line {k}"
        );
        let ratio = h1[k] / h2[k];
        assert!(
            (ratio.re - coh[k]).abs() < 1e-12 && ratio.im.abs() < 1e-12,
            "line {k}"
        );
    }
}
