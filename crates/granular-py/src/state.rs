//! Per-grain arrays between NumPy and the library, both ways: positions or velocities of
//! every grain in input order written straight into a NumPy array's own buffer
//! (`Simulation::positions_into` / `velocities_into`), the arrays a user gives (checked
//! float64 `(N, D)`: `set_state`, `from_snapshot`, a scenario's per-grain keys), and
//! snapshots as NumPy arrays.

use crate::errors::value_error;
use granular::Simulation;
use numpy::{PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Which per-grain vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Positions (wrapped into the box).
    Positions,
    /// Velocities.
    Velocities,
}

/// A new float64 `(n, d)` array of grain ids `0..n`, or `None` when the engine has no
/// grains (the caller takes a snapshot instead).
///
/// The array is allocated by NumPy (`zeros`: NumPy asks Linux for huge pages for buffers
/// of 4 MiB and more, so 10^6 grains fault in a few 2 MiB pages instead of 4 000 small
/// ones) and filled by the library with the interpreter lock released. Allocating a Rust
/// vector and handing it over cost about as much in page faults as the copy itself.
pub fn by_id<'py>(
    py: Python<'py>,
    sim: &Simulation,
    what: Quantity,
) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
    if sim.engine_name() == "intruder" {
        return Ok(None);
    }
    let shape = [sim.particle_count(), sim.dimension()];
    let array = PyArray2::<f64>::zeros(py, shape, false);
    let filled = {
        let mut view = array.try_readwrite()?;
        let out = view.as_slice_mut()?;
        py.detach(|| match what {
            Quantity::Positions => sim.positions_into(out),
            Quantity::Velocities => sim.velocities_into(out),
        })
    };
    Ok(filled.then_some(array))
}

/// A per-grain array given by the user (`positions`, `velocities`) as the row-major
/// values of a float64 `(n, d)` array: a NumPy array must be float64 (another dtype is
/// refused, not converted silently); a list of rows is converted. TypeError / ValueError
/// name the array, what it is and what to give.
pub fn grain_array(
    py: Python<'_>,
    name: &str,
    value: &Bound<'_, PyAny>,
    n: usize,
    d: usize,
) -> PyResult<Vec<f64>> {
    let what = format!(
        "one row of {d} per grain, in input order (grain i is the i-th grain of the \
scenario's species list)"
    );
    values(py, name, value, &[n, d], &what)
}

/// The angular velocities given by the user for rough grains in `d` dimensions: float64
/// `(n,)` in 2D (`ω_z`), `(n, 3)` in 3D, as [`grain_array`].
pub fn spin_array(
    py: Python<'_>,
    value: &Bound<'_, PyAny>,
    n: usize,
    d: usize,
) -> PyResult<Vec<f64>> {
    if d == 2 {
        values(
            py,
            "angular_velocities",
            value,
            &[n],
            "ω_z of each disk, about the axis normal to the plane, in input order",
        )
    } else {
        values(
            py,
            "angular_velocities",
            value,
            &[n, 3],
            "one row ω_x, ω_y, ω_z per sphere, in input order",
        )
    }
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [a] => format!("({a},)"),
        s => format!(
            "({})",
            s.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The row-major values of a float64 array of shape `shape` given as `name`.
fn values(
    py: Python<'_>,
    name: &str,
    value: &Bound<'_, PyAny>,
    shape: &[usize],
    what: &str,
) -> PyResult<Vec<f64>> {
    let numpy = py.import("numpy")?;
    let ndarray = numpy.getattr("ndarray")?;
    let array = if value.is_instance(&ndarray)? {
        let dtype = value.getattr("dtype")?;
        if dtype.str()?.to_str()? != "float64" {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "`{name}` has dtype {}; give float64 values (for example \
np.asarray({name}, dtype=np.float64))",
                dtype.str()?
            )));
        }
        value.clone()
    } else {
        numpy
            .call_method1("asarray", (value, numpy.getattr("float64")?))
            .map_err(|e| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "`{name}` is not an array of numbers ({e}); give a float64 NumPy array of \
shape {}",
                    shape_text(shape)
                ))
            })?
    };
    let given: Vec<usize> = array.getattr("shape")?.extract()?;
    if given != shape {
        return Err(value_error(format!(
            "`{name}` has shape {}; give shape {}: {what}",
            shape_text(&given),
            shape_text(shape)
        )));
    }
    let typed = array.cast::<PyArrayDyn<f64>>()?;
    let view = typed.try_readonly()?;
    // `as_slice` also takes Fortran-ordered arrays (a transposed array), whose memory is
    // column-major: only a C-ordered array is copied as it lies.
    Ok(match view.as_slice() {
        Ok(s) if typed.is_c_contiguous() => s.to_vec(),
        _ => view.as_array().iter().copied().collect(),
    })
}

