//! One error type per layer, gathered in [`Error`]. Errors carry the numerical or positional
//! fact that caused them (a file, line and key; a node and DOF; a pivot), so that the CLI can
//! print one clear message and exit 2 without a backtrace. A failed gate is not an error.

use std::path::PathBuf;

/// A scene file that cannot be used: where, which key, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct SpecError {
    pub file: PathBuf,
    /// 1-based line; 0 when the problem is not tied to one place in the file.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// Dotted path of the offending key, e.g. `node[2].position_m`.
    pub key: String,
    pub message: String,
}

/// `file:line:column: key `k`: message`, or `file: message` when the problem is not tied to
/// one place in the file (line 0).
impl std::fmt::Display for SpecError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file.display())?;
        if self.line > 0 {
            write!(f, ":{}:{}", self.line, self.column)?;
        }
        write!(f, ": ")?;
        if !self.key.is_empty() {
            write!(f, "key `{}`: ", self.key)?;
        }
        write!(f, "{}", self.message)
    }
}

/// The finite-element model cannot be assembled or solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FemError {
    #[error(
        "the model has no free degree of freedom: the supports (and rigid links) hold every DOF of every node, so nothing can vibrate; support only the nodes that are held in the test or in flight"
    )]
    NoFreeDofs,
    #[error("{node} is a rigid-link slave and also supported: support its master, {master}")]
    SupportedSlave { node: String, master: String },
    #[error("{}", massless_dof_message(.node, *.dof, .dof_name, *.mass, *.largest))]
    MasslessDof {
        node: String,
        dof: usize,
        dof_name: &'static str,
        /// Its diagonal mass term (kg, or kg·m² for a rotation).
        mass: f64,
        /// The largest diagonal mass term of the model, same units per kind.
        largest: f64,
    },
    #[error(
        "the stiffness matrix is singular near {node} DOF {dof} ({dof_name}): the model is unconstrained or a mechanism there (add supports for a static or buckling solve), or a spring many decades stiffer than its neighbours has taken the digits of its pivot (model a rigid connection with [[rigid]])"
    )]
    Unconstrained {
        node: String,
        dof: usize,
        dof_name: &'static str,
    },
    #[error(
        "rigid link: node {node} is a slave of more than one master, or a master is also a slave"
    )]
    RigidChain { node: String },
    #[error("{0}")]
    Invalid(String),
}

/// The eigen-solution failed or could not prove itself complete.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModalError {
    #[error("the eigen-solver did not converge: {0}")]
    NoConvergence(String),
    #[error(
        "Sturm check failed: {expected} modes lie below {fmax_hz} Hz (LDLᵀ inertia of K − σM) but the solver returned {found}"
    )]
    SturmMismatch {
        expected: usize,
        found: usize,
        fmax_hz: f64,
    },
    #[error(
        "no buckling factor: the prestress does not destabilise the structure (K_G has no negative direction)"
    )]
    NoBuckling,
    #[error(
        "the static loads are above the buckling load (buckling factor {factor:.3}): the structure has no stable modes"
    )]
    BeyondBuckling { factor: f64 },
    #[error("{0}")]
    Invalid(String),
}

/// Base-excitation response failures.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResponseError {
    #[error("{0}")]
    Invalid(String),
}

/// Measured-log ingest and spectral processing failures. Each variant names the file and the
/// row (1-based line of the file, header = line 1) or column where the fact was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SignalError {
    #[error("{}: the file is empty", file.display())]
    EmptyFile { file: PathBuf },
    #[error("{}: looks like a binary file (byte 0x{byte:02x} at offset {offset}); expected a text log (CSV, LabVIEW .lvm), UFF58/58b, a MATLAB .mat file (level 4 or 5), TDMS or WAV", file.display())]
    BinaryFile {
        file: PathBuf,
        offset: usize,
        byte: u8,
    },
    #[error("{}: the header has no data rows after it", file.display())]
    HeaderOnly { file: PathBuf },
    #[error("{}: line 1: {message}", file.display())]
    BadHeader { file: PathBuf, message: String },
    #[error("{}: line {line}: expected {expected} fields as in the header, found {found}", file.display())]
    RaggedRow {
        file: PathBuf,
        line: u64,
        expected: usize,
        found: usize,
    },
    #[error("{}: line {line}, column `{column}`: {what}{}", file.display(), quoted_cell(text))]
    BadCell {
        file: PathBuf,
        line: u64,
        column: String,
        text: String,
        what: &'static str,
    },
    #[error("{}: no channel named `{name}` (available: {available})", file.display())]
    NoSuchChannel {
        file: PathBuf,
        name: String,
        available: String,
    },
    #[error("{}: line {line}: time {time} does not increase (previous row {previous})", file.display())]
    NonMonotonicTime {
        file: PathBuf,
        line: u64,
        time: f64,
        previous: f64,
    },
    #[error("{}: line {line}: time step {dt} s departs from the sampling interval {expected_dt} s by more than the {jitter_pct}% read as jitter (a gap, or a change of rate); pass --resample to interpolate onto a uniform grid", file.display())]
    NonUniformTime {
        file: PathBuf,
        line: u64,
        dt: f64,
        expected_dt: f64,
        jitter_pct: f64,
    },
    #[error("{}: line {line}: time step {dt} s is less than half the grid interval {expected_dt} s: the log is sampled faster here than the grid, and interpolating would decimate it with no anti-alias filter; pass --resample-fs with the rate wanted", file.display())]
    ResampleFaster {
        file: PathBuf,
        line: u64,
        dt: f64,
        expected_dt: f64,
    },
    #[error("{}: line {line}: a gap of {dt} s is more than {max_steps} sampling intervals ({expected_dt} s); it cannot be resampled honestly", file.display())]
    ResampleGap {
        file: PathBuf,
        line: u64,
        dt: f64,
        expected_dt: f64,
        max_steps: f64,
    },
    #[error("{}: no usable sampling rate: no time column (time, time_s, t, ...) with at least two finite increasing times, and no --fs", file.display())]
    NoSamplingRate { file: PathBuf },
    #[error("{}: line {line}: {message}", file.display())]
    Uff {
        file: PathBuf,
        line: u64,
        message: String,
    },
    /// A located fact in a log of another format (LabVIEW .lvm, MATLAB .mat).
    #[error("{}: line {line}: {message}", file.display())]
    AtLine {
        file: PathBuf,
        line: u64,
        message: String,
    },
    #[error("{}: {message}", file.display())]
    Unsupported { file: PathBuf, message: String },
    #[error("{}", segment_too_long(*nperseg, *len, channel, file.as_deref()))]
    SegmentTooLong {
        nperseg: usize,
        len: usize,
        channel: String,
        /// The log the channel comes from, once known.
        file: Option<PathBuf>,
    },
    #[error("overlap {overlap} must be in [0, 1)")]
    BadOverlap { overlap: f64 },
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    BadParameter {
        name: &'static str,
        value: String,
        reason: String,
    },
    #[error("channel `{channel}`: {message}")]
    Channel { channel: String, message: String },
    #[error("{0}")]
    Invalid(String),
}

