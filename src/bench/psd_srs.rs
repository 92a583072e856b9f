//! The SRS row of `satqual bench psd`: time per channel-second of the shock response spectrum
//! (`satqual srs`'s kernel, [`crate::signal::srs::srs`]) against a loop of
//! `scipy.signal.lfilter` calls with the same Smallwood ramp-invariant coefficients (absolute
//! acceleration and pseudo-velocity, record then residual tail, per natural frequency), on the
//! same samples, in one run. The peer also returns its maximax so the row states how far the
//! two spectra are apart. Without python3 and scipy the row says why it has no peer.

use super::psd::{cpu_seconds, python};
use crate::Error;
use crate::signal::srs::{natural_frequencies, residual_samples, srs};
use serde_json::{Value, json};
use std::path::Path;
use std::time::Instant;

const FS: f64 = 51_200.0;
const SECONDS: f64 = 2.0;
const CHANNELS: usize = 2;
const Q: f64 = 10.0;
const REPS: usize = 3;

/// The peer: one spectrum per channel, the same loop as `data/signal-refs/make_srs_refs.py`.
pub const PY_SRS: &str = r#"
import sys, json, time
import numpy as np, scipy, scipy.signal as sig
x = np.fromfile(sys.argv[1], dtype="<f8").reshape(int(sys.argv[2]), -1)
freqs = np.fromfile(sys.argv[3], dtype="<f8")
fs, q, pad, reps = float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6]), int(sys.argv[7])
dt = 1 / fs

def common(f):
    w = 2 * np.pi * f; z = 1 / (2 * q); e = np.exp(-z * w * dt)
    k = w * dt * np.sqrt(1 - z * z)
    return w, e, k, e * np.cos(k), e * np.sin(k)

def acc(f):
    w, e, k, c, s = common(f); sp = s / k
    return np.array([1 - sp, 2 * (sp - c), e * e - sp]), np.array([1, -2 * c, e * e])

def pv(f):
    w, e, k, c, s = common(f)
    qq = (1 / (2 * q * q) - 1) / np.sqrt(1 - 1 / (4 * q * q)); wt, den = w * dt, dt * w * w
    b = np.array([((1 - c) / q - qq * s - wt) / den, (2 * c * wt - (1 - e * e) / q + 2 * qq * s) / den,
                  (-e * e * (wt + 1 / q) + c / q - qq * s) / den])
    return b, np.array([1, -2 * c, e * e])

def spectrum(ch):
    out, zeros = [], np.zeros(pad)
    for f in freqs:
        row = []
        for mk in (acc, pv):
            b, a = mk(f)
            y, zf = sig.lfilter(b, a, ch, zi=np.zeros(2))
            r, _ = sig.lfilter(b, a, zeros, zi=zf)
            row.append(max(np.abs(y).max(), np.abs(r).max()))
        out.append(row[0])
    return np.array(out)

best, c0 = 1e99, time.process_time()
for _ in range(reps):
    t = time.perf_counter()
    mm = [spectrum(ch) for ch in x]
    best = min(best, time.perf_counter() - t)
res = {"seconds": best, "cpu_seconds": (time.process_time() - c0) / reps, "scipy": scipy.__version__}
if len(sys.argv) > 8:
    ours = np.fromfile(sys.argv[8], dtype="<f8").reshape(len(x), -1)
    res["max_rel_err_vs_ours"] = float(max(np.max(np.abs(o - m) / m) for o, m in zip(ours, mm)))
print(json.dumps(res))
"#;

/// A shock record per channel: a half-sine pulse, a decaying 1.7 kHz ring and xorshift noise.
fn shock_record(channel: usize) -> Vec<f64> {
    let n = (FS * SECONDS) as usize;
    let mut s = 0x9E3779B97F4A7C15u64 ^ (channel as u64 + 1);
    let pi = std::f64::consts::PI;
    (0..n)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let noise = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let t = i as f64 / FS - 0.1;
            let pulse = if (0.0..5e-4).contains(&t) {
                500.0 * (pi * t / 5e-4).sin()
            } else {
                0.0
            };
            let ring = if t > 0.0 {
                80.0 * (-t / 0.02).exp() * (2.0 * pi * 1700.0 * t).sin()
            } else {
                0.0
            };
            pulse + ring + noise
        })
        .collect()
}

fn write_f64(path: &Path, x: impl Iterator<Item = f64>) -> Result<(), Error> {
    let b: Vec<u8> = x.flat_map(f64::to_le_bytes).collect();
    std::fs::write(path, b).map_err(|e| Error::io(path, e))
}

