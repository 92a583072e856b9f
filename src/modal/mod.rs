//! Eigen-solvers and modal results (frequencies, mass-normalised shapes, effective masses).
