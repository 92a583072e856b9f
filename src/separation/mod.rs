//! Separation dynamics of the in-orbit release (the paper's §3–§4 carried to 3-D): rigid
//! satellites with 6 DOF (quaternions), guide bars as flexible cantilevers in modal coordinates
//! (modes of an FE beam model, `bar_modes`), bore-edge contact with Lankarani–Nikravesh normal force and regularised
//! Coulomb friction, four separation springs per interface, the release schedule after the
//! compression device unlocks, an adaptive Dormand–Prince 5(4) integrator with events, an
//! energy audit, and a seeded parallel Monte Carlo.
//!
//! Inputs: a scene with `[stack]` (geometry) and `[separation]` (everything the release adds),
//! turned into a [`Model`] by [`Model::from_scene`]. Public entry points for `pipeline::qualify`:
//! [`Model::from_scene`], [`run`] and [`monte_carlo`].
//!
//! Files: `params` (the model), `body` (quaternion kinematics), `bar` (modal bars),
//! `contact` (LN, friction, contact states), `integrator` (DOPRI5), `sim` (one run),
//! `montecarlo` (dispersed runs and percentiles), `shard` (part files of a sharded Monte Carlo
//! and their merge).

pub mod bar;
pub mod bar_modes;
pub mod body;
pub mod contact;
pub mod integrator;
pub mod montecarlo;
pub mod order_stats;
pub mod params;
pub mod shard;
pub mod shock;
pub mod sim;

pub use contact::{ContactParams, ContactState, Transitions};
pub use integrator::Stats;
pub use montecarlo::{MonteCarloResult, Percentiles, Realization, monte_carlo};
pub use params::{Model, SatelliteParams, SpringParams};
pub use sim::{
    AccelHistory, EdgeLoad, EnergyAudit, History, PairClearance, RunOptions, SatelliteResult,
    SeparationResult, Stall, run,
};
