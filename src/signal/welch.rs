//! Welch PSD and CSD: windows, detrending, segment averaging, one-sided density scaling.
//!
//! Inputs are uniformly sampled channels, either whole slices ([`welch`], [`csd`]) or rows
//! pushed one at a time by the streamed CSV reader ([`WelchStream`]). Both paths run the same
//! block code, so a log read from a file and the same samples held in memory give bit-identical
//! spectra.
//!
//! The definitions follow `scipy.signal.welch`/`csd` exactly (periodic windows built as
//! `general_cosine` on `linspace(-π, π, M+1)`, detrend before windowing, `scale = 1/(fs·Σw²)`,
//! doubling of every bin except DC and, for even `nperseg`, Nyquist; `noverlap = ⌊overlap·nperseg⌋`;
//! only full segments; plain mean over segments), because tests compare against scipy to 1e-9.
//!
//! Determinism: segments are transformed in parallel (rayon), but their spectra are summed in
//! segment order by one thread, so the result does not depend on the number of threads nor on
//! how the samples arrived in blocks.

use crate::error::SignalError;
use rayon::prelude::*;
use realfft::RealFftPlanner;
use realfft::num_complex::Complex64;
use std::sync::Arc;

/// Taper applied to each segment (periodic, as `scipy.signal.get_window`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Window {
    Hann,
    Hamming,
    Flattop,
    Boxcar,
}

