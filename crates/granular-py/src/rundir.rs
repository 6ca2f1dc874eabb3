//! Run and sweep directories from Python: the library's [`RunDir`] names the files and
//! reads them (tables, arrays, snapshots, the summary); `granular/rundir.py` builds
//! `RunData`, `Snapshot` and `SweepData` from what these functions return.

use crate::errors::{guard, simulation_error};
use granular::output::npz::{NpzArray, NpzData};
use granular::run::dir::{Column, FileGroup};
use granular::run::sweep::SweepPlan;
use granular::run::{RunDir, RunError, RunFile, Table};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{PyArray1, PyArrayDyn};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// A run directory's read error as the Python exception for it: a missing file
/// `FileNotFoundError`, another I/O error `OSError`, a file that does not read as what it
/// should be `ValueError`.
fn read_error(e: RunError) -> PyErr {
    match &e {
        RunError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(e.to_string())
        }
        RunError::Io { .. } => PyOSError::new_err(e.to_string()),
        RunError::Read { .. } | RunError::Checkpoint { .. } => PyValueError::new_err(e.to_string()),
        _ => simulation_error(e),
    }
}

fn path_text(p: PathBuf) -> String {
    p.to_string_lossy().into_owned()
}

/// run_files(path) -> dict
///
/// The files of the run directory `path` that are present, by what they hold: `scenario`,
/// `summary`, `timeseries` (paths or None), `histograms`, `correlations`, `arrays` (dicts
/// of short name to path, e.g. `speed`, `pair_correlation`, `structure_factor`), and
/// `snapshots` (the snapshot files in output order).
#[pyfunction]
pub fn run_files<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let run = RunDir::new(path);
    let out = PyDict::new(py);
    for (key, file) in [
        ("scenario", RunFile::Scenario),
        ("summary", RunFile::Summary),
        ("timeseries", RunFile::TimeSeries),
    ] {
        let present = run.has(file).then(|| path_text(run.file(file)));
        out.set_item(key, present)?;
    }
    let groups = [
        (FileGroup::Histograms, PyDict::new(py)),
        (FileGroup::Correlations, PyDict::new(py)),
        (FileGroup::Arrays, PyDict::new(py)),
    ];
    for (group, key, file) in run.result_files() {
        if let Some((_, dict)) = groups.iter().find(|(g, _)| *g == group) {
            dict.set_item(key, path_text(file))?;
        }
    }
    let [(_, histograms), (_, correlations), (_, arrays)] = groups;
    out.set_item("histograms", histograms)?;
    out.set_item("correlations", correlations)?;
    out.set_item("arrays", arrays)?;
    let snapshots: Vec<String> = run
        .snapshots()
        .map_err(read_error)?
        .into_iter()
        .map(|f| path_text(f.path))
        .collect();
    out.set_item("snapshots", snapshots)?;
    Ok(out)
}

/// file_name(what) -> str
///
/// The name of a file of a run or sweep directory: `scenario`, `summary`, `timeseries`,
/// `sweep_table`, `sweep_meta`.
#[pyfunction]
pub fn file_name(what: &str) -> PyResult<&'static str> {
    Ok(match what {
        "scenario" => RunFile::Scenario.name(),
        "summary" => RunFile::Summary.name(),
        "timeseries" => RunFile::TimeSeries.name(),
        "sweep_table" => granular::run::sweep::SWEEP_TABLE,
        "sweep_meta" => granular::run::sweep::SWEEP_META,
        other => {
            return Err(PyValueError::new_err(format!(
                "file_name({other:?}): no such file; use scenario, summary, timeseries, \
sweep_table or sweep_meta"
            )));
        }
    })
}

/// sweep_member(point, seed) -> str
///
/// The directory of a sweep's member, relative to the sweep directory (`point_PPP/seed_SSS`).
#[pyfunction]
pub fn sweep_member(point: usize, seed: usize) -> String {
    SweepPlan::member_name(point, seed)
}

/// read_summary(path) -> str
///
/// `summary.json` of the run directory `path`, read with the library's typed reader and
/// written back as JSON (its fields in the file's order).
#[pyfunction]
pub fn read_summary(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    py.detach(|| {
        guard("reading a summary", || {
            let summary = RunDir::new(path).summary().map_err(read_error)?;
            serde_json::to_string(&summary).map_err(simulation_error)
        })
    })
}

