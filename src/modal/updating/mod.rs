//! Model-updating arithmetic, knowing nothing of scenes: eigenvalue sensitivities from the
//! assembled matrices, a bounded Levenberg–Marquardt least-squares solver, and what the
//! sensitivity matrix says about which parameters the data can identify.

pub mod identifiability;
pub mod lm;
pub mod sensitivity;
