//! `granular.Scenario`: a scenario (TOML text plus `--set` overrides), validated exactly as
//! the command line validates it.

use crate::convert;
use crate::errors::scenario_error;
use granular::scenario::{GrainVectors, Scenario, ScenarioInput};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};
use std::path::{Path, PathBuf};

/// A validated scenario: TOML text (from a file, a string or a dict) with `--set`-style
/// overrides and per-grain NumPy arrays, for any engine (edmd, dsmc, intruder). Every
/// constructor and every override validates at once and raises ScenarioError with the
/// command line's message.
#[pyclass(name = "Scenario", module = "granular")]
#[derive(Clone)]
pub struct PyScenario {
    /// The TOML text the scenario was made from.
    pub source: String,
    /// Overrides `KEY=VALUE`, in the order given.
    pub overrides: Vec<String>,
    /// The file it was loaded from (error messages start with it; relative `.npz` paths
    /// are read from its directory), if any.
    pub origin: Option<String>,
    /// Per-grain arrays given as NumPy arrays (`species[i].positions`,
    /// `species[i].velocity.velocities`), put in after the overrides without becoming text.
    pub arrays: Vec<(String, GrainVectors)>,
    /// The validated scenario.
    pub resolved: Scenario,
}

impl PyScenario {
    /// Parses and validates `source` with `overrides` and `arrays`: every check but the
    /// pre-flight cost limits, which [`PyScenario::within_limits`] applies where a run
    /// starts (check(), Simulation(), run_sweep()) unless `insist=True`.
    pub fn build(
        py: Python<'_>,
        source: String,
        overrides: Vec<String>,
        origin: Option<String>,
    ) -> PyResult<Self> {
        Self::with_arrays(py, source, overrides, origin, Vec::new())
    }

    fn with_arrays(
        py: Python<'_>,
        source: String,
        mut overrides: Vec<String>,
        origin: Option<String>,
        arrays: Vec<(String, GrainVectors)>,
    ) -> PyResult<Self> {
        let read = |o: &[String]| read(py, &source, origin.as_deref(), &arrays, o, false);
        let mut resolved = read(&overrides)?;
        let absolute = origin
            .as_deref()
            .map(|p| granular::scenario::file_overrides(Path::new(p), &resolved))
            .unwrap_or_default();
        if !absolute.is_empty() {
            overrides.extend(absolute);
            resolved = read(&overrides)?;
        }
        Ok(Self {
            source,
            overrides,
            origin,
            arrays,
            resolved,
        })
    }

    /// A simulation's scenario (resumed, or changed in flight) as a `Scenario`: its arrays
    /// are kept as arrays, not written as text.
    pub fn of(py: Python<'_>, scenario: &Scenario, origin: Option<String>) -> PyResult<Self> {
        let (bare, arrays) = scenario.without_arrays();
        Self::with_arrays(py, bare.to_toml(), Vec::new(), origin, arrays)
    }

    /// The scenario of this one's text, arrays and `overrides` (validated; with the cost
    /// limits when `limits`).
    fn read(&self, py: Python<'_>, overrides: &[String], limits: bool) -> PyResult<Scenario> {
        read(
            py,
            &self.source,
            self.origin.as_deref(),
            &self.arrays,
            overrides,
            limits,
        )
    }

    /// The same scenario with more overrides (validated); an override of an array's key,
    /// or of a table above it, replaces the array.
    pub fn with_overrides(&self, py: Python<'_>, more: &[String]) -> PyResult<Self> {
        let mut next = self.clone();
        next.overrides.extend_from_slice(more);
        for o in more {
            next.arrays
                .retain(|(k, _)| !granular::scenario::overridden(o, k));
        }
        next.resolved = next.read(py, &next.overrides, false)?;
        Ok(next)
    }

    /// Keeps the NumPy array `vectors` at the per-grain `key` (in its canonical form
    /// `species[i].positions`), replacing one there; not validated.
    fn stash_array(&mut self, py: Python<'_>, key: &str, vectors: GrainVectors) -> PyResult<()> {
        let key = granular::scenario::array_key(key)
            .map(|(s, which)| format!("species[{s}].{which}"))
            .map_err(|e| scenario_error(py, &e, self.origin.as_deref()))?;
        self.arrays.retain(|(k, _)| *k != key);
        self.arrays.push((key, vectors));
        Ok(())
    }

    /// The pre-flight cost limits (outputs, collisions, bytes written; of the scenario and
    /// of every point of its sweep), unless `insist`: the ScenarioError of `granular run`
    /// (the key to change and `--insist`, which is `insist=True` here).
    pub fn within_limits(&self, py: Python<'_>, insist: bool) -> PyResult<()> {
        if insist {
            return Ok(());
        }
        self.read(py, &self.overrides, true).map(|_| ())
    }
}

