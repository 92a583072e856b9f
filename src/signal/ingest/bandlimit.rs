//! Band-limited resampling of a uniform stream onto another uniform rate: each output sample
//! is a Blackman-windowed sinc low-pass evaluated at the output time, so the anti-alias filter
//! and the interpolation are one step. Linear phase with no delay (the kernel is centred on the
//! output time), streamed: only the kernel's span of input rows is held.
//!
//! The low-pass passes up to 0.4 and stops from 0.5 of the lower of the two rates: a Blackman
//! window's transition width is 5.5 / taps (in units of the input rate) and its stop band is
//! 74 dB down (Smith, *The Scientist and Engineer's Guide to DSP*, ch. 16), so the taps are
//! chosen for a transition of 0.1 of that rate.

use std::collections::VecDeque;

/// Fraction of the lower rate below which the filter passes the signal.
pub const PASSBAND_FRACTION: f64 = 0.4;
/// Fraction of the lower rate (its Nyquist frequency) from which the filter stops it.
pub const STOPBAND_FRACTION: f64 = 0.5;
/// Stop-band attenuation of a Blackman-windowed sinc, dB.
pub const STOPBAND_ATTENUATION_DB: f64 = 74.0;
/// Transition width of a Blackman-windowed sinc times its length, in units of the input rate.
const BLACKMAN_TRANSITION_TAPS: f64 = 5.5;

/// The anti-alias filter applied while resampling, as reported.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AntiAliasReport {
    pub filter: &'static str,
    pub passband_hz: f64,
    pub stopband_hz: f64,
    pub stopband_attenuation_db: f64,
    pub taps: usize,
}

/// Resamples rows arriving at `fs_in` onto `fs_out`, the first output at the first input time.
pub struct BandLimited {
    /// Output interval in input intervals.
    ratio: f64,
    /// Kernel half-width, input intervals.
    half: usize,
    /// Cut-off, cycles per input interval.
    cutoff: f64,
    rows: VecDeque<Vec<f64>>,
    /// Input index of `rows[0]`.
    first: u64,
    received: u64,
    pub emitted: u64,
    out: Vec<f64>,
    report: AntiAliasReport,
}

impl BandLimited {
    pub fn new(fs_in: f64, fs_out: f64) -> BandLimited {
        let lower = fs_in.min(fs_out);
        let transition = (STOPBAND_FRACTION - PASSBAND_FRACTION) * lower / fs_in;
        let half = (BLACKMAN_TRANSITION_TAPS / transition / 2.0).ceil() as usize;
        let cutoff = 0.5 * (PASSBAND_FRACTION + STOPBAND_FRACTION) * lower / fs_in;
        BandLimited {
            ratio: fs_in / fs_out,
            half,
            cutoff,
            rows: VecDeque::new(),
            first: 0,
            received: 0,
            emitted: 0,
            out: Vec::new(),
            report: AntiAliasReport {
                filter: "Blackman-windowed sinc, linear phase",
                passband_hz: PASSBAND_FRACTION * lower,
                stopband_hz: STOPBAND_FRACTION * lower,
                stopband_attenuation_db: STOPBAND_ATTENUATION_DB,
                taps: 2 * half + 1,
            },
        }
    }

    pub fn report(&self) -> AntiAliasReport {
        self.report.clone()
    }

    pub fn push(&mut self, row: &[f64], sink: &mut impl FnMut(&[f64])) {
        self.rows.push_back(row.to_vec());
        self.received += 1;
        self.drain(false, sink);
    }

    /// Emits the outputs left at the end; their kernels are cut at the last input row.
    pub fn finish(&mut self, sink: &mut impl FnMut(&[f64])) {
        self.drain(true, sink);
    }

    fn drain(&mut self, at_end: bool, sink: &mut impl FnMut(&[f64])) {
        while let Some(last) = self.received.checked_sub(1) {
            let centre = self.emitted as f64 * self.ratio;
            if centre > last as f64 + 1e-9 {
                return;
            }
            let hi = centre.floor() as u64 + self.half as u64;
            if !at_end && hi > last {
                return;
            }
            self.emit(centre, hi.min(last), sink);
            let next_lo =
                ((self.emitted as f64 * self.ratio).ceil() as u64).saturating_sub(self.half as u64);
            while self.first < next_lo && !self.rows.is_empty() {
                self.rows.pop_front();
                self.first += 1;
            }
        }
    }

    /// One output at `centre` (input intervals) from inputs up to `hi`. The weights are
    /// normalised by their sum: a constant passes exactly, also where the kernel is cut at the
    /// ends of the log.
    fn emit(&mut self, centre: f64, hi: u64, sink: &mut impl FnMut(&[f64])) {
        let lo = (centre.ceil() as u64)
            .saturating_sub(self.half as u64)
            .max(self.first);
        let width = self.rows.front().map_or(0, Vec::len);
        self.out.clear();
        self.out.resize(width, 0.0);
        let mut wsum = 0.0;
        for k in lo..=hi {
            let w = self.kernel(centre - k as f64);
            wsum += w;
            let row = &self.rows[(k - self.first) as usize];
            for (o, v) in self.out.iter_mut().zip(row) {
                *o += w * v;
            }
        }
        for o in &mut self.out {
            *o /= wsum;
        }
        sink(&self.out);
        self.emitted += 1;
    }

    /// Windowed-sinc weight at offset `tau` input intervals from the output time.
    fn kernel(&self, tau: f64) -> f64 {
        let x = tau / (self.half as f64 + 1.0);
        if x.abs() >= 1.0 {
            return 0.0;
        }
        let pi = std::f64::consts::PI;
        let window = 0.42 + 0.5 * (pi * x).cos() + 0.08 * (2.0 * pi * x).cos();
        let arg = 2.0 * self.cutoff * tau;
        let sinc = if arg == 0.0 {
            1.0
        } else {
            (pi * arg).sin() / (pi * arg)
        };
        2.0 * self.cutoff * sinc * window
    }
}
