//! `[driving]`: a steady state of the granular gas ([`crate::driving`]), DSMC engine.
//!
//! ```toml
//! [driving]
//! kind = "rescale"      # the homogeneous cooling state in scaled variables
//! temperature = 1.0     # optional; default the initial temperature
//! ```
//! or
//! ```toml
//! [driving]
//! kind = "white_noise"  # the stochastically heated gas
//! strength = 2.0        # xi0^2, velocity variance per component and unit time
//! ```

use super::validate::positive;
use super::{EngineKind, Scenario, ScenarioError};
use crate::boundary::AxisKind;
use crate::driving::Driving;
use serde::{Deserialize, Serialize};

/// Which steady state `[driving]` maintains.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DrivingKind {
    /// Velocities rescaled to a fixed temperature after every step (homogeneous cooling
    /// state in scaled variables).
    Rescale,
    /// Gaussian white-noise velocity kicks after every step (heated gas).
    WhiteNoise,
}

/// `[driving]`: see the module docs and `docs/scenario.md`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrivingSpec {
    /// `"rescale"` or `"white_noise"`.
    pub kind: DrivingKind,
    /// `rescale`: the fixed temperature (energy units); default the initial temperature.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<f64>,
    /// `white_noise`: `xi0²`, the velocity variance per component and unit time
    /// (length² / time³).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strength: Option<f64>,
}

impl DrivingSpec {
    /// The engine's driving; `initial_temperature` is the default of `rescale`.
    pub(crate) fn driving(&self, initial_temperature: f64) -> Driving {
        match self.kind {
            DrivingKind::Rescale => Driving::Rescale {
                temperature: self.temperature.unwrap_or(initial_temperature),
            },
            DrivingKind::WhiteNoise => Driving::WhiteNoise {
                strength: self.strength.unwrap_or(0.0),
            },
        }
    }
}

/// Checks `[driving]`: DSMC or one species in the event-driven engine, a periodic box without gravity, and the keys of
/// its kind.
pub(super) fn validate(sc: &Scenario) -> Result<(), ScenarioError> {
    let Some(d) = &sc.driving() else {
        return Ok(());
    };
    if sc.kind() == EngineKind::Edmd && sc.species().len() > 1 {
        return Err(ScenarioError::new(
            "species",
            format!(
                "has {} species, but the steady states of [driving] are those of one \
                 species (the Sonine theory of a monodisperse gas); keep one [[species]] \
                 or remove [driving]",
                sc.species().len()
            ),
        ));
    }
    if sc.axes().iter().any(|a| *a != AxisKind::Periodic) {
        return Err(ScenarioError::new(
            "driving",
            "needs a periodic box on every axis (the steady states are homogeneous, and the \
             energy balance counts collisions only); set box.boundary = \"periodic\" or \
             remove [driving]",
        ));
    }
    if sc.gravity().iter().any(|&g| g != 0.0) {
        return Err(ScenarioError::new(
            "driving",
            "cannot be combined with gravity (the steady states are homogeneous); remove \
             gravity or [driving]",
        ));
    }
    match d.kind {
        DrivingKind::Rescale => {
            if d.strength.is_some() {
                return Err(ScenarioError::new(
                    "driving.strength",
                    "applies to kind = \"white_noise\" only; remove it (rescale takes \
                     driving.temperature)",
                ));
            }
            if let Some(t) = d.temperature {
                positive("driving.temperature", t, "the rescaling temperature")?;
            }
        }
        DrivingKind::WhiteNoise => {
            if d.temperature.is_some() {
                return Err(ScenarioError::new(
                    "driving.temperature",
                    "applies to kind = \"rescale\" only; remove it (the white-noise gas \
                     reaches the temperature where heating balances the collisional loss, \
                     set by driving.strength)",
                ));
            }
            let Some(s) = d.strength else {
                return Err(ScenarioError::new(
                    "driving.strength",
                    "is missing; give xi0^2, the velocity variance per component and unit \
                     time (length^2/time^3), e.g. strength = 1.0",
                ));
            };
            positive("driving.strength", s, "the white-noise strength xi0^2")?;
        }
    }
    Ok(())
}
