//! `[intruder]`: the Gillespie intruder engine in the scenario format (`engine = "intruder"`).
//!
//! The table names the model and then holds the fields of that model, flat and with
//! unknown keys rejected ([`tables`]); they are read into the engines' plain
//! configurations by [`OneDTable::config`] and the like (a tabulated bath's file is read
//! then, [`bath_file`]):
//!
//! * `model = "1d"`: [`OneDTable`] (the 1D intruder, G-8 to G-17 of the Gillespie
//!   intruder paper; G-18 checks it in a Gaussian bath);
//! * `model = "needle"`: [`NeedleTable`] (the 2D needle, G-20 to G-30);
//! * `model = "dsmc-twin"`: the fields of [`OneDTable`] plus `bath_particles`
//!   ([`DsmcTwinTable`], section 4 of the paper);
//! * `model = "disk"` (with `dimension = 2`, the default) and `model = "sphere"` (with
//!   `dimension = 3`): [`BallTable`], a smooth disk or sphere in an isotropic bath (G-31
//!   to G-45, `docs/intruder.md`); `method = "dsmc-twin"` runs its DSMC twin.
//!
//! The grain tables (`[box]`, `[[species]]`, `[initial]`, `[collisions]`) do not apply.

pub mod bath_file;
pub(crate) mod tables;

pub use tables::{BallMethodKey, BallTable, BathTable, DsmcTwinTable, NeedleTable, OneDTable};

use serde::de::Error as _;
use serde::ser::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::validate::positive as positive_in_range;
use super::{Scenario, ScenarioError};
use crate::intruder::ball::BallParams;
use crate::intruder::needle::NeedleParams;
use crate::intruder::one_d::Intruder1dParams;

/// The `[intruder]` table: which model, with that model's configuration.
#[derive(Clone, Debug, PartialEq)]
pub enum IntruderSpec {
    /// `model = "1d"`: one-dimensional intruder (section 3.1).
    OneD(OneDTable),
    /// `model = "needle"`: two-dimensional needle (section 3.2).
    Needle(NeedleTable),
    /// `model = "dsmc-twin"`: DSMC version of the 1D intruder (section 4).
    DsmcTwin(DsmcTwinTable),
    /// `model = "disk"`: a disk in a 2D bath (G-31 to G-45).
    Disk(BallTable),
    /// `model = "sphere"`: a sphere in a 3D bath (G-31 to G-45).
    Sphere(BallTable),
}

/// The accepted `model` values.
pub(crate) const MODELS: &str = "\"1d\", \"needle\", \"dsmc-twin\", \"disk\" or \"sphere\"";

impl IntruderSpec {
    /// The `model` name as written in the scenario.
    pub fn model(&self) -> &'static str {
        match self {
            IntruderSpec::OneD(_) => "1d",
            IntruderSpec::Needle(_) => "needle",
            IntruderSpec::DsmcTwin(_) => "dsmc-twin",
            IntruderSpec::Disk(_) => "disk",
            IntruderSpec::Sphere(_) => "sphere",
        }
    }

    /// The dimension of the intruder's motion: 1 for the `1d` and `dsmc-twin` models, 2 for
    /// the needle and the disk, 3 for the sphere.
    pub fn dimension(&self) -> usize {
        match self {
            IntruderSpec::Needle(_) | IntruderSpec::Disk(_) => 2,
            IntruderSpec::Sphere(_) => 3,
            IntruderSpec::OneD(_) | IntruderSpec::DsmcTwin(_) => 1,
        }
    }

    /// The 1D system's table (for the `1d` and `dsmc-twin` models).
    pub(crate) fn one_d(&self) -> Option<&OneDTable> {
        match self {
            IntruderSpec::OneD(c) => Some(c),
            IntruderSpec::DsmcTwin(c) => Some(&c.intruder),
            _ => None,
        }
    }

    /// The disk's or sphere's table, with its dimension.
    pub(crate) fn ball(&self) -> Option<(&BallTable, usize)> {
        match self {
            IntruderSpec::Disk(c) => Some((c, 2)),
            IntruderSpec::Sphere(c) => Some((c, 3)),
            _ => None,
        }
    }

    /// The `bath` table of the models that have one (all but the needle).
    pub(crate) fn bath(&self) -> Option<&BathTable> {
        match self {
            IntruderSpec::OneD(c) => Some(&c.bath),
            IntruderSpec::DsmcTwin(c) => Some(&c.intruder.bath),
            IntruderSpec::Disk(c) | IntruderSpec::Sphere(c) => Some(&c.bath),
            IntruderSpec::Needle(_) => None,
        }
    }
}

