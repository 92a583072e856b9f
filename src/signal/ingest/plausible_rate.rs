//! The range a sampling rate must lie in, whatever stated it (a time column, a file header, a
//! metadata cell or `--fs`): a rate outside it comes from a unit slip or a corrupted file, and
//! every spectrum computed from it would be nonsense (a 1e-308 s step gives 1e308 Hz).

use crate::error::SignalError;
use std::path::Path;

/// `fs` when it is a plausible sampling rate (the scenes' range,
/// [`crate::spec::plausible::SAMPLING_RATE_HZ`]), else an error naming the file and what gave
/// it.
pub fn plausible_rate(file: &Path, fs: f64, source: &str) -> Result<f64, SignalError> {
    let range = crate::spec::plausible::SAMPLING_RATE_HZ;
    if range.admits(fs) {
        return Ok(fs);
    }
    let (lo, hi) = (range.lo, range.hi);
    Err(SignalError::Unsupported {
        file: file.to_path_buf(),
        message: format!(
            "the sampling rate {fs:e} Hz given by {source} is outside the plausible range [{lo:e}, {hi:e}] Hz; check its unit, or pass --fs F --fs-override"
        ),
    })
}
