//! Test-data processing: log ingest (CSV, UFF58), Welch PSD/CSD, FRF, peaks, sweep tracking,
//! tolerance bands and pre/post signature comparison. Inputs are measured logs only; nothing
//! here prints or exits.
//!
//! Pipeline stages, in the order the `psd`/`frf`/`signature` commands run them:
//! 1. [`ingest`] / [`uff`]: a CSV log (streamed) or a UFF58 record -> channels, sampling rate;
//!    [`logpsd`] runs stages 1-2 for every channel of a file (the `psd` command's analysis).
//! 2. [`welch`]: Welch PSD and CSD (scipy-exact definitions).
//! 3. [`bands`]: Grms, band RMS, octave / third-octave levels, tolerance bands.
//! 4. [`peaks`]: peaks with parabolic interpolation, resonances with half-power Q.
//! 5. [`frf`]: H1, H2, coherence and resonance picking on |H1|.
//! 6. [`sweep`]: sine-sweep tracking (amplitude and phase against drive frequency).
//! 7. [`signature`]: pre/post test signature comparison.
//!
//! Beside them, [`srs`]: the shock response spectrum of a transient (Smallwood's ramp-invariant
//! filter, ISO 18431-4) and its tolerance check against a shock specification.

pub mod bands;
pub mod ema;
pub mod formats;
pub mod frf;
pub mod impact;
pub mod impact_windows;
pub mod ingest;
pub mod logpsd;
pub mod peaks;
pub mod psd_table;
pub mod screen;
pub mod signature;
pub mod srs;
pub mod sweep;
pub mod uff;
pub mod welch;

pub use bands::{
    Band, ToleranceReport, ToleranceSpec, ToleranceStatus, band_rms, octave_bands, read_profile,
    rms_of, tolerance_bands,
};
pub use formats::{LogFormat, read_log};
pub use frf::{Frf, Resonance, frf, frf_of_files, resonances};
pub use ingest::{IngestOptions, Log, LogInfo, Unit, read_csv, stream_csv};
pub use logpsd::{ChannelPsd, LogPsd, PsdSource, psd_of_file};
pub use peaks::{Peak, PeakOptions, find_peaks};
pub use signature::{ModeComparison, SignatureCriteria, SignatureReport, compare_signatures};
pub use srs::{ChannelSrs, LogSrs, Offset, SrsOptions, SrsPoint, srs_of_file};
pub use sweep::{SweepOptions, SweepTrack, not_a_sweep, sweep_resonance, track_sweep};
pub use uff::{UffRecord, read_uff58};
pub use welch::{
    CrossPsd, Detrend, Psd, WelchOptions, WelchResult, WelchStream, Window, csd, welch, welch_multi,
};
