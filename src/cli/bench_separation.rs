//! `satqual bench separation`: placeholder until the work-precision table lands.
use super::Outcome;
use satqual::Error;
use std::path::Path;

pub fn run(_out: &Path) -> Result<Outcome, Error> {
    Err(Error::Other("not yet".into()))
}