impl Serialize for IntruderSpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let body = match self {
            IntruderSpec::OneD(c) => toml::Table::try_from(c),
            IntruderSpec::Needle(c) => toml::Table::try_from(c),
            IntruderSpec::DsmcTwin(c) => toml::Table::try_from(&c.intruder),
            IntruderSpec::Disk(c) | IntruderSpec::Sphere(c) => toml::Table::try_from(c),
        };
        let mut table = body.map_err(S::Error::custom)?;
        if let IntruderSpec::DsmcTwin(c) = self {
            table.insert(
                "bath_particles".into(),
                toml::Value::Integer(c.bath_particles as i64),
            );
        }
        table.insert("model".into(), toml::Value::String(self.model().into()));
        table.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for IntruderSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut table = toml::Table::deserialize(deserializer)?;
        let model = match table.remove("model") {
            Some(toml::Value::String(m)) => m,
            Some(other) => {
                return Err(D::Error::custom(format!(
                    "`intruder.model` is {other}; use {MODELS}"
                )));
            }
            None => {
                return Err(D::Error::custom(format!(
                    "missing field `intruder.model`: add model = {MODELS} to [intruder]"
                )));
            }
        };
        // Name the table in the errors of the model's own fields.
        let wrap = |e: toml::de::Error| {
            let msg = e
                .message()
                .replace("unknown field `", "unknown field `intruder.");
            D::Error::custom(format!("{msg} (in [intruder], model = \"{model}\")"))
        };
        match model.as_str() {
            "1d" => OneDTable::deserialize(table)
                .map(IntruderSpec::OneD)
                .map_err(wrap),
            "needle" => NeedleTable::deserialize(table)
                .map(IntruderSpec::Needle)
                .map_err(wrap),
            "disk" => BallTable::deserialize(table)
                .map(IntruderSpec::Disk)
                .map_err(wrap),
            "sphere" => BallTable::deserialize(table)
                .map(IntruderSpec::Sphere)
                .map_err(wrap),
            "dsmc-twin" => {
                let bath_particles = match table.remove("bath_particles") {
                    None => DsmcTwinTable::default().bath_particles,
                    Some(toml::Value::Integer(n)) if n >= 1 => n as usize,
                    Some(other) => {
                        return Err(D::Error::custom(format!(
                            "`intruder.bath_particles` is {other}; give the number of stored bath velocities, an integer >= 1 (e.g. 10000)"
                        )));
                    }
                };
                let intruder = OneDTable::deserialize(table).map_err(wrap)?;
                Ok(IntruderSpec::DsmcTwin(DsmcTwinTable {
                    intruder,
                    bath_particles,
                }))
            }
            other => Err(D::Error::custom(format!(
                "`intruder.model` is \"{other}\"; use {MODELS}"
            ))),
        }
    }
}

fn err(key: &str, message: String) -> ScenarioError {
    ScenarioError::new(format!("intruder.{key}"), message)
}

fn positive(key: &str, x: f64, what: &str) -> Result<(), ScenarioError> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(err(
            key,
            format!("is {x}; {what} must be positive and finite"),
        ))
    }
}