impl Window {
    pub fn parse(s: &str) -> Result<Window, SignalError> {
        match s.to_ascii_lowercase().as_str() {
            "hann" | "hanning" => Ok(Window::Hann),
            "hamming" => Ok(Window::Hamming),
            "flattop" | "flat-top" => Ok(Window::Flattop),
            "boxcar" | "rect" | "rectangular" | "none" => Ok(Window::Boxcar),
            _ => Err(SignalError::BadParameter {
                name: "window",
                value: s.to_string(),
                reason: "expected hann, hamming, flattop or boxcar".into(),
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Window::Hann => "hann",
            Window::Hamming => "hamming",
            Window::Flattop => "flattop",
            Window::Boxcar => "boxcar",
        }
    }

    /// The `m` periodic window coefficients.
    pub fn coefficients(self, m: usize) -> Vec<f64> {
        let a: &[f64] = match self {
            Window::Boxcar => return vec![1.0; m],
            Window::Hann => &[0.5, 0.5],
            Window::Hamming => &[0.54, 0.46],
            // scipy.signal.windows.flattop (D'Antona & Ferrero).
            Window::Flattop => &[
                0.21557895,
                0.41663158,
                0.277263158,
                0.083578947,
                0.006947368,
            ],
        };
        if m == 1 {
            return vec![1.0];
        }
        // Same arithmetic as numpy.linspace(-pi, pi, m + 1): j·step + start.
        let step = 2.0 * std::f64::consts::PI / m as f64;
        (0..m)
            .map(|j| {
                let fac = j as f64 * step + (-std::f64::consts::PI);
                let mut w = 0.0;
                for (k, ak) in a.iter().enumerate() {
                    w += ak * (k as f64 * fac).cos();
                }
                w
            })
            .collect()
    }
}

/// Trend removed from each segment before windowing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Detrend {
    None,
    Constant,
    Linear,
}

impl Detrend {
    pub fn parse(s: &str) -> Result<Detrend, SignalError> {
        match s.to_ascii_lowercase().as_str() {
            "none" | "false" => Ok(Detrend::None),
            "constant" | "mean" => Ok(Detrend::Constant),
            "linear" => Ok(Detrend::Linear),
            _ => Err(SignalError::BadParameter {
                name: "detrend",
                value: s.to_string(),
                reason: "expected none, constant or linear".into(),
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Detrend::None => "none",
            Detrend::Constant => "constant",
            Detrend::Linear => "linear",
        }
    }

    fn apply(self, x: &mut [f64]) {
        let n = x.len();
        match self {
            Detrend::None => {}
            Detrend::Constant => {
                let mean = x.iter().sum::<f64>() / n as f64;
                x.iter_mut().for_each(|v| *v -= mean);
            }
            Detrend::Linear => {
                if n < 2 {
                    x.iter_mut().for_each(|v| *v = 0.0);
                    return;
                }
                // Closed-form least-squares line on abscissae 0..n-1 (what scipy's lstsq solves).
                let nf = n as f64;
                let xbar = (nf - 1.0) / 2.0;
                let ybar = x.iter().sum::<f64>() / nf;
                let mut sxy = 0.0;
                for (i, v) in x.iter().enumerate() {
                    sxy += (i as f64 - xbar) * (v - ybar);
                }
                let sxx = nf * (nf * nf - 1.0) / 12.0;
                let b = sxy / sxx;
                x.iter_mut()
                    .enumerate()
                    .for_each(|(i, v)| *v -= ybar + b * (i as f64 - xbar));
            }
        }
    }
}

/// Welch parameters. `overlap` is a fraction of `nperseg` in [0, 1).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WelchOptions {
    pub nperseg: usize,
    pub overlap: f64,
    pub window: Window,
    pub detrend: Detrend,
}

impl Default for WelchOptions {
    fn default() -> Self {
        WelchOptions {
            nperseg: 8192,
            overlap: 0.5,
            window: Window::Hann,
            detrend: Detrend::Constant,
        }
    }
}

/// Shortest Welch segment accepted: 16 samples give 9 lines (DC to Nyquist). Below it a
/// tapered window is mostly its own zero ends (a 1-sample Hann window is 0, so every PSD
/// would be 0) and the spectrum describes the window rather than the signal.
pub const MIN_NPERSEG: usize = 16;

/// The segment for a log shorter than the default one: the largest power of two that leaves
/// at least 4 segment lengths of signal (7 averages at 50% overlap, a PSD with ~2.6 degrees of
/// freedom per line rather than one raw periodogram), never below [`MIN_NPERSEG`].
pub fn short_log_nperseg(len: usize) -> usize {
    let mut n = MIN_NPERSEG;
    while 2 * n * 4 <= len {
        n *= 2;
    }
    n
}

/// Fewest Welch averages a default segment may leave: [`short_log_nperseg`]'s 4 segment
/// lengths of signal at 50% overlap.
pub const MIN_DEFAULT_AVERAGES: usize = 7;

/// A note when fewer than [`MIN_DEFAULT_AVERAGES`] segments were averaged: each line of a
/// Welch PSD then carries a normalised random error of about 1/√segments (Bendat & Piersol,
/// Random Data, §8.5.4), 38% at 7 and 100% for a single periodogram.
pub fn averages_note(segments: usize, samples: usize, nperseg: usize) -> Option<String> {
    if segments >= MIN_DEFAULT_AVERAGES || segments == 0 {
        return None;
    }
    let error = 100.0 / (segments as f64).sqrt();
    let shorter = short_log_nperseg(samples);
    let hint = if shorter < nperseg {
        format!("; --nperseg {shorter} averages at least {MIN_DEFAULT_AVERAGES}")
    } else {
        String::new()
    };
    Some(format!(
        "only {segments} segment(s) of {nperseg} samples averaged: each PSD line has a random error of about {error:.0}% (1/√segments){hint}"
    ))
}

/// Fewest lines a band must hold for its peaks and RMS to mean something.
pub const MIN_LINES_IN_BAND: usize = 16;

/// A note when `df` leaves fewer than [`MIN_LINES_IN_BAND`] lines in `lo..=hi` Hz, naming the
/// segment length that would give that many.
pub fn resolution_note(fs: f64, nperseg: usize, lo: f64, hi: f64) -> Option<String> {
    let df = fs / nperseg as f64;
    let lines = ((hi - lo) / df).floor() + 1.0;
    if !lines.is_finite() || lines >= MIN_LINES_IN_BAND as f64 || hi <= lo {
        return None;
    }
    let needed = (MIN_LINES_IN_BAND as f64 * fs / (hi - lo)).ceil();
    let df = round_to_micro(df);
    Some(format!(
        "nperseg {nperseg} gives {df} Hz lines: only {lines} line(s) in the band {lo:.3}–{hi:.3} Hz; \
         pass --nperseg {needed} or more to resolve it"
    ))
}

/// A line spacing to a millionth of a hertz, written without trailing zeros.
pub fn round_to_micro(hz: f64) -> f64 {
    (hz * 1e6).round() / 1e6
}

impl WelchOptions {
    pub fn noverlap(&self) -> usize {
        (self.overlap * self.nperseg as f64).floor() as usize
    }

    pub fn validate(&self) -> Result<(), SignalError> {
        if self.nperseg < MIN_NPERSEG {
            return Err(SignalError::BadParameter {
                name: "nperseg",
                value: self.nperseg.to_string(),
                reason: format!(
                    "must be at least {MIN_NPERSEG} samples (9 lines); a shorter segment measures its window, not the signal"
                ),
            });
        }
        if !(self.overlap.is_finite() && (0.0..1.0).contains(&self.overlap)) {
            return Err(SignalError::BadOverlap {
                overlap: self.overlap,
            });
        }
        Ok(())
    }

