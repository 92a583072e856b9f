//! Test-data processing: log ingest (CSV, UFF58), Welch PSD/CSD, FRF, peaks, sweep tracking,
//! tolerance bands and pre/post signature comparison. Inputs are measured logs only.