fn restitution(x: f64) -> Result<(), ScenarioError> {
    if (0.0..=1.0).contains(&x) {
        Ok(())
    } else {
        Err(err(
            "restitution",
            format!(
                "is {x}; the coefficient of restitution alpha must lie in [0, 1] (1 = elastic)"
            ),
        ))
    }
}

fn grid(
    sample_interval: Option<f64>,
    transient: Option<f64>,
    bins: usize,
) -> Result<(), ScenarioError> {
    if let Some(dt) = sample_interval {
        positive(
            "sample_interval",
            dt,
            "the averaging grid spacing (time units)",
        )?;
    }
    if let Some(t) = transient
        && !(t >= 0.0 && t.is_finite())
    {
        return Err(err(
            "transient",
            format!("is {t}; give the time discarded before averaging, >= 0"),
        ));
    }
    if bins == 0 {
        return Err(err(
            "histogram_bins",
            "is 0; use at least 1 bin (default 120)".into(),
        ));
    }
    Ok(())
}

fn validate_1d(c: &OneDTable) -> Result<(), ScenarioError> {
    positive("mass", c.mass, "the intruder mass M")?;
    positive("bath_mass", c.bath_mass, "the bath particle mass m")?;
    positive("bath_density", c.bath_density, "the bath density rho")?;
    restitution(c.restitution)?;
    if !c.initial_velocity.is_finite() {
        return Err(err(
            "initial_velocity",
            format!("is {}; give a finite velocity", c.initial_velocity),
        ));
    }
    if let Some(h) = c.histogram_max {
        positive("histogram_max", h, "the histogram half-width")?;
    }
    grid(c.sample_interval, c.transient, c.histogram_bins)?;
    match &c.bath {
        BathTable::Gaussian { temperature } | BathTable::PowerLaw { temperature } => {
            positive("bath.temperature", *temperature, "the bath temperature T_B")?;
        }
        BathTable::Tabulated { file, points } => {
            if file.is_some() && points.is_some() {
                return Err(err(
                    "bath",
                    "is tabulated with both file and points; keep one (file = \"path\" or points = [[v, f], ...])".into(),
                ));
            }
            if file.is_none() && points.is_none() {
                return Err(err(
                    "bath",
                    "is tabulated without data; give file = \"path\" (two columns v f, relative to the scenario file) or points = [[v, f], ...]".into(),
                ));
            }
        }
    }
    // Everything else (tabulated points, files given by absolute path) by the engine's
    // own constructor; relative files are checked when the run starts.
    let relative_file = matches!(&c.bath, BathTable::Tabulated { file: Some(f), .. }
        if std::path::Path::new(f.as_str()).is_relative());
    if !relative_file {
        c.config()
            .and_then(|c| Intruder1dParams::new(&c))
            .map_err(|e| {
                err(
                    "bath",
                    format!("{e}; fix the bath description (docs/scenario.md, [intruder])"),
                )
            })?;
    }
    Ok(())
}

fn validate_needle(c: &NeedleTable) -> Result<(), ScenarioError> {
    positive("mass", c.mass, "the needle mass M")?;
    positive("bath_mass", c.bath_mass, "the bath particle mass m")?;
    positive("length", c.length, "the needle length L")?;
    positive("bath_density", c.bath_density, "the bath density rho")?;
    positive(
        "bath_temperature",
        c.bath_temperature,
        "the bath temperature T_B",
    )?;
    if let Some(i) = c.moment_of_inertia {
        positive("moment_of_inertia", i, "the moment of inertia I")?;
    }
    positive(
        "time_tolerance",
        c.time_tolerance,
        "the Eq. 23 tolerance (e.g. 1e-12)",
    )?;
    positive(
        "histogram_width",
        c.histogram_width,
        "the histogram half-width in thermal widths",
    )?;
    restitution(c.restitution)?;
    grid(c.sample_interval, c.transient, c.histogram_bins)?;
    NeedleParams::new(&c.config())
        .map_err(|e| err("model", format!("{e}; fix that field of [intruder]")))?;
    Ok(())
}

