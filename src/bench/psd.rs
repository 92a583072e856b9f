//! `satqual bench psd`: Welch PSD throughput (samples/s) in memory and from CSV for 1e6, 1e7 and
//! 1e8 samples, peak RSS of the streamed CSV path, and, when python3 with scipy and pandas is on
//! the machine, `scipy.signal.welch` (nperseg 8192, Hann, 50%) on the same samples and
//! `pandas.read_csv` on the same file, with the ratios. Writes `psd.json` and `psd.md`.
//!
//! Reductions, so the run stays near three minutes on a shared two-core machine: scipy and
//! pandas run at 1e6 and 1e7 only (scipy's Welch holds every segment at once: at 1e8 samples it
//! would need ~5 GB, and pandas would hold the whole 3 GB file's frame); 1e8 is timed once.
//! Nothing is installed: without python3/scipy/pandas the peer columns say so.
//!
//! The SRS row ([`super::psd_srs`]) is timed in the same run.

use crate::Error;
use crate::signal::ingest::{IngestOptions, stream_csv};
use crate::signal::{Detrend, WelchOptions, Window, psd_of_file, welch};
use serde_json::{Value, json};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

const FS: f64 = 8192.0;

/// Deterministic test signal: xorshift noise plus a 1 kHz tone (no RNG crate needed for a bench).
fn signal(n: usize) -> Vec<f64> {
    let mut s = 0x9E3779B97F4A7C15u64;
    (0..n)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let u = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            u + 0.3 * (2.0 * std::f64::consts::PI * 1000.0 * i as f64 / FS).sin()
        })
        .collect()
}

fn status_kb(key: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// CPU seconds (user + system, all threads) of this process so far, from /proc/self/stat
/// fields 14 and 15 in clock ticks of 1/100 s (the Linux USER_HZ on every mainstream
/// architecture). Wall-clock figures swing on a shared machine; CPU time does much less.
pub(super) fn cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // The command name (field 2) may hold spaces: count fields after its closing parenthesis.
    let rest = s.rsplit_once(')').map_or("", |r| r.1);
    // After the name, field 3 (state) is index 0, so utime (14) and stime (15) are 11 and 12.
    let f: Vec<&str> = rest.split_whitespace().collect();
    let tick = |i: usize| f.get(i).and_then(|v| v.parse::<u64>().ok());
    match (tick(11), tick(12)) {
        (Some(u), Some(k)) => (u + k) as f64 / 100.0,
        _ => f64::NAN,
    }
}

