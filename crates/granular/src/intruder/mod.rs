//! Gillespie simulation of a granular intruder in a bath of thermalised point particles,
//! after Gillespie-type event sampling for a granular intruder (the Gillespie intruder paper,
//! `gillespie-granular-intruder.txt`; equation numbers below refer to it).
//!
//! * [`bath`]: bath velocity distributions, side fluxes (G-5 to G-7, G-14 to G-16, G-19) and exact
//!   samplers of the colliding bath velocity (G-12 and G-13);
//! * [`one_d`]: the one-dimensional intruder (G-8 to G-13, G-17), stationary and ensemble runs;
//! * [`needle`]: the two-dimensional needle (G-20 to G-30);
//! * [`dsmc_twin`]: the DSMC version of the 1D intruder (section 4);
//! * [`theory`]: exact results (G-18, the power-law case `M/m = alpha`);
//! * [`figures`]: the data of the paper's figures as tables.
//!
//! Units: `k_B = 1`; a temperature is `mass * <v_component^2>`. The bath mass `m`
//! (default 1) and the bath density `rho` set the collision rate.

pub mod ball;
pub mod bath;
pub mod dsmc_twin;
pub mod figures;
pub mod needle;
pub mod observables;
pub mod one_d;
pub mod theory;

pub(crate) use bath::{BathConfig, BathError, Tabulated};
pub use bath::{BathDistribution, Gaussian, PowerLaw};

pub(crate) use needle::{Needle, NeedleConfig};
pub(crate) use one_d::{Intruder1d, Intruder1dConfig};
