//! The time column of a streamed log: its steps are checked, its jitter measured, and with
//! `resample` the rows are interpolated onto a uniform grid (then, with a target rate, band-
//! limited onto that rate by [`BandLimited`]).
//!
//! A step within the tolerance of the sampling interval is regular. A step within
//! ±[`JITTER_LIMIT`] of it is jitter, as loggers that stamp rows with a wall clock write: the
//! log is analysed at its mean step (the span over the steps) and the jitter is reported. A
//! longer step is a gap (a missing stretch) and a shorter one a change of rate: both are
//! located errors unless `resample` interpolates through the timestamps.

use super::bandlimit::{AntiAliasReport, BandLimited};
use super::{IngestOptions, ResampleReport};
use crate::error::SignalError;
use std::path::PathBuf;

/// Rows kept before the sampling interval is fixed: the median of their steps is robust to one
/// odd step at the start of the log.
const PRIME_ROWS: usize = 33;

/// Largest relative difference between `--fs` and a rate the log states (its time column, a
/// header field, a preamble line) before it is an error.
pub const FS_AGREEMENT: f64 = 1e-3;

/// Largest step, in sampling intervals, that `resample` bridges by interpolation.
const MAX_RESAMPLE_GAP: f64 = 100.0;

/// Largest departure of a step from the sampling interval read as jitter, as a fraction of it:
/// loggers stamping rows with a wall clock vary by up to ±40%; one missing row is +100%.
pub const JITTER_LIMIT: f64 = 0.5;

/// The jitter of a time column whose steps vary around their mean.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct JitterReport {
    /// Steps departing from the interval by more than the tolerance (but within the limit).
    pub jittered_steps: u64,
    pub first_jittered_line: u64,
    /// Span over steps: the interval the log is analysed with (unless resampled).
    pub mean_step_s: f64,
    /// RMS departure of the steps from their mean, % of it.
    pub rms_deviation_pct: f64,
    /// Largest departure of a step from the mean, % of it.
    pub max_deviation_pct: f64,
}

/// What the time column gave: the rate and count of the rows handed on, and the reports.
pub struct TimingOutcome {
    pub fs_hz: f64,
    pub samples: u64,
    pub resampled: Option<ResampleReport>,
    pub jitter: Option<JitterReport>,
}

/// Running statistics of the steps (Welford), for the jitter report.
#[derive(Default)]
struct StepStats {
    n: u64,
    mean: f64,
    m2: f64,
    min: f64,
    max: f64,
    jittered: u64,
    first_jittered: u64,
}

impl StepStats {
    fn add(&mut self, step: f64) {
        if self.n == 0 {
            (self.min, self.max) = (step, step);
        }
        self.n += 1;
        let d = step - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (step - self.mean);
        self.min = self.min.min(step);
        self.max = self.max.max(step);
    }

    fn report(&self) -> Option<JitterReport> {
        (self.jittered > 0 && self.n > 0).then(|| JitterReport {
            jittered_steps: self.jittered,
            first_jittered_line: self.first_jittered,
            mean_step_s: self.mean,
            rms_deviation_pct: 100.0 * (self.m2 / self.n as f64).sqrt() / self.mean,
            max_deviation_pct: 100.0 * (self.max - self.mean).max(self.mean - self.min) / self.mean,
        })
    }
}

/// Time-column checks and, with `resample`, streaming interpolation onto a uniform grid.
pub struct Timing {
    file: PathBuf,
    resample: bool,
    tol: f64,
    fs_option: Option<f64>,
    /// Where `fs_option` came from, as errors name it ([`IngestOptions::fs_name`]).
    fs_name: &'static str,
    target_fs: Option<f64>,
    band: Option<BandLimited>,
    primed: Vec<(f64, u64, Vec<f64>)>,
    dt: f64,
    t0: f64,
    prev: Option<f64>,
    prev_row: Vec<f64>,
    rows: u64,
    emitted: u64,
    irregular: u64,
    first_irregular: u64,
    largest: f64,
    last_t: f64,
    steps: StepStats,
    out: Vec<f64>,
}

