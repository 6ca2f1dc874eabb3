//! `granular.Scenario`: a scenario (TOML text plus `--set` overrides), validated exactly as
//! the command line validates it.

use crate::convert;
use crate::errors::scenario_error;
use granular::scenario::Scenario;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};
use std::path::{Path, PathBuf};

/// A validated scenario: TOML text (from a file, a string or a dict) with `--set`-style
/// overrides, for any engine (edmd, dsmc, intruder). Every constructor and every override
/// validates at once and raises ScenarioError with the command line's message.
#[pyclass(name = "Scenario", module = "granular")]
#[derive(Clone)]
pub struct PyScenario {
    /// The TOML text the scenario was made from.
    pub source: String,
    /// Overrides `KEY=VALUE`, in the order given.
    pub overrides: Vec<String>,
    /// The file it was loaded from (error messages start with it), if any.
    pub origin: Option<String>,
    /// The validated scenario.
    pub resolved: Scenario,
}

impl PyScenario {
    /// Parses and validates `source` with `overrides`: every check but the pre-flight cost
    /// limits, which [`PyScenario::within_limits`] applies where a run starts (check(),
    /// Simulation(), run_sweep()) unless `insist=True`.
    pub fn build(
        py: Python<'_>,
        source: String,
        mut overrides: Vec<String>,
        origin: Option<String>,
    ) -> PyResult<Self> {
        let mut resolved = Scenario::from_toml_insisting(&source, &overrides)
            .map_err(|e| scenario_error(py, &e, origin.as_deref()))?;
        if let Some(o) = origin
            .as_deref()
            .and_then(|p| granular::scenario::bath_file_override(Path::new(p), &resolved))
        {
            overrides.push(o);
            resolved = Scenario::from_toml_insisting(&source, &overrides)
                .map_err(|e| scenario_error(py, &e, origin.as_deref()))?;
        }
        Ok(Self {
            source,
            overrides,
            origin,
            resolved,
        })
    }

    /// The same scenario with more overrides (validated).
    pub fn with_overrides(&self, py: Python<'_>, more: &[String]) -> PyResult<Self> {
        let mut o = self.overrides.clone();
        o.extend_from_slice(more);
        let resolved = Scenario::from_toml_insisting(&self.source, &o)
            .map_err(|e| scenario_error(py, &e, self.origin.as_deref()))?;
        Ok(Self {
            source: self.source.clone(),
            overrides: o,
            origin: self.origin.clone(),
            resolved,
        })
    }

    /// The pre-flight cost limits (outputs, collisions, bytes written; of the scenario and
    /// of every point of its sweep), unless `insist`: the ScenarioError of `granular run`
    /// (the key to change and `--insist`, which is `insist=True` here).
    pub fn within_limits(&self, py: Python<'_>, insist: bool) -> PyResult<()> {
        if insist {
            return Ok(());
        }
        Scenario::from_toml(&self.source, &self.overrides)
            .map(|_| ())
            .map_err(|e| scenario_error(py, &e, self.origin.as_deref()))
    }
}

/// `KEY=VALUE` with the value written as TOML.
fn assignment(key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    let v = convert::to_toml(value, key)?;
    Ok(format!("{key}={v}"))
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
        let toml::Value::Table(table) = convert::to_toml(d.as_any(), "")? else {
            unreachable!("a dict converts to a table")
        };
        let text = toml::to_string(&table)
            .map_err(|e| crate::errors::value_error(format!("the dict has no TOML form: {e}")))?;
        Self::build(py, text, Vec::new(), None)
    }

    /// set(key, value) -> None
    ///
    /// Overrides one key, exactly like `granular run --set KEY=VALUE`: `key` is dotted,
    /// with `[i]` (or `.i`) for entries of arrays of tables, e.g. "collisions.restitution"
    /// or "species[0].count"; `value` is a bool, int, float, str, list or dict. The result is
    /// validated at once (ScenarioError, and the scenario is left unchanged); use update()
    /// to change keys that only make sense together.
    fn set(&mut self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let a = assignment(key, value)?;
        *self = self.with_overrides(py, &[a])?;
        Ok(())
    }

    /// update(overrides) -> None
    ///
    /// Applies several `set` overrides (a mapping from dotted key to value) and validates
    /// once at the end, so that keys that depend on each other change together (e.g.
    /// "dimension" and "box.lengths").
    fn update(&mut self, py: Python<'_>, overrides: &Bound<'_, PyMapping>) -> PyResult<()> {
        let mut list = Vec::new();
        for item in overrides.items()?.iter() {
            let (k, v): (String, Bound<'_, PyAny>) = item.extract()?;
            list.push(assignment(&k, &v)?);
        }
        *self = self.with_overrides(py, &list)?;
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
    /// The resolved scenario as nested dicts and lists (the TOML of to_toml()).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let table: toml::Table = toml::from_str(&self.resolved.to_toml()).map_err(|e| {
            crate::errors::simulation_error(format!("the resolved scenario did not parse: {e}"))
        })?;
        convert::table_to_dict(py, &table)
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