/// The box of a scenario with grains in the form other analysis packages take (freud's
/// `freud.box.Box.from_box`, HOOMD-blue's box dict): `Lx`, `Ly`, `Lz` (0 in 2D), the tilts
/// `xy`, `xz`, `yz` (0: granular's boxes are rectangular), `dimensions`. SimulationError
/// for the intruder engine, which has no box.
pub fn box_dict<'py>(
    py: Python<'py>,
    scenario: &granular::Scenario,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    if scenario.kind() == granular::scenario::EngineKind::Intruder {
        return Err(crate::errors::simulation_error(
            "the intruder engine has no box (its bath is infinite); box is for edmd and dsmc",
        ));
    }
    let lengths = scenario.lengths();
    let d = pyo3::types::PyDict::new(py);
    for (k, name) in ["Lx", "Ly", "Lz"].iter().enumerate() {
        d.set_item(*name, lengths.get(k).copied().unwrap_or(0.0))?;
    }
    for tilt in ["xy", "xz", "yz"] {
        d.set_item(tilt, 0.0)?;
    }
    d.set_item("dimensions", scenario.dimension)?;
    Ok(d)
}

/// A NumPy array given at a per-grain key of a scenario (`species[i].positions`,
/// `species[i].velocity.velocities`) as the scenario's vectors, without any text; `None`
/// when `value` is no NumPy array or `key` takes none (the value then goes through TOML as
/// before). The array must be float64 `(N, D)` (TypeError, ValueError naming the key).
pub fn given_vectors(
    py: Python<'_>,
    key: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<Option<granular::scenario::GrainVectors>> {
    let ndarray = py.import("numpy")?.getattr("ndarray")?;
    if !value.is_instance(&ndarray)? || granular::scenario::array_key(key).is_err() {
        return Ok(None);
    }
    let shape: Vec<usize> = value.getattr("shape")?.extract()?;
    let [n, d] = shape[..] else {
        return Err(value_error(format!(
            "`{key}` has shape {}; give an (N, D) array: one row of D numbers per grain",
            shape_text(&shape)
        )));
    };
    let what = "one row per grain of the species, in order";
    let values = values(py, key, value, &[n, d], what)?;
    granular::scenario::GrainVectors::given(values, d)
        .map(Some)
        .ok_or_else(|| {
            value_error(format!(
                "`{key}` has shape {}; give at least one column",
                shape_text(&shape)
            ))
        })
}

/// Per-grain arrays by scenario key.
pub type GivenArrays = Vec<(String, granular::scenario::GrainVectors)>;

/// A copy of the scenario dict `d` without the NumPy arrays at its per-grain keys, and
/// those arrays by key. A species' `velocity` table that held per-grain `velocities` goes
/// with them (the arrays make the velocities per grain).
pub fn take_grain_arrays<'py>(
    py: Python<'py>,
    d: &Bound<'py, pyo3::types::PyDict>,
) -> PyResult<(Bound<'py, pyo3::types::PyDict>, GivenArrays)> {
    use pyo3::types::{PyDict, PyList};
    let out = d.copy()?;
    let mut arrays = Vec::new();
    let Some(species) = d.get_item("species")? else {
        return Ok((out, arrays));
    };
    let Ok(list) = species.cast::<PyList>() else {
        return Ok((out, arrays));
    };
    let copied = PyList::empty(py);
    for (i, entry) in list.iter().enumerate() {
        let Ok(entry) = entry.cast::<PyDict>() else {
            copied.append(entry)?;
            continue;
        };
        let entry = entry.copy()?;
        let key = format!("species[{i}].positions");
        if let Some(p) = entry.get_item("positions")?
            && let Some(v) = given_vectors(py, &key, &p)?
        {
            entry.del_item("positions")?;
            arrays.push((key, v));
        }
        let key = format!("species[{i}].velocity.velocities");
        if let Some(velocity) = entry.get_item("velocity")?
            && let Ok(velocity) = velocity.cast::<PyDict>()
            && let Some(given) = velocity.get_item("velocities")?
            && let Some(v) = given_vectors(py, &key, &given)?
        {
            let per_grain = velocity.iter().all(|(k, x)| {
                let k = k.extract::<String>().unwrap_or_default();
                k == "velocities"
                    || (k == "distribution"
                        && x.extract::<String>().is_ok_and(|d| d == "per_grain"))
            });
            if !per_grain {
                return Err(value_error(format!(
                    "`species[{i}].velocity`: `velocities` (one per grain) goes with \
                     distribution = \"per_grain\" and nothing else; remove the other keys"
                )));
            }
            entry.del_item("velocity")?;
            arrays.push((key, v));
        }
        copied.append(entry)?;
    }
    out.set_item("species", copied)?;
    Ok((out, arrays))
}