    fn step(&self) -> usize {
        self.nperseg - self.noverlap()
    }

    /// Number of one-sided frequency lines.
    pub fn lines(&self) -> usize {
        self.nperseg / 2 + 1
    }
}

/// A one-sided auto spectral density (units²/Hz) on lines `k·df`, k = 0..len.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Psd {
    pub fs: f64,
    pub df: f64,
    pub nperseg: usize,
    pub segments: usize,
    pub values: Vec<f64>,
}

impl Psd {
    pub fn frequencies(&self) -> Vec<f64> {
        (0..self.values.len()).map(|k| k as f64 * self.df).collect()
    }

    /// A spectrum given on uniform lines, e.g. read from a UFF58 PSD record.
    pub fn from_lines(df: f64, values: Vec<f64>) -> Psd {
        let nperseg = 2 * values.len().saturating_sub(1);
        Psd {
            fs: df * nperseg as f64,
            df,
            nperseg,
            segments: 0,
            values,
        }
    }
}

/// A one-sided cross spectral density Gxy = mean(conj(X)·Y)·scale (scipy.signal.csd(x, y)).
#[derive(Debug, Clone, PartialEq)]
pub struct CrossPsd {
    pub fs: f64,
    pub df: f64,
    pub nperseg: usize,
    pub segments: usize,
    pub values: Vec<Complex64>,
}

/// Auto and cross spectra of several channels computed in one pass.
#[derive(Debug, Clone, PartialEq)]
pub struct WelchResult {
    pub auto: Vec<Psd>,
    /// In the order of the `pairs` given to [`WelchStream::new`].
    pub cross: Vec<CrossPsd>,
}

/// Segments transformed per parallel block: enough to keep both cores busy, small enough that
/// the per-segment spectra of a block stay a few MB (memory must not grow with the log).
fn block_segments(nperseg: usize, channels: usize) -> usize {
    let per_seg = (nperseg / 2 + 1) * channels.max(1);
    (4_000_000 / per_seg.max(1)).clamp(8, 256)
}

/// Segments summed by one task before the runs are added in order (see `Engine::process`).
const SUM_RUN: usize = 8;

struct Engine {
    opts: WelchOptions,
    window: Vec<f64>,
    fft: Arc<dyn realfft::RealToComplex<f64>>,
    channels: usize,
    pairs: Vec<(usize, usize)>,
    auto: Vec<Vec<f64>>,
    cross: Vec<Vec<Complex64>>,
    segments: usize,
}

impl Engine {
    fn new(
        channels: usize,
        pairs: &[(usize, usize)],
        opts: &WelchOptions,
    ) -> Result<Engine, SignalError> {
        opts.validate()?;
        for &(a, b) in pairs {
            if a >= channels || b >= channels {
                return Err(SignalError::Invalid(format!(
                    "cross pair ({a}, {b}) out of {channels} channels"
                )));
            }
        }
        let nf = opts.lines();
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(opts.nperseg);
        Ok(Engine {
            window: opts.window.coefficients(opts.nperseg),
            opts: opts.clone(),
            fft,
            channels,
            pairs: pairs.to_vec(),
            auto: vec![vec![0.0; nf]; channels],
            cross: vec![vec![Complex64::new(0.0, 0.0); nf]; pairs.len()],
            segments: 0,
        })
    }

