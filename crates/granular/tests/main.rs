//! The library's integration tests, one binary (fast to link on two cores).

mod dsmc;
mod edmd;
mod engines;
mod intruder;
mod observables;
mod problems;
mod spine;