/// Times satqual and, when `scipy` is `Ok`, the peer; otherwise the row carries the reason.
pub fn row(dir: &Path, scipy: Result<(), &str>) -> Result<Value, Error> {
    eprintln!("bench psd: SRS ...");
    let records: Vec<Vec<f64>> = (0..CHANNELS).map(shock_record).collect();
    let freqs = natural_frequencies(10.0, 10_000.0, 12);
    let mut best = f64::INFINITY;
    let mut maximax = Vec::new();
    let c0 = cpu_seconds();
    for _ in 0..REPS {
        let t = Instant::now();
        let spectra = records
            .iter()
            .map(|x| srs(x, FS, &freqs, Q))
            .collect::<Result<Vec<_>, _>>()?;
        best = best.min(t.elapsed().as_secs_f64());
        maximax = spectra.into_iter().flatten().map(|p| p.maximax).collect();
    }
    let cpu = (cpu_seconds() - c0) / REPS as f64;
    let channel_s = CHANNELS as f64 * SECONDS;
    let peer = match scipy {
        Ok(()) => peer(dir, &records, &freqs, &maximax),
        Err(why) => {
            eprintln!("bench psd: SRS row without its scipy peer: {why}");
            None
        }
    };
    let peer_s = peer.as_ref().and_then(|v| v["seconds"].as_f64());
    let peer_cpu = peer.as_ref().and_then(|v| v["cpu_seconds"].as_f64());
    Ok(json!({
        "what": format!("SRS, Q = {Q}, {} natural frequencies (10 Hz to 10 kHz, 1/12 octave), absolute acceleration and pseudo-velocity, primary and residual; {CHANNELS} channels × {SECONDS} s at {FS} Hz; best of {REPS}", freqs.len()),
        "channel_seconds": channel_s,
        "satqual": {"seconds": best, "seconds_per_channel_second": best / channel_s, "cpu_seconds_per_channel_second": cpu / channel_s},
        "scipy_lfilter": peer.as_ref().map(|v| json!({
            "seconds": v["seconds"], "seconds_per_channel_second": peer_s.map(|s| s / channel_s),
            "cpu_seconds_per_channel_second": peer_cpu.map(|c| c / channel_s),
            "version": v["scipy"], "max_rel_err_vs_satqual": v["max_rel_err_vs_ours"],
        })),
        "peer_missing": scipy.err(),
        "speedup_vs_scipy": peer_s.map(|s| s / best),
        "cpu_ratio_vs_scipy": peer_cpu.map(|c| c / cpu),
    }))
}

fn peer(dir: &Path, records: &[Vec<f64>], freqs: &[f64], maximax: &[f64]) -> Option<Value> {
    let (x, f, ours, script) = (
        dir.join("srs_x.f64"),
        dir.join("srs_f.f64"),
        dir.join("srs_ours.f64"),
        dir.join("srs_peer.py"),
    );
    let written = write_f64(&x, records.iter().flatten().copied())
        .and(write_f64(&f, freqs.iter().copied()))
        .and(write_f64(&ours, maximax.iter().copied()))
        .and(std::fs::write(&script, PY_SRS).map_err(|e| Error::io(&script, e)));
    if written.is_err() {
        return None;
    }
    let pad = residual_samples(freqs[0], Q, 1.0 / FS).to_string();
    let path = |p: &Path| p.to_str().unwrap_or("").to_string();
    let args = [
        path(&x),
        CHANNELS.to_string(),
        path(&f),
        FS.to_string(),
        Q.to_string(),
        pad,
        REPS.to_string(),
        path(&ours),
    ];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    python(&script, &args)
}

/// The SRS table of `psd.md`.
pub fn markdown(r: &Value) -> String {
    let per = |v: &Value| {
        v.as_f64()
            .map_or("-".into(), |s| format!("{:.2} ms", s * 1e3))
    };
    let ratio = |v: &Value| v.as_f64().map_or("-".into(), |x| format!("{x:.2}×"));
    let mut s = format!(
        "\n## Shock response spectrum\n\n{}. Time per channel-second of record.\n\n",
        r["what"].as_str().unwrap_or("")
    );
    s.push_str(
        "| | satqual srs | scipy.signal.lfilter loop | scipy/satqual |\n|---|---|---|---|\n",
    );
    s.push_str(&format!(
        "| wall, per channel-second | {} | {} | {} |\n| CPU, per channel-second | {} | {} | {} |\n",
        per(&r["satqual"]["seconds_per_channel_second"]),
        per(&r["scipy_lfilter"]["seconds_per_channel_second"]),
        ratio(&r["speedup_vs_scipy"]),
        per(&r["satqual"]["cpu_seconds_per_channel_second"]),
        per(&r["scipy_lfilter"]["cpu_seconds_per_channel_second"]),
        ratio(&r["cpu_ratio_vs_scipy"]),
    ));
    match (
        r["scipy_lfilter"]["max_rel_err_vs_satqual"].as_f64(),
        r["peer_missing"].as_str(),
    ) {
        (Some(e), _) => s.push_str(&format!(
            "\nMax relative difference of the maximax spectra on the same samples: {e:.2e}.\n"
        )),
        (None, Some(why)) => s.push_str(&format!("\nNo scipy peer: {why}.\n")),
        _ => {}
    }
    s
}
