//! The options every log-reading command shares: how to read a log (`LogArgs`, with the
//! dialect flags) and how to average it (`WelchArgs`). Flattened into each command's
//! arguments so the flags, their help and their parsing are written once.

use satqual::Error;
use satqual::signal::ingest::{IngestOptions, LogInfo, TimeUnit, Unit};
use satqual::signal::{Detrend, WelchOptions, Window};

/// How to read a log: sampling rate, units, resampling and the dialect flags.
#[derive(clap::Args, Debug, Clone)]
pub struct LogArgs {
    /// Sampling rate, Hz (needed without a time column).
    #[arg(long)]
    pub fs: Option<f64>,
    /// `g`, `m/s2` for every channel whose name states no unit, or a list `ch=unit,...`.
    #[arg(long)]
    pub units: Option<String>,
    /// Interpolate a non-uniform time column onto a uniform grid (reported) instead of failing.
    #[arg(long)]
    pub resample: bool,
    /// Resample onto this rate, Hz, through an anti-alias low-pass (implies --resample).
    #[arg(long)]
    pub resample_fs: Option<f64>,
    /// Most spectral lines, from 0 Hz, of a PSD record read from a UFF file (a larger record
    /// is refused before anything is allocated).
    #[arg(long, default_value_t = satqual::signal::logpsd::MAX_PSD_LINES)]
    pub max_psd_lines: usize,
    #[command(flatten)]
    pub dialect: DialectArgs,
}

impl LogArgs {
    /// The reader's options for these flags, reading only `channels` when given.
    pub fn ingest(&self, channels: Option<Vec<String>>) -> Result<IngestOptions, Error> {
        let mut opts = IngestOptions {
            channels,
            fs: self.fs,
            resample: self.resample,
            resample_fs: self.resample_fs,
            max_psd_lines: self.max_psd_lines,
            ..Default::default()
        };
        if let Some(f) = self.resample_fs
            && !(f.is_finite() && f > 0.0)
        {
            return Err(Error::Other(format!(
                "--resample-fs {f}: expected a positive rate in Hz"
            )));
        }
        parse_units(self.units.as_deref(), &mut opts)?;
        self.dialect.apply(&mut opts)?;
        Ok(opts)
    }
}

/// How to read a log whose dialect the reader cannot decide alone.
#[derive(clap::Args, Debug, Clone)]
pub struct DialectArgs {
    /// Column names of a headerless log, comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub columns: Option<Vec<String>>,
    /// Unit of the time column when its name states none: s, ms, us, ns, d (spreadsheet serial days) or iso8601 (date-times).
    #[arg(long)]
    pub time_unit: Option<String>,
    /// Use --fs even when the time column disagrees with it (the time column is ignored).
    #[arg(long)]
    pub fs_override: bool,
}

impl DialectArgs {
    pub fn apply(&self, opts: &mut IngestOptions) -> Result<(), Error> {
        opts.columns = self.columns.clone();
        opts.time_unit = self.time_unit.as_deref().map(TimeUnit::parse).transpose()?;
        opts.fs_override = self.fs_override;
        Ok(())
    }
}

/// Welch averaging: segment length, overlap, window and detrending. A flag left out takes
/// its default; `frf` and `signature` replace all four with the impact options when none is
/// given and the input is an impact.
#[derive(clap::Args, Debug, Clone)]
pub struct WelchArgs {
    /// Welch segment length, samples, at least 16 [default: 8192].
    #[arg(long)]
    pub nperseg: Option<usize>,
    /// Segment overlap as a fraction in [0, 1) [default: 0.5].
    #[arg(long)]
    pub overlap: Option<f64>,
    /// hann, hamming, flattop or boxcar [default: hann].
    #[arg(long)]
    pub window: Option<String>,
    /// none, constant or linear [default: constant].
    #[arg(long)]
    pub detrend: Option<String>,
}

impl WelchArgs {
    /// The checked Welch options.
    pub fn options(&self) -> Result<WelchOptions, Error> {
        let d = WelchOptions::default();
        let o = WelchOptions {
            nperseg: self.nperseg.unwrap_or(d.nperseg),
            overlap: self.overlap.unwrap_or(d.overlap),
            window: self.window.as_deref().map_or(Ok(d.window), Window::parse)?,
            detrend: self
                .detrend
                .as_deref()
                .map_or(Ok(d.detrend), Detrend::parse)?,
        };
        o.validate()?;
        Ok(o)
    }

    /// No Welch flag was given: the options are the defaults, not the user's choice.
    pub fn all_default(&self) -> bool {
        self.nperseg.is_none()
            && self.overlap.is_none()
            && self.window.is_none()
            && self.detrend.is_none()
    }
}

/// Prints the reader's dialect decisions once, on stderr (stdout may hold the JSON).
pub fn print_ingest_notes(info: Option<&LogInfo>) {
    print_notes(info.map(|i| i.ingest.notes.as_slice()).unwrap_or_default());
    print_warnings(
        info.map(|i| i.ingest.warnings.as_slice())
            .unwrap_or_default(),
    );
}

/// Prints what a file says is wrong with it, one `warning:` line each, on stderr.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Prints decisions and warnings, one `note:` line each, on stderr.
pub fn print_notes(notes: &[String]) {
    for n in notes {
        eprintln!("note: {n}");
    }
}

/// Parses `--units`: one unit for all, or `name=unit` pairs.
fn parse_units(spec: Option<&str>, opts: &mut IngestOptions) -> Result<(), Error> {
    let Some(spec) = spec else { return Ok(()) };
    if !spec.contains('=') {
        opts.default_unit = Some(Unit::parse(spec)?);
        return Ok(());
    }
    for item in spec.split(',').filter(|s| !s.trim().is_empty()) {
        let (name, unit) = item
            .split_once('=')
            .ok_or_else(|| Error::Other(format!("--units: `{item}` is not `channel=unit`")))?;
        opts.channel_units
            .push((name.trim().to_string(), Unit::parse(unit)?));
    }
    Ok(())
}
