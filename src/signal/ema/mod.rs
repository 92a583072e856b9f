//! Experimental modal analysis: natural frequencies, damping ratios and complex mode shapes
//! identified from the FRFs of one input (force, drive) to one or several outputs.
//!
//! Two methods:
//! - `lscf` (default): poles from the least-squares complex-frequency estimator over a range of
//!   model orders ([`lscf`]), physical poles chosen from the stabilization diagram
//!   ([`stabilization`]), residues and out-of-band residuals by LSFD ([`lsfd`]), which also
//!   rebuilds the FRFs to overlay on the measured ones;
//! - `peak`: resonances of the summed |H| with half-power damping ζ = 1/(2Q), shapes read as
//!   the FRF values at each peak line (the `frf` command's peak picking).
//!
//! Every mode carries its shape normalised to 1 at its largest component, the modal phase
//! collinearity and the mean phase deviation ([`indicators`]).

pub mod frf_table;
pub mod indicators;
pub mod lscf;
pub mod lsfd;
pub mod measured;
pub mod stabilization;

pub use lsfd::FrfForm;
pub use stabilization::{Criteria, DiagramPole, Stability};

use super::peaks::{PeakOptions, find_peaks, half_power_band, under_resolved_band};
use crate::error::SignalError;
use realfft::num_complex::Complex64;
use serde::Serialize;

/// Most model order the LSCF is asked for: the normal equations are (order + 1)², and beyond a
/// few hundred the monomial basis loses double precision.
pub const ORDER_LIMIT: usize = 400;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    Lscf,
    Peak,
}

/// FRFs of one input to several outputs on common frequency lines.
#[derive(Debug, Clone)]
pub struct FrfSet {
    pub freqs: Vec<f64>,
    pub channels: Vec<String>,
    /// `h[o][k]`: output o, line k.
    pub h: Vec<Vec<Complex64>>,
}

