//! The integration layer: the only module that knows the whole order
//! spec -> fem -> modal -> response -> gates -> results.
//!
//! - [`plan`]: a scene resolved once into typed, defaulted inputs per analysis;
//! - [`workflows`]: one workflow per analysis, shared by the command line and `qualify`;
//! - [`qualify()`]: runs the planned analyses once each, gates them, and fills
//!   [`crate::results::Qualification`];
//! - [`param_sweep`]: a `[sweep]`'s points, each with its gated Monte Carlo.

mod comparison;
pub mod param_sweep;
pub mod plan;
mod provenance;
mod qualify;
pub mod workflows;

pub use provenance::fnv1a;
pub use qualify::qualify;
pub use workflows::modal::{fe_model, locate, modal, modal_summary, modal_with_solver};

/// Progress reporting for long stages; the library never prints, the caller decides. `Sync`,
/// because parallel work (the Monte Carlo's runs) reports from its worker threads.
pub trait Progress: Sync {
    fn stage(&self, _name: &str) {}
    /// `done` of `total` items of the current stage are finished (in any order).
    fn count(&self, _done: usize, _total: usize) {}
}

/// A no-op progress sink.
pub struct Silent;
impl Progress for Silent {}
