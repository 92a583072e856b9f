//! # satqual
//!
//! Qualification of a preloaded stack of flat satellites (the four-guide-bar device of
//! *Design and Analysis of a Compression and Separation Device for Multi-Satellite Deployment*,
//! Aerospace 2022): predict the shaker-test response with a finite-element model, post-process
//! the accelerometer logs of the test, gate the hardware, and simulate the in-orbit release.
//!
//! Data flow (a module imports only modules to its left, plus `units`, `error` and
//! `gates::verdict`, the leaf that gives every criterion's outcome its shape):
//!
//! ```text
//! spec ──> fem ──> modal ──> response ──┐
//!   │                                   ├──> gates ──> results ──> report
//!   │      signal ──────────────────────┤
//!   └────> separation ──────────────────┘
//! ```
//!
//! Only [`pipeline`] knows the whole order: it resolves a scene into a plan, runs one workflow
//! per analysis and fills the [`results`] the report renders. Analyses never do I/O; the
//! binary prints and exits.
//!
//! Beside the flow: [`catalogue`] (the canonical problems: scenes, analytic answers, generated
//! stacks) imports nothing, so tests and benchmarks can all draw from it; [`bench`](mod@bench) (the
//! work-precision tables of `satqual bench`) imports everything and nothing imports it.

pub mod bench;
pub mod campaign;
pub mod catalogue;
pub mod error;
pub mod fem;
pub mod gates;
pub mod modal;
pub mod output_check;
pub mod pipeline;
pub mod report;
pub mod response;
pub mod results;
pub mod separation;
pub mod signal;
pub mod spec;
pub mod units;

pub use error::{Error, Result};