#[derive(Debug, Clone)]
pub struct EmaOptions {
    pub f_lo: f64,
    pub f_hi: f64,
    pub method: Method,
    /// Highest LSCF polynomial order (number of poles); orders 2, 4, … up to it are fitted.
    pub order_max: usize,
    /// `order_max` is the default, not the user's: lowered (with a note) to the highest even
    /// order the band's lines support, instead of refused.
    pub order_max_is_default: bool,
    pub form: FrfForm,
    pub criteria: Criteria,
    /// Peak method: prominence and count of the resonances kept.
    pub peaks: PeakOptions,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeEntry {
    pub channel: String,
    pub re: f64,
    pub im: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    pub frequency_hz: f64,
    pub damping_ratio: f64,
    pub shape: Vec<ShapeEntry>,
    pub mpc: f64,
    /// Mean phase deviation, degrees.
    pub mpd: f64,
    /// LSCF: distinct model orders at which the mode was stable in vector.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stable_orders: Option<usize>,
    /// LSCF: the model order of the chosen pole.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub order: Option<usize>,
}

/// What an identification produced.
#[derive(Debug, Clone)]
pub struct EmaModel {
    pub method: Method,
    /// The lines used, Hz, and the measured FRFs on them.
    pub freqs: Vec<f64>,
    pub measured: Vec<Vec<Complex64>>,
    pub orders: Vec<usize>,
    pub diagram: Vec<DiagramPole>,
    pub modes: Vec<Mode>,
    /// LSFD rebuild of every output on `freqs` (LSCF only).
    pub reconstructed: Option<Vec<Vec<Complex64>>>,
    /// What was skipped and why.
    pub notes: Vec<String>,
}

impl EmaModel {
    pub fn band_hz(&self) -> (f64, f64) {
        (
            self.freqs.first().copied().unwrap_or(0.0),
            self.freqs.last().copied().unwrap_or(0.0),
        )
    }
}

fn bad(name: &'static str, value: impl ToString, reason: impl Into<String>) -> SignalError {
    SignalError::BadParameter {
        name,
        value: value.to_string(),
        reason: reason.into(),
    }
}

/// The lines of `set` from the one nearest `f_lo` (a log's sampling rate read from its time
/// column puts line k a hair off k·df) up to the last at or below `f_hi`, above 0 Hz, checked.
fn band(set: &FrfSet, o: &EmaOptions) -> Result<(Vec<f64>, Vec<Vec<Complex64>>), SignalError> {
    if !(o.f_lo.is_finite() && o.f_hi.is_finite() && o.f_lo >= 0.0 && o.f_hi > o.f_lo) {
        return Err(bad(
            "fmin/fmax",
            format!("{}/{}", o.f_lo, o.f_hi),
            "need 0 ≤ fmin < fmax, finite",
        ));
    }
    let first = (0..set.freqs.len())
        .min_by(|&a, &b| {
            (set.freqs[a] - o.f_lo)
                .abs()
                .total_cmp(&(set.freqs[b] - o.f_lo).abs())
        })
        .unwrap_or(0);
    let idx: Vec<usize> = (first..set.freqs.len())
        .filter(|&k| set.freqs[k] > 0.0 && set.freqs[k] <= o.f_hi)
        .collect();
    let freqs: Vec<f64> = idx.iter().map(|&k| set.freqs[k]).collect();
    let h: Vec<Vec<Complex64>> = set
        .h
        .iter()
        .map(|ho| idx.iter().map(|&k| ho[k]).collect())
        .collect();
    for (c, ho) in set.channels.iter().zip(&h) {
        if let Some(k) = ho
            .iter()
            .position(|z| !(z.re.is_finite() && z.im.is_finite()))
        {
            return Err(SignalError::Channel {
                channel: c.clone(),
                message: format!("the FRF is not finite at {} Hz", freqs[k]),
            });
        }
    }
    check_squares(&set.channels, &freqs, &h)?;
    Ok((freqs, h))
}

/// Largest sum of |H|² the fit's normal equations hold with room for their products.
const SQUARES_LIMIT: f64 = 1e300;

/// The fit sums |H|² over every line and output: an outlier whose square overflows (a cell
/// written as 1.7e308, a unit error of many decades) is named rather than fitted into NaN.
fn check_squares(
    channels: &[String],
    freqs: &[f64],
    h: &[Vec<Complex64>],
) -> Result<(), SignalError> {
    let total: f64 = h.iter().flatten().map(|z| z.norm_sqr()).sum();
    if total.is_finite() && total <= SQUARES_LIMIT {
        return Ok(());
    }
    let (o, k) = (0..h.len())
        .flat_map(|o| (0..h[o].len()).map(move |k| (o, k)))
        .max_by(|a, b| h[a.0][a.1].norm().total_cmp(&h[b.0][b.1].norm()))
        .unwrap_or((0, 0));
    Err(SignalError::Channel {
        channel: channels[o].clone(),
        message: format!(
            "|H| = {:e} at {} Hz: the fit sums |H|², and this one overflows (an outlier or a \
             unit error in the FRF)",
            h[o][k].norm(),
            freqs[k]
        ),
    })
}

/// Identifies the modes of `set` in the band of `opts`.
pub fn identify(set: &FrfSet, opts: &EmaOptions) -> Result<EmaModel, SignalError> {
    let (freqs, h) = band(set, opts)?;
    match opts.method {
        Method::Lscf => identify_lscf(set, freqs, h, opts),
        Method::Peak => Ok(identify_peak(set, freqs, h, opts)),
    }
}

fn identify_lscf(
    set: &FrfSet,
    freqs: Vec<f64>,
    h: Vec<Vec<Complex64>>,
    opts: &EmaOptions,
) -> Result<EmaModel, SignalError> {
    let mut notes = Vec::new();
    let mut n = opts.order_max;
    let band_order = freqs.len().saturating_sub(2) / 2 * 2;
    if opts.order_max_is_default && band_order >= 2 && band_order < n {
        notes.push(format!(
            "the band holds {} lines: model orders up to {band_order} (default {n}; --order-max to choose)",
            freqs.len()
        ));
        n = band_order;
    }
    if !(2..=ORDER_LIMIT).contains(&n) || !n.is_multiple_of(2) {
        return Err(bad(
            "order-max",
            n,
            format!("an even model order in 2..={ORDER_LIMIT}"),
        ));
    }
    if freqs.len() < n + 2 {
        return Err(bad(
            "order-max",
            n,
            format!(
                "the band holds {} lines, fewer than order + 2; lower --order-max or widen the band",
                freqs.len()
            ),
        ));
    }
    let f_top = freqs[freqs.len() - 1];
    let ts = 0.5 / f_top;
    let theta: Vec<f64> = freqs
        .iter()
        .map(|f| std::f64::consts::PI * f / f_top)
        .collect();
    let (fits, stopped) =
        lscf::fit_orders(&theta, &h, ts, n, opts.order_max_is_default).map_err(|e| {
            SignalError::Invalid(format!(
                "LSCF on channel(s) {} over {:.6}–{f_top:.6} Hz: {e}",
                set.channels.join(", "),
                freqs[0]
            ))
        })?;
    if let (Some(e), Some(last)) = (stopped, fits.last()) {
        notes.push(format!("model orders up to {}: {e}", last.order));
    }
    let range = (freqs[0], f_top);
    let diagram = stabilization::diagram(&fits, range, &opts.criteria);
    let chosen = stabilization::select(&diagram, &opts.criteria);
    if chosen.is_empty() {
        notes.push(format!(
            "no pole stable in frequency, damping and vector over {} orders in {:.3}–{:.3} Hz",
            opts.criteria.min_orders, range.0, range.1
        ));
    }
    let poles: Vec<Complex64> = chosen.iter().map(|s| s.pole.lambda).collect();
    let fit = lsfd::fit(&freqs, &h, &poles, opts.form)?;
    let modes = chosen
        .iter()
        .zip(&fit.residues)
        .map(|(s, r)| {
            let mut m = mode_of(&set.channels, s.pole.frequency_hz, s.pole.damping_ratio, r);
            m.stable_orders = Some(s.stable_orders);
            m.order = Some(s.pole.order);
            m
        })
        .collect();
    Ok(EmaModel {
        method: Method::Lscf,
        orders: fits.iter().map(|f| f.order).collect(),
        freqs,
        measured: h,
        diagram,
        modes,
        reconstructed: Some(fit.reconstructed),
        notes,
    })
}

/// A mode with its shape normalised to 1 at its largest component.
fn mode_of(channels: &[String], f: f64, zeta: f64, v: &[Complex64]) -> Mode {
    let big = v
        .iter()
        .copied()
        .reduce(|a, b| if b.norm() > a.norm() { b } else { a })
        .filter(|z| z.norm() > 0.0)
        .unwrap_or(Complex64::new(1.0, 0.0));
    let shape = channels
        .iter()
        .zip(v)
        .map(|(c, z)| {
            let s = z / big;
            ShapeEntry {
                channel: c.clone(),
                re: s.re,
                im: s.im,
            }
        })
        .collect();
    Mode {
        frequency_hz: f,
        damping_ratio: zeta,
        shape,
        mpc: indicators::mpc(v),
        mpd: indicators::mpd_deg(v),
        stable_orders: None,
        order: None,
    }
}

/// Peak picking on the summed magnitude Σ_o |H_o| with half-power damping.
fn identify_peak(
    set: &FrfSet,
    freqs: Vec<f64>,
    h: Vec<Vec<Complex64>>,
    opts: &EmaOptions,
) -> EmaModel {
    let sum: Vec<f64> = (0..freqs.len())
        .map(|k| h.iter().map(|ho| ho[k].norm()).sum())
        .collect();
    let popts = PeakOptions {
        db_per_decade: 20.0,
        f_min_hz: 0.0,
        f_max_hz: f64::INFINITY,
        ..opts.peaks.clone()
    };
    let mut modes = Vec::new();
    let mut notes = Vec::new();
    for p in find_peaks(&freqs, &sum, &popts) {
        let Some((lo, hi)) = half_power_band(&freqs, &sum, p.line, p.value) else {
            notes.push(format!(
                "peak at {:.3} Hz: no half-power crossing on one side, damping not measurable; left out",
                p.frequency_hz
            ));
            continue;
        };
        // Half-power bandwidth: Q = f/Δf and ζ = 1/(2Q) = Δf/(2f) for light damping.
        let zeta = (hi - lo) / (2.0 * p.frequency_hz);
        let df = freqs.get(1).map_or(f64::INFINITY, |f1| f1 - freqs[0]);
        if let Some(lines) = under_resolved_band(hi - lo, df) {
            notes.push(format!(
                "peak at {:.3} Hz: its half-power band ({:.4} Hz) spans {lines:.1} line(s) of {df:.4} Hz, so its damping is set by \
                 the resolution as much as by the structure (the window widens the band: ζ reads high); a longer segment resolves it",
                p.frequency_hz,
                hi - lo
            ));
        }
        let v: Vec<Complex64> = h.iter().map(|ho| ho[p.line]).collect();
        modes.push(mode_of(&set.channels, p.frequency_hz, zeta, &v));
    }
    EmaModel {
        method: Method::Peak,
        freqs,
        measured: h,
        orders: Vec::new(),
        diagram: Vec::new(),
        modes,
        reconstructed: None,
        notes,
    }
}