/// Resets the peak-RSS mark (Linux ≥ 4.0) so each run's VmHWM is its own.
fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn write_csv(path: &Path, x: &[f64]) -> Result<(), Error> {
    let f = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = std::io::BufWriter::with_capacity(1 << 20, f);
    writeln!(w, "time_s,accel_g").map_err(|e| Error::io(path, e))?;
    for (i, v) in x.iter().enumerate() {
        writeln!(w, "{:.9},{:.9e}", i as f64 / FS, v).map_err(|e| Error::io(path, e))?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

fn write_f64(path: &Path, x: &[f64]) -> Result<(), Error> {
    let mut b = Vec::with_capacity(x.len() * 8);
    for v in x {
        b.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, b).map_err(|e| Error::io(path, e))
}

const PY: &str = r#"
import sys, json, time, resource
mode, path = sys.argv[1], sys.argv[2]
out = {}
if mode == "welch":
    import numpy as np, scipy, scipy.signal as ss
    x = np.fromfile(path, dtype="<f8")
    best = 1e99
    reps = int(sys.argv[3])
    c0 = time.process_time()
    for _ in range(reps):
        t = time.perf_counter()
        f, p = ss.welch(x, fs=8192.0, window="hann", nperseg=8192, noverlap=4096, detrend="constant")
        best = min(best, time.perf_counter() - t)
    out = {"seconds": best, "cpu_seconds": (time.process_time() - c0) / reps, "scipy": scipy.__version__}
    if len(sys.argv) > 4:
        ours = np.fromfile(sys.argv[4], dtype="<f8")
        m = p > 1e-12 * p.max()
        out["max_rel_err_vs_ours"] = float(np.max(np.abs(ours[m] - p[m]) / p[m]))
elif mode in ("pandas+scipy", "polars+scipy", "polars"):
    import numpy as np, scipy.signal as ss
    if mode.startswith("pandas"):
        import pandas as lib
        read = lambda: lib.read_csv(path)["accel_g"].to_numpy()
    else:
        import polars as lib
        read = lambda: lib.read_csv(path)["accel_g"].to_numpy()
    best = 1e99
    reps = int(sys.argv[3])
    c0 = time.process_time()
    for _ in range(reps):
        t = time.perf_counter()
        x = read()
        if mode != "polars":
            f, p = ss.welch(x, fs=8192.0, window="hann", nperseg=8192, noverlap=4096, detrend="constant")
        best = min(best, time.perf_counter() - t)
        del x
    out = {"seconds": best, "cpu_seconds": (time.process_time() - c0) / reps, "version": lib.__version__}
else:
    import pandas as pd
    best = 1e99
    c0 = time.process_time()
    for _ in range(int(sys.argv[3])):
        t = time.perf_counter()
        df = pd.read_csv(path)
        best = min(best, time.perf_counter() - t)
        rows = len(df)
        del df
    out = {"seconds": best, "cpu_seconds": (time.process_time() - c0) / int(sys.argv[3]), "rows": rows, "pandas": pd.__version__}
out["peak_rss_kb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps(out))
"#;

pub(super) fn python(script: &Path, args: &[&str]) -> Option<Value> {
    let o = std::process::Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .ok()?;
    if !o.status.success() {
        return None;
    }
    serde_json::from_slice(&o.stdout).ok()
}

fn have_python() -> bool {
    python_imports("scipy.signal, pandas")
}

fn python_imports(modules: &str) -> bool {
    std::process::Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Whether the SRS peer can run, or why not.
fn scipy_available() -> Result<(), &'static str> {
    match std::process::Command::new("python3")
        .args(["-c", "import numpy, scipy.signal"])
        .output()
    {
        Err(_) => Err("python3 is not on the PATH"),
        Ok(o) if !o.status.success() => Err("python3 cannot import numpy and scipy.signal"),
        Ok(_) => Ok(()),
    }
}

/// The table as (JSON, Markdown).
pub fn run() -> Result<(String, String), Error> {
    let opts = WelchOptions {
        nperseg: 8192,
        overlap: 0.5,
        window: Window::Hann,
        detrend: Detrend::Constant,
    };
    let tmp: PathBuf =
        std::env::temp_dir().join(format!("satqual-bench-psd-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).map_err(|e| Error::io(&tmp, e))?;
    let script = tmp.join("peer.py");
    std::fs::write(&script, PY).map_err(|e| Error::io(&script, e))?;
    let py = have_python();
    if !py {
        eprintln!(
            "bench psd: no scipy.welch / pandas.read_csv peers: python3 cannot import scipy.signal and pandas"
        );
    }
    let have_polars = py && python_imports("polars");
    if py && !have_polars {
        eprintln!("bench psd: no polars peer: python3 cannot import polars (pip install polars)");
    }
    let threads = rayon::current_num_threads();
    let load_before = std::fs::read_to_string("/proc/loadavg")
        .unwrap_or_default()
        .trim()
        .to_string();
    let mut rows = Vec::new();
    for (label, n) in [
        ("1e6", 1_000_000usize),
        ("1e7", 10_000_000),
        ("1e8", 100_000_000),
    ] {
        eprintln!("bench psd: {label} samples ...");
        let x = signal(n);
        // Best of several runs, the same count for satqual and the peers: on a shared machine
        // the minimum is the figure least disturbed by other work.
        let reps = if n <= 1_000_000 {
            10
        } else if n <= 10_000_000 {
            5
        } else {
            1
        };
        let csv_reps = if n <= 1_000_000 {
            5
        } else if n <= 10_000_000 {
            2
        } else {
            1
        };
        let mut best = f64::INFINITY;
        let mut psd = None;
        let c0 = cpu_seconds();
        for _ in 0..reps {
            let t = Instant::now();
            let p = welch(&x, FS, &opts)?;
            best = best.min(t.elapsed().as_secs_f64());
            psd = Some(p);
        }
        let welch_cpu = (cpu_seconds() - c0) / reps as f64;
        let peers = py && n <= 10_000_000;
        let bin = tmp.join(format!("x_{label}.f64"));
        let ours_bin = tmp.join(format!("psd_{label}.f64"));
        let scipy = if peers {
            write_f64(&bin, &x)?;
            if let Some(p) = &psd {
                write_f64(&ours_bin, &p.values)?;
            }
            let r = python(
                &script,
                &[
                    "welch",
                    bin.to_str().unwrap_or(""),
                    &reps.to_string(),
                    ours_bin.to_str().unwrap_or(""),
                ],
            );
            let _ = std::fs::remove_file(&bin);
            let _ = std::fs::remove_file(&ours_bin);
            r
        } else {
            None
        };
        let csv = tmp.join(format!("log_{label}.csv"));
        let t = Instant::now();
        write_csv(&csv, &x)?;
        let write_s = t.elapsed().as_secs_f64();
        let file_bytes = std::fs::metadata(&csv).map(|m| m.len()).unwrap_or(0);
        drop(x);
        drop(psd);
        // Read only (parse and check every row, discard): the figure comparable with pandas.
        let reset = reset_peak();
        let base_rss = status_kb("VmRSS:").unwrap_or(0);
        let mut read_s = f64::INFINITY;
        let mut count = 0u64;
        let c0 = cpu_seconds();
        for _ in 0..csv_reps {
            let t = Instant::now();
            count = 0;
            stream_csv(&csv, &IngestOptions::default(), |_| count += 1)?;
            read_s = read_s.min(t.elapsed().as_secs_f64());
        }
        let read_cpu = (cpu_seconds() - c0) / csv_reps as f64;
        let read_peak = status_kb("VmHWM:").unwrap_or(0);
        // Read and Welch, streamed: the `satqual psd` path.
        reset_peak();
        let mut psd_s = f64::INFINITY;
        let mut res = None;
        for _ in 0..csv_reps {
            let t = Instant::now();
            res = Some(psd_of_file(&csv, &IngestOptions::default(), &opts)?);
            psd_s = psd_s.min(t.elapsed().as_secs_f64());
        }
        let psd_peak = status_kb("VmHWM:").unwrap_or(0);
        let pandas = if peers {
            python(
                &script,
                &["pandas", csv.to_str().unwrap_or(""), &csv_reps.to_string()],
            )
        } else {
            None
        };
        let pipeline = |mode: &str, ok: bool| {
            (peers && ok)
                .then(|| {
                    python(
                        &script,
                        &[mode, csv.to_str().unwrap_or(""), &csv_reps.to_string()],
                    )
                })
                .flatten()
        };
        let pandas_scipy = pipeline("pandas+scipy", true);
        let polars = pipeline("polars", have_polars);
        let polars_scipy = pipeline("polars+scipy", have_polars);
        let _ = std::fs::remove_file(&csv);
        let rate = |s: f64| n as f64 / s;
        let peer_row = |v: &Option<Value>, ours: f64| {
            v.as_ref().map(|v| json!({
                "seconds": v["seconds"], "cpu_seconds_per_run": v["cpu_seconds"], "version": v["version"],
                "samples_per_s": v["seconds"].as_f64().map(rate),
                "speedup_of_satqual": v["seconds"].as_f64().map(|s| s / ours),
            }))
        };
        let scipy_s = scipy.as_ref().and_then(|v| v["seconds"].as_f64());
        let pandas_s = pandas.as_ref().and_then(|v| v["seconds"].as_f64());
        rows.push(json!({
            "samples": n,
            "label": label,
            "in_memory": {"seconds": best, "samples_per_s": rate(best), "cpu_seconds_per_run": welch_cpu, "repetitions": reps},
            "scipy_welch": scipy.as_ref().map(|v| json!({
                "seconds": v["seconds"], "samples_per_s": scipy_s.map(rate), "cpu_seconds_per_run": v["cpu_seconds"], "peak_rss_kb": v["peak_rss_kb"],
                "version": v["scipy"], "max_rel_err_vs_satqual": v["max_rel_err_vs_ours"],
            })),
            "speedup_vs_scipy": scipy_s.map(|s| s / best),
            "cpu_ratio_vs_scipy": scipy.as_ref().and_then(|v| v["cpu_seconds"].as_f64()).map(|c| c / welch_cpu),
            "csv": {
                "file_bytes": file_bytes,
                "write_seconds": write_s,
                "rows_read": count,
                "read_seconds": read_s,
                "read_samples_per_s": rate(read_s),
                "read_cpu_seconds_per_run": read_cpu,
                "read_and_psd_seconds": psd_s,
                "read_and_psd_samples_per_s": rate(psd_s),
                "baseline_rss_kb": base_rss,
                "read_peak_rss_kb": read_peak,
                "read_and_psd_peak_rss_kb": psd_peak,
                "peak_reset": reset,
                "repetitions": csv_reps,
                "grms": res.as_ref().and_then(|r| r.channels.first().map(|c| c.grms)),
            },
            "pandas_read_csv": pandas.as_ref().map(|v| json!({
                "seconds": v["seconds"], "samples_per_s": pandas_s.map(rate), "cpu_seconds_per_run": v["cpu_seconds"], "peak_rss_kb": v["peak_rss_kb"], "version": v["pandas"],
            })),
            "csv_read_speedup_vs_pandas": pandas_s.map(|s| s / read_s),
            "csv_read_cpu_ratio_vs_pandas": pandas.as_ref().and_then(|v| v["cpu_seconds"].as_f64()).map(|c| c / read_cpu),
            "polars_read_csv": peer_row(&polars, read_s),
            "pandas_then_scipy_welch": peer_row(&pandas_scipy, psd_s),
            "polars_then_scipy_welch": peer_row(&polars_scipy, psd_s),
        }));
    }
    let srs = super::psd_srs::row(&tmp, scipy_available())?;
    let _ = std::fs::remove_dir_all(&tmp);
    let report = json!({
        "what": "Welch PSD throughput, nperseg 8192, Hann, 50% overlap, constant detrend, one channel, fs 8192 Hz",
        "threads": threads,
        "loadavg_before": load_before,
        "loadavg_after": std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim(),
        "python_peers": py,
        "reductions": "scipy and pandas run at 1e6 and 1e7 samples only (memory: scipy holds all segments, ~5 GB at 1e8); 1e8 timed once; Welch best of 10 (1e6) and 5 (1e7), CSV best of 5 (1e6) and 2 (1e7), same counts for the peers",
        "rows": rows,
        "srs": srs,
    });
    let md = markdown(&report);
    Ok((super::to_json(&report)?, md))
}

fn fmt_rate(v: &Value) -> String {
    v.as_f64()
        .map_or("-".into(), |r| format!("{:.1} M/s", r / 1e6))
}

fn fmt_ratio(v: &Value) -> String {
    v.as_f64().map_or("-".into(), |r| format!("{r:.2}×"))
}

fn fmt_mb(v: &Value) -> String {
    v.as_f64()
        .map_or("-".into(), |k| format!("{:.0} MB", k / 1024.0))
}

fn markdown(r: &Value) -> String {
    let mut s = String::from("# satqual bench psd\n\n");
    s.push_str(&format!(
        "{} ({} rayon threads). {}.\n\nLoad average (/proc/loadavg) before: {}; after: {}. Figures are wall-clock best-of-N; on a loaded machine they move by 2× between runs.\n\n",
        r["what"].as_str().unwrap_or(""),
        r["threads"],
        r["reductions"].as_str().unwrap_or(""),
        r["loadavg_before"].as_str().unwrap_or("?"),
        r["loadavg_after"].as_str().unwrap_or("?")
    ));
    s.push_str("| samples | satqual Welch (memory) | scipy.signal.welch | speed-up | satqual CSV read | pandas.read_csv | speed-up | satqual CSV read + PSD | peak RSS read+PSD (baseline) | file |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    for row in r["rows"].as_array().into_iter().flatten() {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} ({}) | {:.0} MB |\n",
            row["label"].as_str().unwrap_or(""),
            fmt_rate(&row["in_memory"]["samples_per_s"]),
            fmt_rate(&row["scipy_welch"]["samples_per_s"]),
            fmt_ratio(&row["speedup_vs_scipy"]),
            fmt_rate(&row["csv"]["read_samples_per_s"]),
            fmt_rate(&row["pandas_read_csv"]["samples_per_s"]),
            fmt_ratio(&row["csv_read_speedup_vs_pandas"]),
            fmt_rate(&row["csv"]["read_and_psd_samples_per_s"]),
            fmt_mb(&row["csv"]["read_and_psd_peak_rss_kb"]),
            fmt_mb(&row["csv"]["baseline_rss_kb"]),
            row["csv"]["file_bytes"].as_f64().unwrap_or(0.0) / 1e6,
        ));
    }
    s.push_str("\nCPU seconds per run (user + system, all threads; 10 ms ticks, so the 1e6 figures are coarse):\n\n");
    s.push_str("| samples | satqual Welch | scipy Welch | scipy/satqual | satqual CSV read | pandas.read_csv | pandas/satqual |\n|---|---|---|---|---|---|---|\n");
    let cpu = |v: &Value| v.as_f64().map_or("-".into(), |c| format!("{c:.3} s"));
    for row in r["rows"].as_array().into_iter().flatten() {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} |\n",
            row["label"].as_str().unwrap_or(""),
            cpu(&row["in_memory"]["cpu_seconds_per_run"]),
            cpu(&row["scipy_welch"]["cpu_seconds_per_run"]),
            fmt_ratio(&row["cpu_ratio_vs_scipy"]),
            cpu(&row["csv"]["read_cpu_seconds_per_run"]),
            cpu(&row["pandas_read_csv"]["cpu_seconds_per_run"]),
            fmt_ratio(&row["csv_read_cpu_ratio_vs_pandas"]),
        ));
    }
    s.push_str("\nFile to PSD, end to end (read the CSV, then Welch on the column; the peers read with pandas or polars and run scipy.signal.welch), and the CSV read alone against polars:\n\n");
    s.push_str("| samples | satqual psd | pandas + scipy | satqual speed-up | polars + scipy | satqual speed-up | satqual read | polars.read_csv | satqual speed-up |\n|---|---|---|---|---|---|---|---|---|\n");
    for row in r["rows"].as_array().into_iter().flatten() {
        let peer = |k: &str| {
            (
                fmt_rate(&row[k]["samples_per_s"]),
                fmt_ratio(&row[k]["speedup_of_satqual"]),
            )
        };
        let (pd, pd_x) = peer("pandas_then_scipy_welch");
        let (pl, pl_x) = peer("polars_then_scipy_welch");
        let (plr, plr_x) = peer("polars_read_csv");
        s.push_str(&format!(
            "| {} | {} | {pd} | {pd_x} | {pl} | {pl_x} | {} | {plr} | {plr_x} |\n",
            row["label"].as_str().unwrap_or(""),
            fmt_rate(&row["csv"]["read_and_psd_samples_per_s"]),
            fmt_rate(&row["csv"]["read_samples_per_s"]),
        ));
    }
    let errs: Vec<String> = r["rows"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|row| {
            row["scipy_welch"]["max_rel_err_vs_satqual"]
                .as_f64()
                .map(|e| format!("{}: {e:.2e}", row["label"].as_str().unwrap_or("")))
        })
        .collect();
    if !errs.is_empty() {
        s.push_str(&format!(
            "\nMax relative difference satqual vs scipy PSD on the same samples: {}.\n",
            errs.join(", ")
        ));
    }
    s.push_str(&super::psd_srs::markdown(&r["srs"]));
    s.push_str("\nPeak RSS is VmHWM of this process, reset before each CSV run (/proc/self/clear_refs); the baseline is VmRSS before the run. Peers' peak RSS is in psd.json.\n");
    s
}
