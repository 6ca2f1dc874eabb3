//! The library's integration tests, one binary (fast to link on two cores).

mod dsmc;
mod edmd;
mod engines;
mod intruder;
mod intruder_scenario;
mod problems;
mod spine;
