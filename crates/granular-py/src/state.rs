//! Positions or velocities of every grain in input order, without building a whole
//! snapshot: the library's `Simulation::positions_into` / `velocities_into`, writing
//! straight into a NumPy array's own buffer.

use granular::Simulation;
use numpy::{PyArray2, PyArrayMethods};
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