impl Timing {
    pub fn new(opts: &IngestOptions, file: PathBuf) -> Timing {
        Timing {
            file,
            resample: opts.resample || opts.resample_fs.is_some(),
            tol: opts.jitter_tolerance,
            fs_option: opts.fs,
            fs_name: opts.fs_name,
            target_fs: opts.resample_fs,
            band: None,
            primed: Vec::new(),
            dt: 0.0,
            t0: 0.0,
            prev: None,
            prev_row: Vec::new(),
            rows: 0,
            emitted: 0,
            irregular: 0,
            first_irregular: 0,
            largest: 0.0,
            last_t: 0.0,
            steps: StepStats::default(),
            out: Vec::new(),
        }
    }

    pub fn push(
        &mut self,
        t: f64,
        line: u64,
        row: &[f64],
        sink: &mut impl FnMut(&[f64]),
    ) -> Result<(), SignalError> {
        if let Some(pt) = self.primed.last().map(|p| p.0).or(self.prev)
            && t <= pt
        {
            return Err(SignalError::NonMonotonicTime {
                file: self.file.clone(),
                line,
                time: t,
                previous: pt,
            });
        }
        self.rows += 1;
        self.last_t = t;
        if self.dt == 0.0 {
            self.primed.push((t, line, row.to_vec()));
            if self.primed.len() == PRIME_ROWS {
                self.start(sink)?;
            }
            return Ok(());
        }
        self.accept(t, line, row, sink)
    }

