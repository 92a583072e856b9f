//! The report's figures, one file per family, each with the CSV of the data it plots under
//! `curves/`, so every plotted number can be checked.

mod environments;
mod modal;
mod monte_carlo;
mod response;
mod separation;
mod test_logs;

use super::Qualification;
use super::document::Figure;
use crate::error::Error;

/// Files of the report: path relative to the report folder, content.
pub type Files = Vec<(String, Vec<u8>)>;

/// Draws every figure the results allow, in report order, and adds their curves to `files`.
pub fn build(q: &Qualification, files: &mut Files) -> Result<Vec<Figure>, Error> {
    let mut figs = Vec::new();
    if let Some(env) = &q.environments {
        figs.extend(environments::figures(env, files)?);
    }
    if let Some(m) = &q.modal {
        figs.push(modal::effective_mass(m, files)?);
    }
    if let Some(resp) = &q.response {
        figs.extend(response::figures(resp, files)?);
    }
    if let Some(td) = &q.test_data {
        figs.extend(test_logs::figures(td, files)?);
    }
    if let Some(sep) = &q.separation {
        if let Some(mc) = &sep.monte_carlo {
            figs.extend(monte_carlo::histograms(mc, files)?);
        }
        if let Some(h) = &sep.result.history {
            figs.extend(separation::histories(h, files)?);
        }
    }
    Ok(figs)
}

/// A CSV table: the header line, then one line per row, numbers in full precision.
fn csv(header: &str, rows: impl Iterator<Item = Vec<f64>>) -> Vec<u8> {
    let mut s = String::from(header);
    s.push('\n');
    for r in rows {
        let line: Vec<String> = r.iter().map(|v| format!("{v:.9e}")).collect();
        s.push_str(&line.join(","));
        s.push('\n');
    }
    s.into_bytes()
}
