//! The library's integration tests, one binary (fast to link on two cores).

mod averages;
mod collision_law;
mod common;
mod decomposed;
mod dsmc;
mod edmd;
mod edmd_reference;
mod engines;
mod golden;
mod intruder;
mod intruder_ball;
mod intruder_scenario;
mod observables;
mod preflight;
mod problems;
mod resolved;
mod rough;
mod scenario_errors;
mod set_state;
mod simulation;
mod spine;
mod steady;
mod steady_edmd;
mod structure_transport;
mod sweeps;
mod trajectory;
