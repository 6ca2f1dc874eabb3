//! The tables of `[intruder]` as the scenario format writes them (serde, defaults, unknown
//! keys rejected), one per model, and their conversion into the engines' plain
//! configurations ([`Intruder1dConfig`], [`NeedleConfig`], [`DsmcTwinConfig`],
//! [`BallConfig`], [`BallDsmcTwinConfig`]). A
//! tabulated bath given by `file` is read here ([`super::bath_file`]): the engines read no
//! file and know nothing of the scenario format.
//!
//! The defaults are the engines' ([`Intruder1dConfig::default`], ...): a table left empty
//! is the engine's default configuration.

use serde::{Deserialize, Serialize};

use super::bath_file;
use crate::intruder::ball::{
    BallConfig, BallDsmcTwinConfig, BallError, BallMethod, IsotropicBathConfig,
};
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
    pub(crate) fn config(&self) -> Result<BathConfig, BathError> {
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

impl BathTable {
    /// The bath of a disk or sphere intruder in `dimension` 2 or 3: a tabulated bath is
    /// the speed distribution `P(c)` (G-44), a `file` read here and checked as one (errors
    /// name `bath.file` and the file; inline `points` are checked by the engine, whose
    /// errors name `bath.points`).
    pub(crate) fn isotropic_config(
        &self,
        dimension: usize,
    ) -> Result<IsotropicBathConfig, BallError> {
        Ok(match self {
            BathTable::Gaussian { temperature } => IsotropicBathConfig::Gaussian {
                temperature: *temperature,
            },
            BathTable::PowerLaw { temperature } => IsotropicBathConfig::PowerLaw {
                temperature: *temperature,
            },
            BathTable::Tabulated {
                file: Some(f),
                points: _,
            } => {
                let file_error = |m: String| BallError::new("bath.file", m);
                let points = bath_file::read_columns(std::path::Path::new(f)).map_err(|e| {
                    file_error(format!(
                        "cannot be used: {e}; give a two-column file of speeds c >= 0 and densities P(c) >= 0"
                    ))
                })?;
                crate::intruder::ball::bath::SpeedTable::new(dimension, &points)
                    .map_err(|e| file_error(format!("is {f:?}, whose table {}", e.message)))?;
                IsotropicBathConfig::Tabulated { points }
            }
            BathTable::Tabulated {
                file: None,
                points: Some(pts),
            } => IsotropicBathConfig::Tabulated {
                points: pts.iter().map(|p| (p[0], p[1])).collect(),
            },
            BathTable::Tabulated {
                file: None,
                points: None,
            } => {
                return Err(BallError::new(
                    "bath",
                    "is tabulated without data; give file = \"path\" or points = [[c, P], ...] (speeds c >= 0)",
                ));
            }
        })
    }
}

/// `method` of a disk or sphere intruder: the Gillespie engine's event samplers, or its
/// DSMC twin (section 4 of the paper in `d` dimensions, G-45).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BallMethodKey {
    /// Thinning against the bound G-38 (any bath).
    #[default]
    Thinning,
    /// The paper's direct method in `d` dimensions (Gaussian bath only).
    Direct,
    /// The DSMC twin with `bath_particles` stored bath velocities.
    DsmcTwin,
}

/// `[intruder]` with `model = "disk"` (2D) or `model = "sphere"` (3D): a smooth ball of
/// radius `R` in an isotropic bath of point particles (G-31 to G-45). Field by field the
/// engine's [`BallConfig`], whose documentation gives units and defaults, plus
/// `bath_particles` for `method = "dsmc-twin"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BallTable {
    /// Intruder radius `R`.
    pub radius: f64,
    /// Intruder mass `M`.
    pub mass: f64,
    /// Bath particle mass `m`.
    pub bath_mass: f64,
    /// Coefficient of restitution `alpha` in `[0, 1]` (G-37).
    pub restitution: f64,
    /// Bath number density `rho` (1/length^d).
    pub bath_density: f64,
    /// `[intruder.bath]`; a tabulated bath is a speed distribution `P(c)` (G-44).
    pub bath: BathTable,
    /// Initial intruder velocity `V(0)`, `d` components (empty: at rest).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub initial_velocity: Vec<f64>,
    /// Averaging grid spacing; default the engine's.
    pub sample_interval: Option<f64>,
    /// Time discarded before averaging; default the engine's.
    pub transient: Option<f64>,
    /// `"thinning"`, `"direct"` or `"dsmc-twin"`.
    pub method: BallMethodKey,
    /// Histogram edge `h`; default the engine's.
    pub histogram_max: Option<f64>,
    /// Number of histogram bins.
    pub histogram_bins: usize,
    /// `method = "dsmc-twin"`: number of stored bath velocities (default 10000).
    pub bath_particles: Option<usize>,
}

