//! Figures over finished granular runs, drawn from their files: plotting, `granular plot`,
//! `granular compare` and `granular reproduce`.

pub mod compare;
pub mod figures;
pub mod intruder_plots;
mod plot;
pub mod reproduce;
