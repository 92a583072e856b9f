//! The release shock of `satqual separate`: its summary lines and, with `--out`, its CSV
//! files (the uniform acceleration history and the SRS of every moving body).

use satqual::Error;
use satqual::report::write_atomic;
use satqual::separation::shock::{BodyShock, ReleaseShock};
use std::fmt::Write as _;
use std::path::Path;

/// One line per moving body: peak, SRS maximum and the specification check.
pub(super) fn summary(s: &mut String, shock: &ReleaseShock) {
    let _ = writeln!(
        s,
        "  release shock (SRS Q {}, {}–{} Hz at 1/{} octave, histories at {} Hz):",
        shock.q, shock.fmin_hz, shock.fmax_hz, shock.per_octave, shock.sample_rate_hz
    );
    for b in &shock.bodies {
        let spec = match &b.spec {
            Some(c) => format!(
                "; spec {}{}",
                if c.pass { "pass" } else { "FAIL" },
                c.governing.map_or(String::new(), |g| format!(
                    " ({:.3} g against {:.3} g at {:.1} Hz, {} axis)",
                    g.measured_g, g.limit_g, g.frequency_hz, g.axis
                ))
            ),
            None => String::new(),
        };
        let _ = writeln!(
            s,
            "    {}: peak {:.4} g ({}) at {:.4} s, SRS max {:.4} g at {:.1} Hz ({}){spec}",
            b.body, b.peak_g, b.peak_axis, b.peak_time_s, b.srs_max_g, b.srs_max_hz, b.srs_max_axis
        );
    }
}

/// `shock-<body>.csv` (time, acceleration per axis in g) and `srs-<body>.csv` (maximax per
/// axis in g) for every moving body.
pub(super) fn write_csv(dir: &Path, shock: &ReleaseShock) -> Result<(), Error> {
    for b in &shock.bodies {
        let stem = b.body.replace(' ', "-");
        write_atomic(
            &dir.join(format!("shock-{stem}.csv")),
            history(b, shock.sample_rate_hz).as_bytes(),
        )?;
        write_atomic(&dir.join(format!("srs-{stem}.csv")), spectrum(b).as_bytes())?;
    }
    Ok(())
}

fn history(b: &BodyShock, fs: f64) -> String {
    let mut s = String::from("time_s,ax_g,ay_g,az_g\n");
    for (k, a) in b.samples.iter().enumerate() {
        let t = b.window_s[0] + k as f64 / fs;
        let _ = writeln!(s, "{t},{},{},{}", a[0], a[1], a[2]);
    }
    s
}

fn spectrum(b: &BodyShock) -> String {
    let mut s = String::from("frequency_hz,x_maximax_g,y_maximax_g,z_maximax_g\n");
    for (k, p) in b.axes[0].srs.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{},{},{}",
            p.frequency_hz, p.maximax, b.axes[1].srs[k].maximax, b.axes[2].srs[k].maximax
        );
    }
    s
}