/// A disk or sphere: the model against `dimension`, the magnitudes, `bath_particles`
/// against `method`, then the engine's own checks (errors name `intruder.<key>`).
fn validate_ball(
    c: &BallTable,
    model: &str,
    dimension: usize,
    scenario_dimension: usize,
) -> Result<(), ScenarioError> {
    if scenario_dimension != dimension {
        let other = if dimension == 2 { "sphere" } else { "disk" };
        return Err(err(
            "model",
            format!(
                "is \"{model}\", which moves in {dimension} dimensions, but dimension is {scenario_dimension} (2 when not given); set dimension = {dimension} at the top of the scenario, or use model = \"{other}\""
            ),
        ));
    }
    let key = |k: &str| format!("intruder.{k}");
    positive_in_range(&key("radius"), c.radius, "the intruder radius R")?;
    positive_in_range(&key("mass"), c.mass, "the intruder mass M")?;
    positive_in_range(&key("bath_mass"), c.bath_mass, "the bath particle mass m")?;
    positive_in_range(
        &key("bath_density"),
        c.bath_density,
        "the bath number density rho",
    )?;
    if let BathTable::Gaussian { temperature } | BathTable::PowerLaw { temperature } = &c.bath {
        positive_in_range(
            &key("bath.temperature"),
            *temperature,
            "the bath temperature T_B",
        )?;
    }
    restitution(c.restitution)?;
    grid(c.sample_interval, c.transient, c.histogram_bins)?;
    match (c.method, c.bath_particles) {
        (BallMethodKey::DsmcTwin, Some(0)) => {
            return Err(err(
                "bath_particles",
                "is 0; store at least one bath velocity (e.g. 10000)".into(),
            ));
        }
        (BallMethodKey::Thinning | BallMethodKey::Direct, Some(n)) => {
            return Err(err(
                "bath_particles",
                format!(
                    "is {n}, but it is the sample size of the DSMC twin and method is not \"dsmc-twin\"; remove bath_particles or set method = \"dsmc-twin\""
                ),
            ));
        }
        _ => {}
    }
    if let BathTable::Tabulated { file, points } = &c.bath {
        if file.is_some() && points.is_some() {
            return Err(err(
                "bath",
                "is tabulated with both file and points; keep one (file = \"path\" or points = [[c, P], ...])".into(),
            ));
        }
        // A relative file is read when the run starts (relative to the scenario file).
        if matches!(file, Some(f) if std::path::Path::new(f.as_str()).is_relative()) {
            return Ok(());
        }
    }
    c.config(dimension)
        .and_then(|cfg| BallParams::new(&cfg, dimension))
        .map_err(|e| err(&e.key, e.message))?;
    Ok(())
}

/// Validates a scenario with `engine = "intruder"`: the `[intruder]` table and the stop
/// rules that make sense for a single driven particle (the shared `[stop]` and `[output]`
/// checks follow in `Scenario::validate`).
pub(super) fn validate(sc: &Scenario, spec: &IntruderSpec) -> Result<(), ScenarioError> {
    match spec {
        IntruderSpec::OneD(c) => validate_1d(c)?,
        IntruderSpec::DsmcTwin(c) => {
            validate_1d(&c.intruder)?;
            if c.bath_particles == 0 {
                return Err(err(
                    "bath_particles",
                    "is 0; store at least one bath velocity (e.g. 10000)".into(),
                ));
            }
        }
        IntruderSpec::Needle(c) => validate_needle(c)?,
        IntruderSpec::Disk(c) | IntruderSpec::Sphere(c) => {
            validate_ball(c, spec.model(), spec.dimension(), sc.dimension)?
        }
    }
    let stop = &sc.stop;
    if let Some(f) = stop.energy_fraction {
        return Err(ScenarioError::new(
            "stop.energy_fraction",
            format!(
                "is {f}, but the intruder is driven by a thermal bath and its energy does not decay; use stop.time, stop.collisions or stop.events"
            ),
        ));
    }
    Ok(())
}
