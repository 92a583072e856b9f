//! Parameter sweeps of the release (`[sweep]`): the design's points, each point's scene, and
//! each point's Monte Carlo, gated.
//!
//! - [`design`]: the points of a grid or a seeded Latin hypercube;
//! - [`point`]: the scene of one point, edited as TOML text and loaded through the normal,
//!   validated path;
//! - [`run`]: the work units (point × realization) of a sweep or of one shard of it, and the
//!   per-point table with its gates.
//!
//! Determinism: unit `u` is run `u mod N` of point `⌊u / N⌋`; every point uses the same seed
//! (common random numbers, so two points differ by their parameters, not by their draws), and a
//! realization depends only on (point, seed, run). A shard computes a contiguous block of units;
//! any split gives the same realizations, and the table is built from them in unit order.

pub mod design;
pub mod point;
pub mod run;

pub use design::Design;
pub use run::{SweepJob, realize_units, table};
