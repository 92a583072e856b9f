//! Finite-element model: beam, mass, spring and rigid-link elements, assembly, supports and
//! prestress (geometric stiffness). Input: a validated generic model from `spec`.

pub mod bar;
pub mod beam;
pub mod model;

pub use bar::{BarModes, cantilever_bar_modes};
pub use model::FeModel;
