//! Pass/fail criteria. Each gate rule turns an analysis result and a limit from the scene (or
//! a documented default in `spec::qualify::GatesSpec`) into a [`Verdict`]; a failed gate is a
//! result, not an error. One file per family of rules, each stating its criterion, limit,
//! margin definition and source:
//!
//! - [`verdict`]: the [`Verdict`] shape and the shared margin definitions (a leaf, also used
//!   by the response analyses for their margins of safety);
//! - [`frequency`]: first lateral and axial frequencies, buckling factor;
//! - [`lock_integrity`]: governing gapping, slip and guide-bar margins;
//! - [`separation`]: exit speed, tip-off, clearing the bars, re-contact, Monte Carlo bounds;
//! - [`test_data`]: random control tolerance and pre/post signatures;
//! - [`summary`]: the governing gate of each family.

pub mod correlation;
pub mod frequency;
pub mod lock_integrity;
pub mod separation;
pub mod summary;
pub mod test_data;
pub mod verdict;

pub use verdict::{
    Group, MARGIN_CAP, Verdict, above, at_least, at_most, design_margin, margin_of_safety,
    strength_margin,
};
