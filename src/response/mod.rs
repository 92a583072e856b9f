//! Base-driven sine and random response by modal superposition, and load recovery.
//! Inputs: the FE model (fem) and its modes (modal); profiles from the scene (spec).
