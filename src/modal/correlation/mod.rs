//! Test-analysis correlation arithmetic on real mode shapes at the test DOFs: the modal
//! assurance criterion, the pairing of test modes with FE modes, and the SEREP test-analysis
//! mass matrix with the cross-orthogonality it gives. Shapes are `Vec<f64>` over the test
//! points, one per mode; nothing here knows about scenes or channels.

pub mod mac;
pub mod pairing;
pub mod serep;

pub use mac::{mac, mac_matrix};
pub use pairing::{Pair, PairingMethod};
pub use serep::{cross_orthogonality, serep_mass};
