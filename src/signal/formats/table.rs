//! Columns read whole by a format reader (LabVIEW `.lvm`, MATLAB `.mat`) to a [`Log`]: the
//! caller's channel selection, units and sampling rate applied the way the CSV reader applies
//! them, with the same errors.

use crate::error::SignalError;
use crate::signal::ingest::{
    ChannelInfo, FS_AGREEMENT, IngestOptions, IngestRecord, Log, LogInfo, TimeUnit, Unit,
    UnitSource,
};
use std::path::Path;

/// An error at a line of a text format, prefixed by the format's name (`LVM: …`).
pub fn at_line(path: &Path, line: usize, format: &str, message: impl Into<String>) -> SignalError {
    SignalError::AtLine {
        file: path.to_path_buf(),
        line: line as u64,
        message: format!("{format}: {}", message.into()),
    }
}

/// One data column as a format reader found it.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub name: String,
    /// Unit label stated by the file for this column (`g`, `m/s^2`, `Volts`); empty if none.
    pub unit_label: String,
    pub values: Vec<f64>,
}

/// Where the file's sampling rate came from.
#[derive(Debug, Clone, PartialEq)]
pub enum Rate {
    /// The file states it (a header field, a scalar variable): Hz and where.
    Stated(f64, String),
    /// A time vector: the times in seconds and its name.
    Times(Vec<f64>, String),
    /// Nothing: `--fs` is needed.
    Unknown,
}

/// What a format reader hands over.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub format: &'static str,
    pub delimiter: &'static str,
    pub decimal: &'static str,
    pub series: Vec<Series>,
    pub rate: Rate,
    /// Columns or variables not read, and why (said once on stderr).
    pub ignored: Vec<String>,
    /// Channels found but not readable at this log's rate and length (a slower channel, a
    /// shorter vector): name and why. Asking for one by name is an error giving the reason.
    pub unreadable: Vec<(String, String)>,
    pub notes: Vec<String>,
    /// What the file itself says is wrong with it (a count it announces and does not hold):
    /// the data read is analysed, and the warning goes with every result.
    pub warnings: Vec<String>,
}

/// The unit of a column: a `--units` entry for it, then the unit label the file gives (`g`,
/// `m/s2`), then its name, then the default unit of the read; a column the file states in
/// volts keeps them (see [`crate::signal::ingest::unit::is_electrical`]).
fn unit_of(s: &Series, opts: &IngestOptions) -> (Unit, UnitSource) {
    if let Some((_, u)) = opts.channel_units.iter().find(|(n, _)| *n == s.name) {
        return (*u, UnitSource::Option);
    }
    let stated = Unit::parse(&s.unit_label).ok().filter(|u| *u != Unit::AsIs);
    if let Some(u) = stated.or_else(|| Unit::from_name(&s.name)) {
        return (u, UnitSource::Name);
    }
    if crate::signal::ingest::unit::is_electrical(&s.unit_label) {
        return (Unit::AsIs, UnitSource::Name);
    }
    match opts.default_unit {
        Some(u) => (u, UnitSource::Option),
        None => (Unit::AsIs, UnitSource::Default),
    }
}

/// The sampling rate: the file's, checked against `--fs`; `--fs` alone when the file states
/// none; `--fs-override` makes `--fs` win.
fn sampling_rate(path: &Path, rate: &Rate, opts: &IngestOptions) -> Result<f64, SignalError> {
    if let (true, Some(fs)) = (opts.fs_override, opts.fs)
        && fs.is_finite()
        && fs > 0.0
    {
        return crate::signal::ingest::plausible_rate(path, fs, opts.fs_name);
    }
    let stated = match rate {
        Rate::Stated(fs, _) => Some(*fs),
        Rate::Times(t, name) => Some(rate_of_times(path, t, name, opts.jitter_tolerance)?),
        Rate::Unknown => None,
    };
    let fs = match (stated, opts.fs) {
        (Some(s), Some(f)) if !opts.fs_override && (s - f).abs() > FS_AGREEMENT * f => {
            let stated = format!(
                "{} of {}, which gives {s:.6} Hz",
                rate_source(rate),
                path.display()
            );
            return Err(crate::signal::ingest::fs_disagrees(
                opts.fs_name,
                f,
                &stated,
            ));
        }
        (_, Some(f)) => f,
        (Some(s), None) => s,
        (None, None) => {
            return Err(SignalError::NoSamplingRate {
                file: path.to_path_buf(),
            });
        }
    };
    if fs.is_finite() && fs > 0.0 {
        let source = if opts.fs == Some(fs) {
            opts.fs_name.to_string()
        } else {
            rate_source(rate)
        };
        crate::signal::ingest::plausible_rate(path, fs, &source)
    } else {
        Err(SignalError::NoSamplingRate {
            file: path.to_path_buf(),
        })
    }
}

