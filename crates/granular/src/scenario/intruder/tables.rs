//! The tables of `[intruder]` as the scenario format writes them (serde, defaults, unknown
//! keys rejected), one per model, and their conversion into the engines' plain
//! configurations ([`Intruder1dConfig`], [`NeedleConfig`], [`DsmcTwinConfig`]). A
//! tabulated bath given by `file` is read here ([`super::bath_file`]): the engines read no
//! file and know nothing of the scenario format.
//!
//! The defaults are the engines' ([`Intruder1dConfig::default`], ...): a table left empty
//! is the engine's default configuration.

use serde::{Deserialize, Serialize};

use super::bath_file;
use crate::intruder::dsmc_twin::DsmcTwinConfig;
use crate::intruder::needle::NeedleMethod;
use crate::intruder::one_d::Method1d;
use crate::intruder::{BathConfig, BathError, Intruder1dConfig, NeedleConfig};

/// `[intruder.bath]`: the bath velocity distribution (`kind = "gaussian"`, `"power-law"` or
/// `"tabulated"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum BathTable {
    /// Gaussian, G-14, `a = m / (2 T_B)`.
    Gaussian {
        /// Bath temperature `T_B = m <v^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Power law, G-19, `a = m / T_B` (since `<v^2> = 1/a`).
    PowerLaw {
        /// Bath temperature `T_B = m <v^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Piecewise-linear density through the given points, normalised.
    Tabulated {
        /// Two-column text/CSV file `v f` (velocity units, density in 1/velocity); a
        /// relative path is relative to the scenario file.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        file: Option<String>,
        /// Inline points `[[v, f], ...]`, used when `file` is absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        points: Option<Vec<[f64; 2]>>,
    },
}

impl Default for BathTable {
    fn default() -> Self {
        BathTable::from(&BathConfig::default())
    }
}

impl From<&BathConfig> for BathTable {
    fn from(c: &BathConfig) -> Self {
        match c {
            BathConfig::Gaussian { temperature } => BathTable::Gaussian {
                temperature: *temperature,
            },
            BathConfig::PowerLaw { temperature } => BathTable::PowerLaw {
                temperature: *temperature,
            },
            BathConfig::Tabulated { points } => BathTable::Tabulated {
                file: None,
                points: Some(points.iter().map(|&(v, f)| [v, f]).collect()),
            },
        }
    }
}

impl BathTable {
    /// The engine's bath: a tabulated `file` is read and parsed here (relative to the
    /// working directory unless absolute; `Scenario` loading makes it absolute).
    pub fn config(&self) -> Result<BathConfig, BathError> {
        Ok(match self {
            BathTable::Gaussian { temperature } => BathConfig::Gaussian {
                temperature: *temperature,
            },
            BathTable::PowerLaw { temperature } => BathConfig::PowerLaw {
                temperature: *temperature,
            },
            BathTable::Tabulated {
                file: Some(f),
                points: _,
            } => BathConfig::Tabulated {
                points: bath_file::read(std::path::Path::new(f))?,
            },
            BathTable::Tabulated {
                file: None,
                points: Some(pts),
            } => BathConfig::Tabulated {
                points: pts.iter().map(|p| (p[0], p[1])).collect(),
            },
            BathTable::Tabulated {
                file: None,
                points: None,
            } => {
                return Err(BathError::Parameter(
                    "a tabulated bath needs `file` or `points`".into(),
                ));
            }
        })
    }
}

/// `[intruder]` with `model = "1d"` (and the fields of `"dsmc-twin"`): the 1D intruder,
/// G-8 to G-17 of the Gillespie intruder paper. Field by field the engine's
/// [`Intruder1dConfig`], whose documentation gives units and defaults.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OneDTable {
    /// Intruder mass `M`.
    pub mass: f64,
    /// Bath particle mass `m`.
    pub bath_mass: f64,
    /// Coefficient of restitution `alpha` in `[0, 1]` (G-17).
    pub restitution: f64,
    /// Bath number density `rho` (1/length), G-5 and G-6.
    pub bath_density: f64,
    /// `[intruder.bath]`.
    pub bath: BathTable,
    /// Initial intruder velocity `v1(0)`.
    pub initial_velocity: f64,
    /// Averaging grid spacing; default the engine's.
    pub sample_interval: Option<f64>,
    /// Time discarded before averaging; default the engine's.
    pub transient: Option<f64>,
    /// Event sampler: `"thinning"` or `"direct"`.
    pub method: Method1d,
    /// Histogram half-width `h`; default the engine's.
    pub histogram_max: Option<f64>,
    /// Number of histogram bins.
    pub histogram_bins: usize,
}

impl Default for OneDTable {
    fn default() -> Self {
        let c = Intruder1dConfig::default();
        Self {
            mass: c.mass,
            bath_mass: c.bath_mass,
            restitution: c.restitution,
            bath_density: c.bath_density,
            bath: BathTable::from(&c.bath),
            initial_velocity: c.initial_velocity,
            sample_interval: c.sample_interval,
            transient: c.transient,
            method: c.method,
            histogram_max: c.histogram_max,
            histogram_bins: c.histogram_bins,
        }
    }
}

impl OneDTable {
    /// The engine's configuration (a tabulated bath `file` is read).
    pub fn config(&self) -> Result<Intruder1dConfig, BathError> {
        Ok(Intruder1dConfig {
            mass: self.mass,
            bath_mass: self.bath_mass,
            restitution: self.restitution,
            bath_density: self.bath_density,
            bath: self.bath.config()?,
            initial_velocity: self.initial_velocity,
            sample_interval: self.sample_interval,
            transient: self.transient,
            method: self.method,
            histogram_max: self.histogram_max,
            histogram_bins: self.histogram_bins,
        })
    }
}

