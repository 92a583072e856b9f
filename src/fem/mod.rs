//! Finite-element model: beam, mass, spring and rigid-link elements, assembly, supports and
//! prestress (geometric stiffness). Input: a validated generic model from `spec`.

pub mod beam;
pub mod model;

pub use model::FeModel;