fn rate_source(rate: &Rate) -> String {
    match rate {
        Rate::Stated(_, from) => from.clone(),
        Rate::Times(_, name) => format!("the time vector `{name}`"),
        Rate::Unknown => "nothing".into(),
    }
}

/// Sample intervals written by one clock (a `Delta_X`, a `wf_increment`) agree to the last
/// bits.
pub fn same_interval(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// The interval most of `intervals` share, the first one's on a tie, with the index of the
/// first interval holding it.
pub fn most_common_interval(intervals: &[f64]) -> Option<(f64, usize)> {
    let mut counts: Vec<(f64, usize, usize)> = Vec::new();
    for (i, &dt) in intervals.iter().enumerate() {
        match counts.iter_mut().find(|c| same_interval(c.0, dt)) {
            Some(c) => c.1 += 1,
            None => counts.push((dt, 1, i)),
        }
    }
    let most = counts.iter().map(|c| c.1).max()?;
    counts.iter().find(|c| c.1 == most).map(|c| (c.0, c.2))
}

/// Keeps the series of the time vector's length (`times`: its length and name), else of the
/// most common length (the longer on a tie), and lists the others as unreadable.
pub fn keep_common_length(
    series: &mut Vec<Series>,
    unreadable: &mut Vec<(String, String)>,
    times: Option<(usize, &str)>,
) {
    let (len, of_what) = match times {
        Some((len, name)) => (len, format!("the time vector `{name}`")),
        None => {
            let mut counts: Vec<(usize, usize)> = Vec::new();
            for s in series.iter() {
                match counts.iter_mut().find(|(l, _)| *l == s.values.len()) {
                    Some(c) => c.1 += 1,
                    None => counts.push((s.values.len(), 1)),
                }
            }
            let len = counts
                .iter()
                .max_by_key(|(l, n)| (*n, *l))
                .map_or(0, |c| c.0);
            (len, "most channels".to_string())
        }
    };
    let (keep, drop): (Vec<Series>, Vec<Series>) = std::mem::take(series)
        .into_iter()
        .partition(|s| s.values.len() == len);
    for s in drop {
        let why = format!("{} samples, not the {len} of {of_what}", s.values.len());
        unreadable.push((s.name, why));
    }
    *series = keep;
}

/// Rate of a time vector: increasing, every step within `tol` of the mean step (a non-uniform
/// vector is refused: these formats are read whole and not resampled).
fn rate_of_times(path: &Path, t: &[f64], name: &str, tol: f64) -> Result<f64, SignalError> {
    let bad = |message: String| SignalError::Unsupported {
        file: path.to_path_buf(),
        message: format!("time vector `{name}`: {message}"),
    };
    if t.len() < 2 {
        return Err(bad("fewer than two times".into()));
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    for (k, w) in t.windows(2).enumerate() {
        let step = w[1] - w[0];
        // A NaN step fails this test too.
        if step.is_nan() || step <= 0.0 {
            return Err(bad(format!(
                "sample {} at {} s does not follow {} s",
                k + 2,
                w[1],
                w[0]
            )));
        }
        if (step - dt).abs() > tol * dt {
            return Err(bad(format!(
                "step {step:e} s at sample {} departs from the mean step {dt:e} s by more than {}%: the samples are not uniform; pass --fs F --fs-override to take them as uniform at F Hz",
                k + 2,
                tol * 100.0
            )));
        }
    }
    Ok(1.0 / dt)
}

/// Where the channel `name` is among the series read; a channel the reader found but could
/// not read says why.
fn channel_index(path: &Path, t: &Table, name: &str) -> Result<usize, SignalError> {
    if let Some(i) = t.series.iter().position(|s| s.name == name) {
        return Ok(i);
    }
    if let Some((_, why)) = t.unreadable.iter().find(|(n, _)| n == name) {
        return Err(SignalError::Unsupported {
            file: path.to_path_buf(),
            message: format!("channel `{name}` cannot be read with the others: {why}"),
        });
    }
    Err(SignalError::NoSuchChannel {
        file: path.to_path_buf(),
        name: name.to_string(),
        available: t
            .series
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", "),
    })
}

/// Picks the channels asked for (all by default), converts them to their reported unit, and
/// describes the read.
pub fn table_to_log(path: &Path, t: Table, opts: &IngestOptions) -> Result<Log, SignalError> {
    let fs = sampling_rate(path, &t.rate, opts)?;
    let chosen: Vec<usize> = match &opts.channels {
        Some(list) => list
            .iter()
            .map(|n| channel_index(path, &t, n))
            .collect::<Result<_, _>>()?,
        None => (0..t.series.len()).collect(),
    };
    let mut t = t;
    t.ignored.extend(
        t.unreadable
            .iter()
            .map(|(name, why)| format!("`{name}` ({why})")),
    );
    if chosen.is_empty() {
        return Err(SignalError::Unsupported {
            file: path.to_path_buf(),
            message: format!(
                "no channel to read in this {} file (not read: {})",
                t.format,
                if t.ignored.is_empty() {
                    "nothing".to_string()
                } else {
                    t.ignored.join("; ")
                }
            ),
        });
    }
    let samples = t.series[chosen[0]].values.len();
    let mut channels = Vec::new();
    let mut data = Vec::new();
    for &i in &chosen {
        let s = &t.series[i];
        if s.values.len() != samples {
            return Err(SignalError::Unsupported {
                file: path.to_path_buf(),
                message: format!(
                    "channel `{}` holds {} samples, `{}` {samples}: channels of one log must have the same length",
                    s.name,
                    s.values.len(),
                    t.series[chosen[0]].name
                ),
            });
        }
        if let Some(k) = s.values.iter().position(|v| !v.is_finite()) {
            return Err(SignalError::Unsupported {
                file: path.to_path_buf(),
                message: format!(
                    "channel `{}`: sample {} of {} is {}: a log must hold finite numbers",
                    s.name,
                    k + 1,
                    s.values.len(),
                    s.values[k]
                ),
            });
        }
        let (unit, unit_source) = unit_of(s, opts);
        let k = unit.to_report_factor();
        let unit_label = match unit {
            Unit::AsIs => crate::signal::ingest::unit::kept_label(&s.unit_label),
            _ => String::new(),
        };
        channels.push(ChannelInfo {
            name: s.name.clone(),
            unit,
            unit_source,
            column: i,
            unit_label,
            stated_label: s.unit_label.clone(),
        });
        data.push(s.values.iter().map(|v| v * k).collect());
    }
    let overridden = opts.fs_override && opts.fs.is_some();
    let mut notes = t.notes;
    notes.extend(crate::signal::ingest::electrical_notes(&channels, opts));
    if overridden && !matches!(t.rate, Rate::Unknown) {
        notes.push(format!(
            "{}: {} ignored: --fs-override uses --fs {fs} Hz",
            path.display(),
            rate_source(&t.rate)
        ));
    }
    let (time_column, time_unit) = match &t.rate {
        Rate::Times(_, name) if !overridden => (Some(name.clone()), Some(TimeUnit::S)),
        _ => (None, None),
    };
    if !t.ignored.is_empty() {
        notes.push(format!(
            "{}: not read: {}",
            path.display(),
            t.ignored.join("; ")
        ));
    }
    let info = LogInfo {
        file: path.to_path_buf(),
        channels,
        time_column: time_column.clone(),
        fs_hz: fs,
        samples: samples as u64,
        resampled: None,
        ingest: IngestRecord {
            delimiter: t.delimiter,
            decimal: t.decimal,
            skipped_lines: 0,
            time_column,
            time_unit,
            ignored_columns: t.ignored,
            metadata: Vec::new(),
            jitter: None,
            notes,
            warnings: t.warnings,
        },
    };
    Ok(Log { info, data })
}