/// A cell's text after the error, or nothing for an empty cell (whose message says so).
fn quoted_cell(text: &str) -> String {
    if text.is_empty() {
        String::new()
    } else {
        format!(" `{text}`")
    }
}

fn segment_too_long(
    nperseg: usize,
    len: usize,
    channel: &str,
    file: Option<&std::path::Path>,
) -> String {
    let min = crate::signal::welch::MIN_NPERSEG;
    let at = file.map_or(String::new(), |f| format!("{}: ", f.display()));
    if len < min {
        format!(
            "{at}the signal{} has {len} samples, fewer than the {min} of the shortest Welch segment: too short for a spectrum (a shock record goes to `satqual srs`)",
            channel_suffix(channel)
        )
    } else {
        format!(
            "{at}nperseg = {nperseg} is longer than the signal ({len} samples){}",
            channel_suffix(channel)
        )
    }
}

fn channel_suffix(channel: &str) -> String {
    if channel.is_empty() {
        String::new()
    } else {
        format!(" in channel `{channel}`")
    }
}

/// Separation-dynamics failures. A run that fails stops at once and reports where and when;
/// no partial history is written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SeparationError {
    /// The state became NaN or infinite: the run stopped at `time_s`; `body` names the body or
    /// bar whose coordinates went non-finite first.
    #[error(
        "the separation run produced a non-finite state at t = {time_s} s in {body}; stopped, nothing written"
    )]
    NonFinite { time_s: f64, body: String },
    /// The adaptive step fell below the round-off floor: the problem is too stiff for the
    /// tolerance; `cause` names the stiffest element and the step it implies.
    #[error(
        "key `separation.tolerance`: the step size fell to {step_s:e} s at t = {time_s} s (round-off floor); {cause}; loosen the tolerance or soften that element"
    )]
    StepTooSmall {
        time_s: f64,
        step_s: f64,
        cause: String,
    },
    /// The step budget ran out before the end of the run; `cause` as for `StepTooSmall`.
    #[error(
        "key `separation.max_steps`: more than {max_steps} steps before t = {time_s} s; {cause}; raise separation.max_steps, loosen separation.tolerance or soften that element"
    )]
    TooManySteps {
        time_s: f64,
        max_steps: usize,
        cause: String,
    },
    /// The model cannot be built (e.g. the bar modes failed).
    #[error("{0}")]
    Invalid(String),
}

/// Everything that can go wrong in satqual.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Spec(#[from] SpecError),
    #[error(transparent)]
    Fem(#[from] FemError),
    #[error(transparent)]
    Modal(#[from] ModalError),
    #[error(transparent)]
    Response(#[from] ResponseError),
    #[error(transparent)]
    Signal(#[from] SignalError),
    #[error(transparent)]
    Separation(#[from] SeparationError),
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{0}")]
    Other(String),
}

impl SignalError {
    /// A too-short signal's error named by its channel and log; any other error as it is.
    pub fn in_channel(self, channel: &str, file: &std::path::Path) -> SignalError {
        match self {
            SignalError::SegmentTooLong { nperseg, len, .. } => SignalError::SegmentTooLong {
                nperseg,
                len,
                channel: channel.to_string(),
                file: Some(file.to_path_buf()),
            },
            other => other,
        }
    }
}

impl Error {
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// "carries no mass", or, for a mass too small to count against the model's largest (below
/// 1e-14 of it), that mass with a hint at units: an inertia in g·mm² is 1e-9 of kg·m².
fn massless_dof_message(node: &str, dof: usize, dof_name: &str, mass: f64, largest: f64) -> String {
    let at = format!("the mass matrix is singular on {node} DOF {dof} ({dof_name})");
    let fix = "add a support on it, a mass or inertia, or a beam that gives it mass";
    if mass > 0.0 {
        format!(
            "{at}: its mass term {mass:.3e} is below 1e-14 of the model's largest ({largest:.3e}), so it is lost to round-off; check its units (kg, kg·m²: an inertia in g·mm² is 1e-9 of its value in kg·m²), or {fix}"
        )
    } else {
        format!("{at}: it carries no mass and is not supported; {fix}")
    }
}
