//! Campaigns beyond one machine: batch scripts that run the shards of a Monte Carlo as an
//! array job and merge them in a job that waits for all of them (`slurm`).

pub mod slurm;