    fn start(&mut self, sink: &mut impl FnMut(&[f64])) -> Result<(), SignalError> {
        let primed = std::mem::take(&mut self.primed);
        let mut steps: Vec<f64> = primed.windows(2).map(|w| w[1].0 - w[0].0).collect();
        steps.sort_by(|a, b| a.total_cmp(b));
        // Steps are checked against the time column's own interval; `--fs` is compared with
        // the whole span at the end, where rounding of the times no longer matters.
        self.dt = match (steps.get(steps.len() / 2), self.fs_option) {
            (Some(&dt), _) => dt,
            (None, Some(fs)) => 1.0 / fs,
            (None, None) => 1.0,
        };
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(SignalError::NoSamplingRate {
                file: self.file.clone(),
            });
        }
        self.band = self.target_fs.map(|f| BandLimited::new(1.0 / self.dt, f));
        self.t0 = primed.first().map_or(0.0, |p| p.0);
        for (t, line, row) in primed {
            self.accept(t, line, &row, sink)?;
        }
        Ok(())
    }

    fn accept(
        &mut self,
        t: f64,
        line: u64,
        row: &[f64],
        sink: &mut impl FnMut(&[f64]),
    ) -> Result<(), SignalError> {
        let Some(pt) = self.prev else {
            emit(&mut self.band, row, sink);
            self.emitted = 1;
            self.prev = Some(t);
            self.prev_row.clear();
            self.prev_row.extend_from_slice(row);
            return Ok(());
        };
        let step = t - pt;
        self.check_step(step, line)?;
        self.largest = self.largest.max(step);
        self.steps.add(step);
        if self.resample {
            self.interpolate(pt, step, t, row, sink);
        } else {
            emit(&mut self.band, row, sink);
            self.emitted += 1;
        }
        self.prev = Some(t);
        self.prev_row.clear();
        self.prev_row.extend_from_slice(row);
        Ok(())
    }

    /// Classifies one step: regular, jitter (counted), or beyond jitter (an error unless
    /// resampling, and then an error past the largest gap bridged).
    fn check_step(&mut self, step: f64, line: u64) -> Result<(), SignalError> {
        let off = (step - self.dt).abs();
        if off <= self.tol * self.dt {
            return Ok(());
        }
        if self.irregular == 0 {
            self.first_irregular = line;
        }
        self.irregular += 1;
        if off <= JITTER_LIMIT * self.dt {
            if self.steps.jittered == 0 {
                self.steps.first_jittered = line;
            }
            self.steps.jittered += 1;
            return Ok(());
        }
        if !self.resample {
            return Err(SignalError::NonUniformTime {
                file: self.file.clone(),
                line,
                dt: step,
                expected_dt: self.dt,
                jitter_pct: JITTER_LIMIT * 100.0,
            });
        }
        // Interpolating across a gap of many intervals would invent data (and a gap of 1e9
        // intervals would never end); a step far shorter than the grid's would be decimated
        // by the interpolation with no anti-alias filter.
        if step.is_nan() || step > MAX_RESAMPLE_GAP * self.dt {
            return Err(SignalError::ResampleGap {
                file: self.file.clone(),
                line,
                dt: step,
                expected_dt: self.dt,
                max_steps: MAX_RESAMPLE_GAP,
            });
        }
        if step < (1.0 - JITTER_LIMIT) * self.dt {
            return Err(SignalError::ResampleFaster {
                file: self.file.clone(),
                line,
                dt: step,
                expected_dt: self.dt,
            });
        }
        Ok(())
    }

    /// Emits every grid time in (pt, t] by linear interpolation between the two rows.
    fn interpolate(
        &mut self,
        pt: f64,
        step: f64,
        t: f64,
        row: &[f64],
        sink: &mut impl FnMut(&[f64]),
    ) {
        loop {
            let tg = self.t0 + self.emitted as f64 * self.dt;
            if tg > t + 1e-9 * self.dt {
                break;
            }
            let a = ((tg - pt) / step).clamp(0.0, 1.0);
            self.out.clear();
            self.out
                .extend(self.prev_row.iter().zip(row).map(|(p, v)| p + a * (v - p)));
            emit(&mut self.band, &self.out, sink);
            self.emitted += 1;
        }
    }

    pub fn finish(mut self, sink: &mut impl FnMut(&[f64])) -> Result<TimingOutcome, SignalError> {
        if self.dt == 0.0 {
            if self.primed.len() < 2 && self.fs_option.is_none() {
                return Err(SignalError::NoSamplingRate {
                    file: self.file.clone(),
                });
            }
            self.start(sink)?;
        }
        let anti_alias = self.band.as_mut().map(|b| {
            b.finish(sink);
            b.report()
        });
        let resampled = self.resample && (self.irregular > 0 || anti_alias.is_some());
        let fs = match (resampled, self.target_fs) {
            (true, Some(f)) => f,
            (true, None) => 1.0 / self.dt,
            (false, _) => self.rate_of_span()?,
        };
        if !(fs.is_finite() && fs > 0.0) {
            return Err(SignalError::NoSamplingRate {
                file: self.file.clone(),
            });
        }
        let fs = super::plausible_rate(&self.file, fs, "the time column or --fs")?;
        let samples = self.band.as_ref().map_or(self.emitted, |b| b.emitted);
        let report = resampled.then(|| self.resample_report(samples, anti_alias));
        Ok(TimingOutcome {
            fs_hz: fs,
            samples,
            resampled: report,
            jitter: self.steps.report(),
        })
    }

    /// The rate of rows taken as they are: `--fs` when it agrees with the time column, else
    /// the span over the steps (which also averages jitter out).
    fn rate_of_span(&self) -> Result<f64, SignalError> {
        let from_time = (self.rows - 1) as f64 / (self.last_t - self.t0);
        let Some(fs) = self.fs_option else {
            return Ok(from_time);
        };
        if self.rows > 1 && (from_time - fs).abs() > FS_AGREEMENT * fs {
            let stated = format!(
                "the time column of {}, which gives {from_time:.6} Hz",
                self.file.display()
            );
            return Err(super::fs_disagrees(self.fs_name, fs, &stated));
        }
        Ok(fs)
    }

    fn resample_report(&self, samples: u64, anti_alias: Option<AntiAliasReport>) -> ResampleReport {
        ResampleReport {
            uniform_dt_s: self.target_fs.map_or(self.dt, |f| 1.0 / f),
            irregular_rows: self.irregular,
            first_irregular_line: self.first_irregular,
            largest_step_s: self.largest,
            input_rows: self.rows,
            output_samples: samples,
            anti_alias,
        }
    }
}

/// Hands a row on: straight to the sink, or through the band-limited resampler.
fn emit(band: &mut Option<BandLimited>, row: &[f64], sink: &mut impl FnMut(&[f64])) {
    match band {
        Some(b) => b.push(row, sink),
        None => sink(row),
    }
}