    /// Transforms the segments starting at `starts` of every channel (each a slice indexed
    /// from the same origin), then adds them in order.
    fn process(&mut self, data: &[&[f64]], starts: &[usize]) {
        let n = self.opts.nperseg;
        let nf = self.opts.lines();
        let channels = self.channels;
        let fft = &self.fft;
        let window = &self.window;
        let detrend = self.opts.detrend;
        let pairs = &self.pairs;
        // Segments are summed in fixed runs of SUM_RUN (by index within the block, never by
        // thread), then the runs are added in order: the result is independent of the thread
        // count and identical for a block processed in memory or from a stream.
        let results: Vec<(Vec<f64>, Vec<Complex64>)> = starts
            .par_chunks(SUM_RUN)
            .map_init(
                || {
                    (
                        fft.make_input_vec(),
                        fft.make_scratch_vec(),
                        vec![Complex64::new(0.0, 0.0); nf * channels],
                    )
                },
                |(input, scratch, spectra), run| {
                    let mut p = vec![0.0; nf * channels];
                    let mut x = vec![Complex64::new(0.0, 0.0); nf * pairs.len()];
                    for &s in run {
                        for (c, ch) in data.iter().enumerate() {
                            input.copy_from_slice(&ch[s..s + n]);
                            detrend.apply(input);
                            input
                                .iter_mut()
                                .zip(window.iter())
                                .for_each(|(v, w)| *v *= w);
                            // Lengths are fixed by construction; a failure is a bug, not bad input.
                            fft.process_with_scratch(
                                input,
                                &mut spectra[c * nf..(c + 1) * nf],
                                scratch,
                            )
                            .expect("realfft buffer lengths");
                        }
                        for c in 0..channels {
                            p[c * nf..(c + 1) * nf]
                                .iter_mut()
                                .zip(&spectra[c * nf..(c + 1) * nf])
                                .for_each(|(a, z)| *a += z.norm_sqr());
                        }
                        for (k, &(a, b)) in pairs.iter().enumerate() {
                            let (sa, sb) = (
                                &spectra[a * nf..(a + 1) * nf],
                                &spectra[b * nf..(b + 1) * nf],
                            );
                            x[k * nf..(k + 1) * nf]
                                .iter_mut()
                                .zip(sa.iter().zip(sb))
                                .for_each(|(acc, (za, zb))| *acc += za.conj() * zb);
                        }
                    }
                    (p, x)
                },
            )
            .collect();
        for (p, x) in results {
            for c in 0..channels {
                self.auto[c]
                    .iter_mut()
                    .zip(&p[c * nf..(c + 1) * nf])
                    .for_each(|(a, v)| *a += v);
            }
            for k in 0..pairs.len() {
                self.cross[k]
                    .iter_mut()
                    .zip(&x[k * nf..(k + 1) * nf])
                    .for_each(|(a, v)| *a += v);
            }
        }
        self.segments += starts.len();
    }

    fn finish(self, fs: f64, len: usize, names: &[String]) -> Result<WelchResult, SignalError> {
        if self.segments == 0 {
            let channel = names.first().cloned().unwrap_or_default();
            return Err(SignalError::SegmentTooLong {
                nperseg: self.opts.nperseg,
                len,
                channel,
                file: None,
            });
        }
        if !(fs.is_finite() && fs > 0.0) {
            return Err(SignalError::BadParameter {
                name: "fs",
                value: fs.to_string(),
                reason: "the sampling rate must be positive".into(),
            });
        }
        let n = self.opts.nperseg;
        let wss: f64 = self.window.iter().map(|w| w * w).sum();
        let scale = 1.0 / (fs * wss) / self.segments as f64;
        let last_doubled = if n % 2 == 1 { n / 2 } else { n / 2 - 1 };
        let factor = |k: usize| {
            if k >= 1 && k <= last_doubled {
                2.0
            } else {
                1.0
            }
        };
        let df = fs / n as f64;
        let segments = self.segments;
        let auto = self
            .auto
            .into_iter()
            .map(|v| Psd {
                fs,
                df,
                nperseg: n,
                segments,
                values: v
                    .iter()
                    .enumerate()
                    .map(|(k, p)| p * scale * factor(k))
                    .collect(),
            })
            .collect();
        let cross = self
            .cross
            .into_iter()
            .map(|v| CrossPsd {
                fs,
                df,
                nperseg: n,
                segments,
                values: v
                    .iter()
                    .enumerate()
                    .map(|(k, p)| p * (scale * factor(k)))
                    .collect(),
            })
            .collect();
        Ok(WelchResult { auto, cross })
    }
}

/// Welch spectra of channels held in memory (all of the same length).
pub fn welch_multi(
    channels: &[&[f64]],
    pairs: &[(usize, usize)],
    fs: f64,
    opts: &WelchOptions,
) -> Result<WelchResult, SignalError> {
    opts.validate()?;
    let len = channels.iter().map(|c| c.len()).min().unwrap_or(0);
    // Checked before the engine exists: its sums and FFT plan are sized by nperseg, which a
    // mistyped option could make enormous.
    if len < opts.nperseg {
        return Err(SignalError::SegmentTooLong {
            nperseg: opts.nperseg,
            len,
            channel: String::new(),
            file: None,
        });
    }
    let mut engine = Engine::new(channels.len(), pairs, opts)?;
    let starts: Vec<usize> = if len >= opts.nperseg {
        (0..=(len - opts.nperseg) / opts.step())
            .map(|i| i * opts.step())
            .collect()
    } else {
        Vec::new()
    };
    for block in starts.chunks(block_segments(opts.nperseg, channels.len())) {
        engine.process(channels, block);
    }
    engine.finish(fs, len, &[])
}

/// Welch PSD of one channel, as `scipy.signal.welch(x, fs, window, nperseg, noverlap, detrend)`.
pub fn welch(x: &[f64], fs: f64, opts: &WelchOptions) -> Result<Psd, SignalError> {
    let mut r = welch_multi(&[x], &[], fs, opts)?;
    Ok(r.auto.remove(0))
}

/// Auto spectra Gxx, Gyy and the cross spectrum Gxy of two channels.
pub fn csd(
    x: &[f64],
    y: &[f64],
    fs: f64,
    opts: &WelchOptions,
) -> Result<(Psd, Psd, CrossPsd), SignalError> {
    let mut r = welch_multi(&[x, y], &[(0, 1)], fs, opts)?;
    let gxy = r.cross.remove(0);
    let gyy = r.auto.remove(1);
    let gxx = r.auto.remove(0);
    Ok((gxx, gyy, gxy))
}

/// Welch estimator fed one sample row at a time; holds at most one block of samples per
/// channel, so memory stays flat however long the log is.
pub struct WelchStream {
    /// Built at the first full segment, so that an `nperseg` larger than the log costs nothing.
    engine: Option<Engine>,
    opts: WelchOptions,
    pairs: Vec<(usize, usize)>,
    buffers: Vec<Vec<f64>>,
    need: usize,
    consumed: usize,
    names: Vec<String>,
}

impl WelchStream {
    pub fn new(
        names: &[String],
        pairs: &[(usize, usize)],
        opts: &WelchOptions,
    ) -> Result<WelchStream, SignalError> {
        if names.is_empty() {
            return Err(SignalError::Invalid(
                "a Welch stream needs at least one channel".into(),
            ));
        }
        opts.validate()?;
        if let Some(&(a, b)) = pairs
            .iter()
            .find(|&&(a, b)| a >= names.len() || b >= names.len())
        {
            return Err(SignalError::Invalid(format!(
                "cross pair ({a}, {b}) out of {} channels",
                names.len()
            )));
        }
        let block = block_segments(opts.nperseg, names.len());
        let need = opts
            .nperseg
            .saturating_add((block - 1).saturating_mul(opts.step()));
        Ok(WelchStream {
            engine: None,
            opts: opts.clone(),
            pairs: pairs.to_vec(),
            buffers: vec![Vec::new(); names.len()],
            need,
            consumed: 0,
            names: names.to_vec(),
        })
    }