/// `[intruder]` with `model = "needle"`: the 2D needle, G-20 to G-30. Field by field the
/// engine's [`NeedleConfig`], whose documentation gives units and defaults.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NeedleTable {
    /// Needle mass `M`.
    pub mass: f64,
    /// Bath particle mass `m`.
    pub bath_mass: f64,
    /// Needle length `L`.
    pub length: f64,
    /// Moment of inertia `I` about the centre; default `M L^2 / 12`.
    pub moment_of_inertia: Option<f64>,
    /// Coefficient of restitution `alpha` in `[0, 1]` (G-29).
    pub restitution: f64,
    /// Bath areal number density `rho`.
    pub bath_density: f64,
    /// Bath temperature `T_B`.
    pub bath_temperature: f64,
    /// Initial centre-of-mass velocity `(v1x, v1y)`.
    pub initial_velocity: [f64; 2],
    /// Initial angular velocity `omega`.
    pub initial_angular_velocity: f64,
    /// Initial orientation `theta_0` (radians).
    pub initial_angle: f64,
    /// Event sampler: `"thinning"` or `"paper"`.
    pub method: NeedleMethod,
    /// Tolerance of G-23 (paper method only).
    pub time_tolerance: f64,
    /// Averaging grid spacing; default the engine's.
    pub sample_interval: Option<f64>,
    /// Time discarded before averaging; default the engine's.
    pub transient: Option<f64>,
    /// Histogram half-width in equipartition widths.
    pub histogram_width: f64,
    /// Number of histogram bins.
    pub histogram_bins: usize,
}

impl From<&NeedleConfig> for NeedleTable {
    fn from(c: &NeedleConfig) -> Self {
        Self {
            mass: c.mass,
            bath_mass: c.bath_mass,
            length: c.length,
            moment_of_inertia: c.moment_of_inertia,
            restitution: c.restitution,
            bath_density: c.bath_density,
            bath_temperature: c.bath_temperature,
            initial_velocity: c.initial_velocity,
            initial_angular_velocity: c.initial_angular_velocity,
            initial_angle: c.initial_angle,
            method: c.method,
            time_tolerance: c.time_tolerance,
            sample_interval: c.sample_interval,
            transient: c.transient,
            histogram_width: c.histogram_width,
            histogram_bins: c.histogram_bins,
        }
    }
}

impl Default for NeedleTable {
    fn default() -> Self {
        NeedleTable::from(&NeedleConfig::default())
    }
}

impl NeedleTable {
    /// The engine's configuration.
    pub fn config(&self) -> NeedleConfig {
        NeedleConfig {
            mass: self.mass,
            bath_mass: self.bath_mass,
            length: self.length,
            moment_of_inertia: self.moment_of_inertia,
            restitution: self.restitution,
            bath_density: self.bath_density,
            bath_temperature: self.bath_temperature,
            initial_velocity: self.initial_velocity,
            initial_angular_velocity: self.initial_angular_velocity,
            initial_angle: self.initial_angle,
            method: self.method,
            time_tolerance: self.time_tolerance,
            sample_interval: self.sample_interval,
            transient: self.transient,
            histogram_width: self.histogram_width,
            histogram_bins: self.histogram_bins,
        }
    }
}

/// `[intruder]` with `model = "dsmc-twin"`: the fields of the 1D intruder plus
/// `bath_particles` (section 4 of the paper).
#[derive(Clone, Debug, PartialEq)]
pub struct DsmcTwinTable {
    /// The physical system, as `model = "1d"` (`method` is ignored).
    pub intruder: OneDTable,
    /// Number of stored bath velocities `n_bath`.
    pub bath_particles: usize,
}

impl Default for DsmcTwinTable {
    fn default() -> Self {
        Self {
            intruder: OneDTable::default(),
            bath_particles: DsmcTwinConfig::default().bath_particles,
        }
    }
}

impl DsmcTwinTable {
    /// The engine's configuration (a tabulated bath `file` is read).
    pub fn config(&self) -> Result<DsmcTwinConfig, BathError> {
        Ok(DsmcTwinConfig {
            intruder: self.intruder.config()?,
            bath_particles: self.bath_particles,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_reject_unknown_fields_and_round_trip() {
        assert!(toml::from_str::<OneDTable>("masss = 1.0").is_err());
        let c: OneDTable =
            toml::from_str("mass = 2.0\n[bath]\nkind = \"power-law\"\ntemperature = 1.0").unwrap();
        assert_eq!(c.mass, 2.0);
        assert_eq!(c.bath, BathTable::PowerLaw { temperature: 1.0 });
        let text = toml::to_string(&c).unwrap();
        assert_eq!(toml::from_str::<OneDTable>(&text).unwrap(), c);
        assert!(toml::from_str::<BathTable>("kind = \"gaussian\"\ntemp = 1.0").is_err());
        let n = NeedleTable {
            moment_of_inertia: Some(0.2),
            method: NeedleMethod::Paper,
            ..Default::default()
        };
        let text = toml::to_string(&n).unwrap();
        assert_eq!(toml::from_str::<NeedleTable>(&text).unwrap(), n);
        assert!(toml::from_str::<NeedleTable>("lenght = 2.0").is_err());
    }

    #[test]
    fn empty_tables_are_the_engine_defaults() {
        assert_eq!(
            OneDTable::default().config().unwrap(),
            Intruder1dConfig::default()
        );
        assert_eq!(NeedleTable::default().config(), NeedleConfig::default());
        assert_eq!(
            DsmcTwinTable::default().config().unwrap(),
            DsmcTwinConfig::default()
        );
    }
}
