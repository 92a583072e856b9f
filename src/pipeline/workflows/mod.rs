//! One workflow per analysis, used by both the command line and `qualify`: each takes
//! resolved inputs (a plan or a request whose constants are explicit) and returns data; the
//! callers decide what to print or gate.

pub mod calibration;
pub mod correlate;
pub mod ema;
pub mod frf;
pub mod matrices;
pub mod modal;
pub mod psd;
pub mod response;
pub mod separate;
pub mod signature;
pub mod sweep;
pub mod test_data;
pub mod update;