/// read_table(path) -> tuple[list[str], list[numpy.ndarray | list[str]]]
///
/// A CSV file of a run or sweep directory (`#` lines are comments): the header and the
/// columns, each a float64 array where every entry is a number (NaN and inf included),
/// else a list of str.
#[pyfunction]
pub fn read_table<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Vec<String>, Bound<'py, PyList>)> {
    let table = py.detach(|| Table::read(&path)).map_err(read_error)?;
    let columns = PyList::empty(py);
    for (_, column) in table.columns() {
        match column {
            Column::Numbers(v) => columns.append(PyArray1::from_vec(py, v))?,
            Column::Text(v) => columns.append(v)?,
        }
    }
    Ok((table.header, columns))
}

/// One array of a `.npz` file as NumPy: numbers as arrays of their type and shape, strings
/// as `numpy.array` of str.
fn array<'py>(py: Python<'py>, a: NpzArray) -> PyResult<Bound<'py, PyAny>> {
    let shape: Vec<usize> = a.shape.iter().map(|&e| e as usize).collect();
    fn shaped<'py, T: numpy::Element>(
        py: Python<'py>,
        shape: &[usize],
        v: Vec<T>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let a = ArrayD::from_shape_vec(IxDyn(shape), v)
            .map_err(|e| PyValueError::new_err(format!("array of shape {shape:?}: {e}")))?;
        Ok(PyArrayDyn::from_owned_array(py, a).into_any())
    }
    match a.data {
        NpzData::F64(v) => shaped(py, &shape, v),
        NpzData::U32(v) => shaped(py, &shape, v),
        NpzData::U64(v) => shaped(py, &shape, v),
        NpzData::I64(v) => shaped(py, &shape, v),
        NpzData::Str(v) => py
            .import("numpy")?
            .call_method1("array", (v,))?
            .call_method1("reshape", (shape,)),
    }
}

/// read_arrays(path) -> dict[str, numpy.ndarray]
///
/// The arrays of a NumPy `.npz` file of a run directory, in file order.
#[pyfunction]
pub fn read_arrays<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let arrays = py
        .detach(|| granular::run::dir::read_arrays(&path))
        .map_err(read_error)?;
    let out = PyDict::new(py);
    for (name, a) in arrays {
        out.set_item(name, array(py, a)?)?;
    }
    Ok(out)
}

/// read_snapshot(path) -> dict
///
/// A snapshot file, read and checked by the library: `time` (float), `dimension` (int),
/// `positions` and `velocities` (float64 `(N, D)`), `radii`, `masses` (float64 `(N,)`),
/// `species` (uint32 `(N,)`), `species_names` (list of str).
#[pyfunction]
pub fn read_snapshot<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let s = py
        .detach(|| granular::run::read_snapshot(&path))
        .map_err(read_error)?;
    let n = s.radii.len();
    let d = s.dimension;
    let matrix = |v: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        let a = numpy::ndarray::Array2::from_shape_vec((n, d), v)
            .map_err(|e| simulation_error(format!("a snapshot array is not {n} x {d}: {e}")))?;
        Ok(numpy::PyArray2::from_owned_array(py, a).into_any())
    };
    let out = PyDict::new(py);
    out.set_item("time", s.time)?;
    out.set_item("dimension", d)?;
    out.set_item("positions", matrix(s.positions)?)?;
    out.set_item("velocities", matrix(s.velocities)?)?;
    out.set_item("radii", PyArray1::from_vec(py, s.radii))?;
    out.set_item("masses", PyArray1::from_vec(py, s.masses))?;
    out.set_item("species", PyArray1::from_vec(py, s.species))?;
    out.set_item("species_names", s.species_names)?;
    // Rough grains: (N,) in 2D, (N, 3) in 3D.
    if !s.angular_velocities.is_empty() {
        let w = s.angular_velocities;
        let spins = if d == 2 {
            PyArray1::from_vec(py, w).into_any()
        } else {
            let a = numpy::ndarray::Array2::from_shape_vec((n, 3), w).map_err(|e| {
                simulation_error(format!("snapshot angular velocities are not {n} x 3: {e}"))
            })?;
            numpy::PyArray2::from_owned_array(py, a).into_any()
        };
        out.set_item("angular_velocities", spins)?;
    }
    Ok(out)
}
