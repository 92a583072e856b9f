//! `satqual bench psd`: placeholder replaced below.
use super::Outcome;
use satqual::Error;
pub fn run(_out: &std::path::Path) -> Result<Outcome, Error> {
    Err(Error::Other("bench psd: not written yet".into()))
}
