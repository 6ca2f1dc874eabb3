//! Exact and kinetic-theory results the engines are checked against.

pub mod equilibrium;
