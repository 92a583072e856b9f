//! The canonical problems, shared by the tests and `satqual bench`: the repository's scenes,
//! the analytic answers they are checked against, and the scenes generated from them (stacks
//! of N satellites, frame towers, a small separation stack).
//!
//! Everything here is plain data and scene text: the catalogue depends on nothing else in the
//! crate, so any module, test or benchmark can draw from it. Paths are relative to the
//! repository root, the working directory of `cargo test` and of the benchmarks; the golden
//! outputs quote them, so they stay relative.

pub mod analytic;
pub mod generated;

/// Clamped-free steel cantilever, 20×20 mm, 1 m (analytic Euler-Bernoulli βL roots).
pub const CANTILEVER: &str = "test-specs/verification/cantilever.toml";
/// NAFEMS R0015 FV4: cantilever with offset masses.
pub const NAFEMS_FV4: &str = "test-specs/verification/nafems-fv4.toml";
/// NAFEMS R0015 FV5: deep simply supported beam.
pub const NAFEMS_FV5: &str = "test-specs/verification/nafems-fv5.toml";
/// Base-driven single-DOF oscillator (see [`analytic::SDOF_NATURAL_HZ`]).
pub const SDOF_BASE: &str = "test-specs/verification/sdof-base.toml";
/// The paper's six-satellite preloaded stack: the reference scene.
pub const PAPER_STACK: &str = "test-specs/paper-stack.toml";
/// The paper's two-satellite shaker-test configuration (measured modes).
pub const SHAKER_2SAT: &str = "test-specs/shaker-2sat.toml";
/// A scene that gates measured test logs (tolerance bands, signatures).
pub const TEST_DATA: &str = "test-specs/test-data.toml";

/// The verification scenes, each with an analytic or published reference.
pub const VERIFICATION_SCENES: [&str; 4] = [CANTILEVER, NAFEMS_FV4, NAFEMS_FV5, SDOF_BASE];

/// Every scene in `test-specs/`.
pub const ALL_SCENES: [&str; 7] = [
    PAPER_STACK,
    SHAKER_2SAT,
    TEST_DATA,
    CANTILEVER,
    NAFEMS_FV4,
    NAFEMS_FV5,
    SDOF_BASE,
];

/// The scenes with sine and random base-excitation input.
pub const RESPONSE_SCENES: [&str; 3] = [PAPER_STACK, SHAKER_2SAT, SDOF_BASE];

/// Measured logs from third parties, each folder with its SOURCE.md.
pub mod logs {
    /// Impact-hammer hits `impact_1.csv` … `impact_5.csv` (pyFRF).
    pub const IMPACT_DIR: &str = "data/realdata/pyfrf-impact";
    /// Multi-tone sine dwell on a shaker beam (USC, CC BY-SA 4.0).
    pub const SHAKER_BEAM: &str = "data/realdata/usc-shaker-beam/data_set_1_3200Hz.csv";
    /// A vibration controller's random PSD as UFF58 (pyuff).
    pub const CONTROLLER_PSD_UFF: &str =
        "data/realdata/pyuff-vibcontrol-psd/sample_dataset58_psd.uff";

    /// The `i`-th impact-hammer hit (1 to 5).
    pub fn impact(i: usize) -> String {
        format!("{IMPACT_DIR}/impact_{i}.csv")
    }
}