    /// Appends one sample per channel.
    pub fn push_row(&mut self, row: &[f64]) {
        for (b, v) in self.buffers.iter_mut().zip(row) {
            b.push(*v);
        }
        if self.buffers.first().is_some_and(|b| b.len() >= self.need) {
            // Cannot fail: `new` checked the options and the pairs that `Engine::new` checks.
            let _ = self.flush();
        }
    }

    fn flush(&mut self) -> Result<(), SignalError> {
        let n = self.opts.nperseg;
        let step = self.opts.step();
        let len = self.buffers.first().map_or(0, |b| b.len());
        if len < n {
            return Ok(());
        }
        if self.engine.is_none() {
            self.engine = Some(Engine::new(self.names.len(), &self.pairs, &self.opts)?);
        }
        let Some(engine) = self.engine.as_mut() else {
            return Ok(());
        };
        let count = (len - n) / step + 1;
        let starts: Vec<usize> = (0..count).map(|i| i * step).collect();
        let views: Vec<&[f64]> = self.buffers.iter().map(|b| b.as_slice()).collect();
        engine.process(&views, &starts);
        let drop = count * step;
        for b in &mut self.buffers {
            b.drain(..drop.min(b.len()));
        }
        self.consumed += drop;
        Ok(())
    }

    /// Samples pushed so far per channel.
    pub fn len(&self) -> usize {
        self.consumed + self.buffers.first().map_or(0, |b| b.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn finish(mut self, fs: f64) -> Result<WelchResult, SignalError> {
        self.flush()?;
        let len = self.len();
        match self.engine {
            Some(engine) => engine.finish(fs, len, &self.names),
            None => Err(SignalError::SegmentTooLong {
                nperseg: self.opts.nperseg,
                len,
                channel: self.names.first().cloned().unwrap_or_default(),
                file: None,
            }),
        }
    }
}

impl Psd {
    /// Root of the trapezoidal integral over all lines (the Grms of a g²/Hz spectrum).
    pub fn rms(&self) -> f64 {
        super::bands::rms_of(&self.frequencies(), &self.values)
    }

    /// RMS within `[f_lo, f_hi]`, band edges interpolated between lines.
    pub fn band_rms(&self, f_lo: f64, f_hi: f64) -> f64 {
        super::bands::band_rms(&self.frequencies(), &self.values, f_lo, f_hi)
    }
}