impl Default for BallTable {
    fn default() -> Self {
        let c = BallConfig::default();
        Self {
            radius: c.radius,
            mass: c.mass,
            bath_mass: c.bath_mass,
            restitution: c.restitution,
            bath_density: c.bath_density,
            bath: BathTable::Gaussian {
                temperature: match c.bath {
                    IsotropicBathConfig::Gaussian { temperature } => temperature,
                    _ => 0.5,
                },
            },
            initial_velocity: c.initial_velocity,
            sample_interval: c.sample_interval,
            transient: c.transient,
            method: BallMethodKey::Thinning,
            histogram_max: c.histogram_max,
            histogram_bins: c.histogram_bins,
            bath_particles: None,
        }
    }
}

impl BallTable {
    /// The engine's configuration in `dimension` 2 or 3 (a tabulated bath `file` is read);
    /// for `method = "dsmc-twin"` the physical system of the twin (`method` thinning).
    pub(crate) fn config(&self, dimension: usize) -> Result<BallConfig, BallError> {
        Ok(BallConfig {
            radius: self.radius,
            mass: self.mass,
            bath_mass: self.bath_mass,
            restitution: self.restitution,
            bath_density: self.bath_density,
            bath: self.bath.isotropic_config(dimension)?,
            initial_velocity: self.initial_velocity.clone(),
            sample_interval: self.sample_interval,
            transient: self.transient,
            method: match self.method {
                BallMethodKey::Direct => BallMethod::Direct,
                BallMethodKey::Thinning | BallMethodKey::DsmcTwin => BallMethod::Thinning,
            },
            histogram_max: self.histogram_max,
            histogram_bins: self.histogram_bins,
        })
    }

    /// Whether the table runs the DSMC twin.
    pub(crate) fn is_twin(&self) -> bool {
        self.method == BallMethodKey::DsmcTwin
    }

    /// The DSMC twin's configuration (`bath_particles` default 10000).
    pub(crate) fn twin_config(&self, dimension: usize) -> Result<BallDsmcTwinConfig, BallError> {
        Ok(BallDsmcTwinConfig {
            ball: self.config(dimension)?,
            bath_particles: self
                .bath_particles
                .unwrap_or(BallDsmcTwinConfig::default().bath_particles),
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
    pub(crate) fn config(&self) -> Result<Intruder1dConfig, BathError> {
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
    pub(crate) fn config(&self) -> NeedleConfig {
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
    pub(crate) fn config(&self) -> Result<DsmcTwinConfig, BathError> {
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
        for d in [2, 3] {
            assert_eq!(
                BallTable::default().config(d).unwrap(),
                BallConfig::default()
            );
            let twin = BallTable {
                method: BallMethodKey::DsmcTwin,
                ..Default::default()
            };
            assert_eq!(twin.twin_config(d).unwrap(), BallDsmcTwinConfig::default());
        }
    }

    #[test]
    fn ball_table_round_trips() {
        let c: BallTable = toml::from_str(
            "radius = 0.25\nmethod = \"dsmc-twin\"\nbath_particles = 500\ninitial_velocity = [1.0, 0.0, 2.0]\n[bath]\nkind = \"power-law\"\ntemperature = 1.0",
        )
        .unwrap();
        assert_eq!(c.radius, 0.25);
        assert!(c.is_twin());
        assert_eq!(c.twin_config(3).unwrap().bath_particles, 500);
        let text = toml::to_string(&c).unwrap();
        assert_eq!(toml::from_str::<BallTable>(&text).unwrap(), c);
        assert!(toml::from_str::<BallTable>("raduis = 1.0").is_err());
    }

    #[test]
    fn a_speed_table_file_is_checked_as_a_speed_distribution() {
        let dir = tempfile::tempdir().unwrap();
        let good = dir.path().join("speeds.dat");
        std::fs::write(&good, "c P\n0 0\n1 1\n3 0\n").unwrap();
        let table = |f: &std::path::Path| BathTable::Tabulated {
            file: Some(f.display().to_string()),
            points: None,
        };
        assert_eq!(
            table(&good).isotropic_config(3).unwrap(),
            IsotropicBathConfig::Tabulated {
                points: vec![(0.0, 0.0), (1.0, 1.0), (3.0, 0.0)]
            }
        );
        let bad = dir.path().join("velocities.dat");
        std::fs::write(&bad, "-1 0\n0 1\n1 0\n").unwrap();
        let e = table(&bad).isotropic_config(2).unwrap_err();
        assert_eq!(e.key, "bath.file");
        assert!(
            e.message.contains("velocities.dat") && e.message.contains("speeds >= 0"),
            "{e}"
        );
        let e = table(&dir.path().join("missing.dat"))
            .isotropic_config(2)
            .unwrap_err();
        assert_eq!(e.key, "bath.file");
        assert!(e.message.contains("missing.dat"), "{e}");
    }
}
