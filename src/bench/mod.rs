//! Work-precision tables (run time against error) for `satqual bench WHAT`: mesh density for
//! the FE core, the sparse modal solver against scipy's eigsh, the response grids and modal
//! truncation, the streamed PSD against scipy, the separation integrator's tolerance, and the
//! modal identification (LSCF) against noise and model order, and model updating.
//!
//! Unlike the analyses, a benchmark does I/O: it times runs, writes its table as JSON and
//! Markdown to the output folder, and may call Python peers (skipped when absent). The
//! problems come from [`crate::catalogue`], as in the tests. Timings are measured here,
//! never asserted in tests.

mod ema;
mod fem;
mod modal;
mod modal_peers;
mod modal_sweep;
mod psd;
mod psd_srs;
mod response;
mod separation;
mod update;

use crate::Error;
use std::path::Path;

/// The benchmarks, by the name `satqual bench` takes.
pub const NAMES: [&str; 7] = [
    "fem",
    "modal",
    "response",
    "psd",
    "separation",
    "ema",
    "update",
];

/// A finished benchmark: its table, as written to `<out>/<name>.json` and `<name>.md`.
#[derive(Debug, Clone)]
pub struct Table {
    pub name: &'static str,
    /// The machine-readable result (pretty-printed JSON).
    pub json: String,
    /// The human-readable table.
    pub markdown: String,
}

/// Runs the benchmark `name` and writes its table to `out`.
pub fn run(name: &str, out: &Path) -> Result<Table, Error> {
    let (name, (json, markdown)) = match name {
        "fem" => ("fem", fem::run()?),
        "modal" => ("modal", modal::run(out)?),
        "response" => ("response", response::run()?),
        "psd" => ("psd", psd::run()?),
        "separation" => ("separation", separation::run()?),
        "ema" => ("ema", ema::run()?),
        "update" => ("update", update::run()?),
        other => {
            return Err(Error::Other(format!(
                "unknown benchmark `{other}` (one of {})",
                NAMES.join(", ")
            )));
        }
    };
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    crate::report::write_atomic(&out.join(format!("{name}.json")), json.as_bytes())?;
    crate::report::write_atomic(&out.join(format!("{name}.md")), markdown.as_bytes())?;
    Ok(Table {
        name,
        json,
        markdown,
    })
}

/// Pretty JSON of a benchmark's result.
fn to_json<T: serde::Serialize>(value: &T) -> Result<String, Error> {
    serde_json::to_string_pretty(value).map_err(|e| Error::Other(e.to_string()))
}
