//! Positions or velocities of every grain in input order, without building a whole
//! snapshot: the library's `Simulation::positions_into` / `velocities_into`, writing
//! straight into a NumPy array's own buffer.

use granular::Simulation;
use numpy::{PyArray2, PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;

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
        return Err(crate::errors::value_error(format!(
            "`{name}` has shape {}; give shape {}: {what}",
            shape_text(&given),
            shape_text(shape)
        )));
    }
    let typed = array.cast::<PyArrayDyn<f64>>()?;
    let view = typed.try_readonly()?;
    Ok(match view.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => view.as_array().iter().copied().collect(),
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