/// A row-major `n x d` vector as a NumPy array of shape `(n, d)`, without copying it again.
pub fn matrix<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    n: usize,
    d: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let a = numpy::ndarray::Array2::from_shape_vec((n, d), values).map_err(|e| {
        crate::errors::simulation_error(format!(
            "internal error: a snapshot array is not {n} x {d}: {e}"
        ))
    })?;
    Ok(PyArray2::from_owned_array(py, a))
}

/// Angular velocities as NumPy: (n,) for disks, (n, 3) for spheres.
pub fn spins<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    n: usize,
    d: usize,
) -> PyResult<Bound<'py, PyAny>> {
    if d == 2 {
        Ok(PyArray1::from_vec(py, values).into_any())
    } else {
        Ok(matrix(py, values, n, 3)?.into_any())
    }
}

/// The arrays of a snapshot: time, positions, velocities and, from a rough run, angular
/// velocities.
pub struct SnapshotArrays {
    /// The snapshot's time.
    pub time: f64,
    /// Positions, row-major `(n, d)`.
    pub positions: Vec<f64>,
    /// Velocities, row-major `(n, d)`.
    pub velocities: Vec<f64>,
    /// Angular velocities of a rough run's snapshot.
    pub angular_velocities: Option<Vec<f64>>,
}

/// The arrays of a snapshot given as a path, a `granular.Snapshot` or a dict, checked
/// against the scenario's grains and dimension.
pub fn snapshot_arrays(
    py: Python<'_>,
    snapshot: &Bound<'_, PyAny>,
    scenario: &granular::Scenario,
) -> PyResult<SnapshotArrays> {
    if scenario.kind() == granular::scenario::EngineKind::Intruder {
        return Err(crate::errors::state_error(
            granular::grain_state::StateError::NoGrains { engine: "intruder" },
        ));
    }
    let n: usize = scenario.species().iter().map(|s| s.count).sum();
    let d = scenario.dimension;
    let path: Option<PathBuf> = if snapshot.is_instance_of::<pyo3::types::PyDict>() {
        None
    } else {
        snapshot.extract().ok()
    };
    if let Some(path) = path {
        let s = py
            .detach(|| granular::run::read_snapshot(&path))
            .map_err(|e| {
                pyo3::exceptions::PyOSError::new_err(format!("{}: {e}", path.display()))
            })?;
        if s.radii.len() != n || s.dimension != d {
            return Err(value_error(format!(
                "{}: the snapshot holds {} grains in {} dimensions; the scenario has {n} in {d}",
                path.display(),
                s.radii.len(),
                s.dimension
            )));
        }
        return Ok(SnapshotArrays {
            time: s.time,
            positions: s.positions,
            velocities: s.velocities,
            angular_velocities: (!s.angular_velocities.is_empty()).then_some(s.angular_velocities),
        });
    }
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        if let Ok(dict) = snapshot.cast::<pyo3::types::PyDict>() {
            dict.get_item(key)?
                .ok_or_else(|| value_error(format!("the snapshot dict has no `{key}`")))
        } else {
            snapshot.getattr(key).map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "snapshot must be the path of a snapshot .npz, a granular.Snapshot (granular.load_run(...).snapshot(k)) or the dict of Simulation.snapshot(); it has no `{key}`"
                ))
            })
        }
    };
    let time: f64 = get("time")?.extract()?;
    let positions = grain_array(py, "positions", &get("positions")?, n, d)?;
    let velocities = grain_array(py, "velocities", &get("velocities")?, n, d)?;
    // Angular velocities where the snapshot has them (a rough run's): a dict's key or a
    // `granular.Snapshot`'s attribute, absent or None otherwise.
    let spins = match snapshot.cast::<pyo3::types::PyDict>() {
        Ok(dict) => dict.get_item("angular_velocities")?,
        Err(_) => snapshot.getattr("angular_velocities").ok(),
    };
    let angular_velocities = match spins.filter(|w| !w.is_none()) {
        Some(w) => Some(spin_array(py, &w, n, d)?),
        None => None,
    };
    Ok(SnapshotArrays {
        time,
        positions,
        velocities,
        angular_velocities,
    })
}
