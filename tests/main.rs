//! The integration tests, as modules of one test binary: the crate and its dependencies link
//! once instead of once per file. Run one area with a filter, e.g.
//! `cargo test --release --test integration signal_`.
//!
//! Shared helpers (running the binary, temporary folders, error-location checks) live in
//! `common`; the canonical problems (verification scenes, the SDOF, the stack variants) come
//! from `satqual::catalogue`, which the benches use too.

#[macro_use]
mod common;

// Every command's output, byte for byte.
mod golden;

// Where commands write, what they print on stderr.
mod cli_output;

// FE core and modal solvers.
mod cli_modal;
mod fem_verification;
mod fixture;
mod modal_band_edges;
mod modal_sparse;
mod modal_stability;
mod scene_errors;
mod stack;

// Response analyses.
mod response_accuracy;
mod response_cli;
mod response_errors;

// Qualification end to end.
mod qualify;

// Separation dynamics.
mod separation_accuracy;
mod separation_cli;
mod separation_contact;
mod separation_gates;
mod separation_input;
mod separation_montecarlo;
mod separation_shock;

// Sharded Monte Carlo, merge, Slurm scripts.
mod campaign;
mod param_sweep;

// Test-log signal processing.
mod correlate;
mod damping;
mod ema;
mod ema_measured;
mod signal_bands;
mod signal_dialects;
mod signal_formats;
mod signal_frf;
mod signal_impact;
mod signal_ingest;
mod signal_proptest;
mod signal_psd_cli;
mod signal_psd_table;
mod signal_signature;
mod signal_srs;
mod signal_sweep;
mod signal_tdms;
mod signal_timing;
mod signal_wav;
mod signal_welch;
mod update;
mod update_damping;
mod update_logs;

// Hostile input: limits, plausibility, finite outputs, mutation fuzzing.
mod fuzz;
mod hostile_inputs;