/// The scenario of `source` (from the file `origin`, whose directory relative `.npz` paths
/// are read from), with `arrays` and `overrides`: validated, with the cost limits when
/// `limits`.
fn read(
    py: Python<'_>,
    source: &str,
    origin: Option<&str>,
    arrays: &[(String, GrainVectors)],
    overrides: &[String],
    limits: bool,
) -> PyResult<Scenario> {
    let base = origin.map(|o| Path::new(o).parent().unwrap_or(Path::new("")).to_path_buf());
    ScenarioInput {
        text: source,
        overrides,
        base: base.as_deref(),
        arrays,
        limits,
    }
    .read()
    .map_err(|e| scenario_error(py, &e, origin))
}

/// `KEY=VALUE` with the value written as TOML.
fn assignment(key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    let v = convert::to_toml(value, key)?;
    Ok(format!("{key}={v}"))
}

/// The scenario with `key` set to `value`: a NumPy array at a per-grain key
/// (`species[i].positions`, `species[i].velocity.velocities`) is kept as an array, anything
/// else becomes an override.
fn set_one(
    py: Python<'_>,
    scenario: &PyScenario,
    key: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<PyScenario> {
    if let Some(v) = crate::state::given_vectors(py, key, value)? {
        let mut next = scenario.clone();
        next.stash_array(py, key, v)?;
        return next.with_overrides(py, &[]);
    }
    scenario.with_overrides(py, &[assignment(key, value)?])
}

#[pymethods]
impl PyScenario {
    /// Scenario.load(path) -> Scenario
    ///
    /// Reads a scenario file (TOML, docs/scenario.md). A relative tabulated-bath `file` is
    /// taken relative to the scenario file, as `granular run` does. Raises ScenarioError
    /// (message starting with the path) or FileNotFoundError/OSError.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let text = granular::scenario::read_text_file(&path).map_err(|e| {
            let msg = match e.kind() {
                std::io::ErrorKind::InvalidInput | std::io::ErrorKind::InvalidData => e.to_string(),
                _ => format!("{}: {e}", path.display()),
            };
            if e.kind() == std::io::ErrorKind::NotFound {
                PyFileNotFoundError::new_err(msg)
            } else {
                PyOSError::new_err(msg)
            }
        })?;
        Self::build(py, text, Vec::new(), Some(path.display().to_string()))
    }

    /// Scenario.from_toml(text) -> Scenario
    ///
    /// A scenario from TOML text; error lines count from the first line of `text`.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: String) -> PyResult<Self> {
        Self::build(py, text, Vec::new(), None)
    }

    /// Scenario.from_dict(d) -> Scenario
    ///
    /// A scenario from a dict shaped like the TOML file (nested dicts for tables, a list of
    /// dicts for `species`; None values are left out), e.g.
    /// `{"engine": "edmd", "species": [{"name": "disk", "count": 100, "radius": 0.01}]}`.
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>) -> PyResult<Self> {
        let (d, arrays) = crate::state::take_grain_arrays(py, d)?;
        let toml::Value::Table(table) = convert::to_toml(d.as_any(), "")? else {
            unreachable!("a dict converts to a table")
        };
        let text = toml::to_string(&table)
            .map_err(|e| crate::errors::value_error(format!("the dict has no TOML form: {e}")))?;
        Self::with_arrays(py, text, Vec::new(), None, arrays)
    }

    /// set(key, value) -> None
    ///
    /// Overrides one key, exactly like `granular run --set KEY=VALUE`: `key` is dotted,
    /// with `[i]` (or `.i`) for entries of arrays of tables, e.g. "collisions.restitution"
    /// or "species[0].count"; `value` is a bool, int, float, str, list or dict. The result is
    /// validated at once (ScenarioError, and the scenario is left unchanged); use update()
    /// to change keys that only make sense together.
    fn set(&mut self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        *self = set_one(py, self, key, value)?;
        Ok(())
    }

    /// update(overrides) -> None
    ///
    /// Applies several `set` overrides (a mapping from dotted key to value) and validates
    /// once at the end, so that keys that depend on each other change together (e.g.
    /// "dimension" and "box.lengths").
    fn update(&mut self, py: Python<'_>, overrides: &Bound<'_, PyMapping>) -> PyResult<()> {
        let mut list = Vec::new();
        let mut next = self.clone();
        for item in overrides.items()?.iter() {
            let (k, v): (String, Bound<'_, PyAny>) = item.extract()?;
            match crate::state::given_vectors(py, &k, &v)? {
                Some(a) => next.stash_array(py, &k, a)?,
                None => list.push(assignment(&k, &v)?),
            }
        }
        *self = next.with_overrides(py, &list)?;
        Ok(())
    }

    /// to_toml() -> str
    ///
    /// The resolved scenario as TOML, every default filled in (what `granular check` prints).
    fn to_toml(&self) -> String {
        self.resolved.to_toml()
    }

    /// to_dict() -> dict
    ///
    /// The resolved scenario as nested dicts and lists (the TOML of to_toml()), with
    /// per-grain positions and velocities as float64 `(N, D)` NumPy arrays.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (bare, arrays) = self.resolved.without_arrays();
        let table: toml::Table = toml::from_str(&bare.to_toml()).map_err(|e| {
            crate::errors::simulation_error(format!("the resolved scenario did not parse: {e}"))
        })?;
        let dict = convert::table_to_dict(py, &table)?;
        let species = dict.get_item("species")?;
        for (key, v) in arrays {
            let (s, which) = granular::scenario::array_key(&key)
                .map_err(|e| crate::errors::simulation_error(e.to_string()))?;
            let a = crate::state::matrix(py, v.values().to_vec(), v.len(), v.width())?;
            let Some(entry) = species.as_ref().map(|l| l.get_item(s)).transpose()? else {
                continue;
            };
            if which == "positions" {
                entry.set_item("positions", a)?;
            } else {
                entry.get_item("velocity")?.set_item("velocities", a)?;
            }
        }
        Ok(dict)
    }

    /// check(insist=False) -> str
    ///
    /// Validates again, with the pre-flight cost limits of `granular check` (outputs,
    /// collisions, bytes written; docs/scenario.md, "Limits"), and returns the line
    /// `granular check` prints, e.g. "valid (10000 grains, 1 species)"; raises ScenarioError
    /// when invalid or above a limit. `insist=True` lifts the limits (`check --insist`).
    #[pyo3(signature = (insist = false))]
    fn check(&self, py: Python<'_>, insist: bool) -> PyResult<String> {
        self.within_limits(py, insist)?;
        let sc = &self.resolved;
        Ok(match &sc.intruder() {
            Some(i) => format!("valid (intruder engine, model {})", i.model()),
            None => format!(
                "valid ({} grains, {} species)",
                sc.particle_count(),
                sc.species().len()
            ),
        })
    }

    /// copy() -> Scenario
    ///
    /// An independent copy (overrides on it do not change this one).
    fn copy(&self) -> Self {
        self.clone()
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyScenario>()
            .map(|o| o.borrow().resolved == self.resolved)
            .unwrap_or(false)
    }

    fn __repr__(&self) -> String {
        let sc = &self.resolved;
        let what = match &sc.intruder() {
            Some(i) => format!("model={:?}", i.model().to_string()),
            None => format!(
                "dimension={}, particles={}",
                sc.dimension,
                sc.particle_count()
            ),
        };
        format!(
            "<granular.Scenario engine={:?} {what} seed={}{}>",
            self.engine(),
            sc.seed,
            self.origin
                .as_deref()
                .map(|o| format!(" from {o:?}"))
                .unwrap_or_default()
        )
    }

    /// The engine: "edmd", "dsmc" or "intruder".
    #[getter]
    fn engine(&self) -> String {
        match self.resolved.kind() {
            granular::scenario::EngineKind::Edmd => "edmd",
            granular::scenario::EngineKind::Dsmc => "dsmc",
            granular::scenario::EngineKind::Intruder => "intruder",
        }
        .into()
    }

    /// The box as a dict that freud (`freud.box.Box.from_box`) and HOOMD-blue take: "Lx",
    /// "Ly", "Lz" (0 in 2D), "xy", "xz", "yz" (0), "dimensions". SimulationError for the intruder
    /// engine, which has no box.
    #[getter(r#box)]
    fn simulation_box<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        crate::state::box_dict(py, &self.resolved)
    }

    /// Spatial dimension D (2: disks, 3: spheres; for the intruder engine 2 with the disk, 3
    /// with the sphere, unused by the other models).
    #[getter]
    fn dimension(&self) -> usize {
        self.resolved.dimension
    }

    /// The seed of all random streams (Simulation(seed=...) overrides it).
    #[getter]
    fn seed(&self) -> u64 {
        self.resolved.seed
    }

    /// Number of grains N over all species (0 for the intruder engine).
    #[getter]
    fn particle_count(&self) -> usize {
        self.resolved.particle_count()
    }

    /// The scenario's one-line description ("" when none).
    #[getter]
    fn description(&self) -> String {
        self.resolved.description.clone()
    }

    /// Species names, in the scenario's order.
    #[getter]
    fn species_names(&self) -> Vec<String> {
        self.resolved
            .species()
            .iter()
            .map(|s| s.name.clone())
            .collect()
    }

    /// The overrides applied so far, as `KEY=VALUE` strings (the `--set` arguments that
    /// give the same scenario on the command line).
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.overrides.clone()
    }

    /// The TOML text the scenario was made from (before the overrides).
    #[getter]
    fn source(&self) -> String {
        self.source.clone()
    }

    /// The file the scenario was loaded from, or None.
    #[getter]
    fn path(&self) -> Option<String> {
        self.origin.clone()
    }
}
