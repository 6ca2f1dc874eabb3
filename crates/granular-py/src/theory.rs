//! The library's exact theory on NumPy arrays. Each function here takes flat float64 arrays
//! of one length (the Python layer, `granular.theory`, broadcasts and reshapes) and applies
//! the library's scalar formula element by element; no formula is written here.

use crate::errors::value_error;
use granular::intruder::{BathDistribution, Gaussian, PowerLaw};
use granular::theory::relaxation::{SonineRelaxation, SonineState};
use granular::theory::rough::{Approximation, RoughGas, RoughState};
use granular::theory::{equilibrium as eq, haff};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

type Out<'py> = PyResult<Bound<'py, PyArray1<f64>>>;
/// Two arrays of one length (a temperature and an `a2` series).
type Pair<'py> = PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)>;

/// `f` applied element by element to `K` arrays of one length.
fn map<'py, const K: usize>(
    py: Python<'py>,
    arrays: [PyReadonlyArray1<'py, f64>; K],
    f: impl Fn([f64; K]) -> f64,
) -> Out<'py> {
    let slices: Vec<&[f64]> = arrays
        .iter()
        .map(|a| a.as_slice())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            value_error("the arrays must be contiguous (granular.theory makes them so)")
        })?;
    let n = slices.first().map_or(0, |s| s.len());
    if slices.iter().any(|s| s.len() != n) {
        return Err(value_error(
            "the arrays must have one length (granular.theory broadcasts them)",
        ));
    }
    let out: Vec<f64> = (0..n)
        .map(|i| f(std::array::from_fn(|k| slices[k][i])))
        .collect();
    Ok(PyArray1::from_vec(py, out))
}

fn dimension_2_or_3(dimension: usize) -> PyResult<()> {
    if dimension == 2 || dimension == 3 {
        Ok(())
    } else {
        Err(value_error(format!(
            "dimension is {dimension}; use 2 (disks) or 3 (spheres)"
        )))
    }
}

type A<'py> = PyReadonlyArray1<'py, f64>;

#[pyfunction]
fn speed_density<'py>(
    py: Python<'py>,
    dimension: usize,
    v: A<'py>,
    m: A<'py>,
    t: A<'py>,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [v, m, t], |[v, m, t]| {
        eq::speed_density(dimension, v, m, t)
    })
}

#[pyfunction]
fn speed_cdf<'py>(py: Python<'py>, dimension: usize, v: A<'py>, m: A<'py>, t: A<'py>) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [v, m, t], |[v, m, t]| eq::speed_cdf(dimension, v, m, t))
}

#[pyfunction]
fn mean_speed<'py>(py: Python<'py>, dimension: usize, m: A<'py>, t: A<'py>) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [m, t], |[m, t]| eq::mean_speed(dimension, m, t))
}

#[pyfunction]
fn compressibility<'py>(py: Python<'py>, dimension: usize, eta: A<'py>) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [eta], |[e]| eq::compressibility(dimension, e))
}

#[pyfunction]
fn collision_frequency_from_pressure<'py>(
    py: Python<'py>,
    dimension: usize,
    z: A<'py>,
    diameter: A<'py>,
    m: A<'py>,
    t: A<'py>,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [z, diameter, m, t], |[z, d, m, t]| {
        eq::collision_frequency_from_pressure(dimension, z, d, m, t)
    })
}

#[pyfunction]
fn contact_value<'py>(py: Python<'py>, dimension: usize, phi: A<'py>) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [phi], |[p]| haff::contact_value(dimension, p))
}

#[pyfunction]
fn packing_fraction<'py>(py: Python<'py>, dimension: usize, n: A<'py>, r: A<'py>) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [n, r], |[n, r]| haff::packing_fraction(dimension, n, r))
}

#[pyfunction]
fn mean_free_path<'py>(
    py: Python<'py>,
    dimension: usize,
    n: A<'py>,
    r: A<'py>,
    chi: A<'py>,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [n, r, chi], |[n, r, c]| {
        haff::mean_free_path(dimension, n, r, c)
    })
}

#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn collision_frequency<'py>(
    py: Python<'py>,
    dimension: usize,
    n: A<'py>,
    r: A<'py>,
    t: A<'py>,
    m: A<'py>,
    chi: A<'py>,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [n, r, t, m, chi], |[n, r, t, m, c]| {
        haff::collision_frequency(dimension, n, r, t, m, c)
    })
}

#[pyfunction]
fn sonine_a2<'py>(py: Python<'py>, dimension: usize, e: A<'py>) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [e], |[e]| haff::sonine_a2(dimension, e))
}

#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn cooling_rate<'py>(
    py: Python<'py>,
    dimension: usize,
    n: A<'py>,
    r: A<'py>,
    t: A<'py>,
    m: A<'py>,
    e: A<'py>,
    chi: A<'py>,
    sonine: bool,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [n, r, t, m, e, chi], |[n, r, t, m, e, c]| {
        haff::cooling_rate(dimension, n, r, t, m, e, c, sonine)
    })
}

#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn haff_time<'py>(
    py: Python<'py>,
    dimension: usize,
    n: A<'py>,
    r: A<'py>,
    t: A<'py>,
    m: A<'py>,
    e: A<'py>,
    chi: A<'py>,
    sonine: bool,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    map(py, [n, r, t, m, e, chi], |[n, r, t, m, e, c]| {
        haff::haff_time(dimension, n, r, t, m, e, c, sonine)
    })
}

#[pyfunction]
fn haff_energy<'py>(py: Python<'py>, k0: A<'py>, t: A<'py>, t0: A<'py>) -> Out<'py> {
    map(py, [k0, t, t0], |[k, t, t0]| haff::haff_energy(k, t, t0))
}

#[pyfunction]
fn martin_piasecki_ratio<'py>(py: Python<'py>, e: A<'py>, m: A<'py>, mb: A<'py>) -> Out<'py> {
    map(py, [e, m, mb], |[e, m, mb]| {
        granular::intruder::theory::martin_piasecki_ratio(e, m, mb)
    })
}

fn dimension_1_to_3(dimension: usize) -> PyResult<()> {
    if (1..=3).contains(&dimension) {
        Ok(())
    } else {
        Err(value_error(format!(
            "dimension is {dimension}; use 1 (a point intruder on a line), 2 (a disk) or 3 (a sphere)"
        )))
    }
}

/// Collision rate of a disk or sphere (or a 1D intruder) at speed `v` in a Gaussian bath,
/// G-32 with G-33.
#[pyfunction]
fn intruder_collision_rate<'py>(
    py: Python<'py>,
    dimension: usize,
    v: A<'py>,
    r: A<'py>,
    rho: A<'py>,
    t_b: A<'py>,
    mb: A<'py>,
) -> Out<'py> {
    dimension_1_to_3(dimension)?;
    map(py, [v, r, rho, t_b, mb], |[v, r, rho, t_b, mb]| {
        granular::theory::intruder::gaussian_collision_rate(dimension, v, r, rho, t_b, mb)
    })
}

/// Mean collision rate of a Maxwellian intruder in a Gaussian bath, G-42.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn intruder_mean_collision_rate<'py>(
    py: Python<'py>,
    dimension: usize,
    r: A<'py>,
    rho: A<'py>,
    t_b: A<'py>,
    mb: A<'py>,
    t: A<'py>,
    m: A<'py>,
) -> Out<'py> {
    dimension_1_to_3(dimension)?;
    map(py, [r, rho, t_b, mb, t, m], |[r, rho, t_b, mb, t, m]| {
        granular::theory::intruder::maxwellian_mean_collision_rate(dimension, r, rho, t_b, mb, t, m)
    })
}

/// Kurtosis of a `d`-dimensional Maxwellian, G-41.
#[pyfunction]
fn maxwellian_kurtosis(dimension: usize) -> PyResult<f64> {
    dimension_1_to_3(dimension)?;
    Ok(granular::theory::intruder::maxwellian_kurtosis(dimension))
}

/// Which quantity of a bath distribution.
fn bath_quantity(dist: &dyn BathDistribution, what: &str, v: f64) -> f64 {
    match what {
        "density" => dist.density(v),
        "cdf" => dist.cdf(v),
        "plus" => dist.flux_plus(v),
        "minus" => dist.flux_minus(v),
        _ => dist.flux(v),
    }
}

/// Density, cdf or side fluxes (per unit bath density) of a Gaussian (Eq. 14) or power-law
/// (Eq. 19) bath of temperature `t_b` and particle mass `m`.
#[pyfunction]
fn bath<'py>(py: Python<'py>, kind: &str, what: &str, v: A<'py>, t_b: f64, m: f64) -> Out<'py> {
    let dist: Box<dyn BathDistribution> = match kind {
        "gaussian" => Box::new(Gaussian::with_temperature(t_b, m).map_err(value_error_of)?),
        "power_law" => Box::new(PowerLaw::with_temperature(t_b, m).map_err(value_error_of)?),
        other => {
            return Err(value_error(format!(
                "bath is {other:?}; use \"gaussian\" or \"power_law\""
            )));
        }
    };
    if !matches!(what, "density" | "cdf" | "plus" | "minus" | "both") {
        return Err(value_error(format!(
            "side is {what:?}; use \"both\", \"plus\" or \"minus\""
        )));
    }
    map(py, [v], |[v]| bath_quantity(dist.as_ref(), what, v))
}

fn value_error_of(e: impl std::fmt::Display) -> PyErr {
    value_error(e.to_string())
}

/// The needle's total collision rate, Eq. 21-22.
#[pyfunction]
fn needle_flux<'py>(
    py: Python<'py>,
    rho: A<'py>,
    a: A<'py>,
    length: A<'py>,
    vn: A<'py>,
    omega: A<'py>,
) -> Out<'py> {
    map(py, [rho, a, length, vn, omega], |[r, a, l, v, w]| {
        granular::intruder::needle::total_flux(r, a, l, v, w)
    })
}

/// The rough gas of the four parameters, checked: α in [0, 1], β in [-1, 1], κ in its
/// range (`None` for any value out of range: the result is NaN, as for a NaN input).
fn rough_gas(dimension: usize, alpha: f64, beta: f64, kappa: f64) -> Option<RoughGas> {
    let ok = (0.0..=1.0).contains(&alpha)
        && (-1.0..=1.0).contains(&beta)
        && kappa > 0.0
        && kappa <= granular::collision_law::rough::max_inertia(dimension);
    ok.then_some(RoughGas {
        dimension,
        normal_restitution: alpha,
        tangential_restitution: beta,
        inertia: kappa,
    })
}

/// Which state and approximation of the rough-gas theory, from the Python names.
fn rough_choice(state: &str, approximation: &str) -> PyResult<(RoughState, Approximation)> {
    let state = match state {
        "cooling" => RoughState::Cooling,
        "white_noise" => RoughState::WhiteNoise,
        other => {
            return Err(value_error(format!(
                "state is {other:?}; use \"cooling\" (the homogeneous cooling state) or \"white_noise\""
            )));
        }
    };
    let approximation = match approximation {
        "maxwell" => Approximation::Maxwell,
        "sonine" => Approximation::Sonine,
        other => {
            return Err(value_error(format!(
                "approximation is {other:?}; use \"maxwell\" (RS-4 to RS-6) or \"sonine\" (RS-8, RS-9)"
            )));
        }
    };
    Ok((state, approximation))
}

/// `RoughGas::temperature_ratio` (RS-4, RS-6, RS-8, RS-9) element by element; NaN where the
/// parameters are out of range or there is no solution.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn rough_temperature_ratio<'py>(
    py: Python<'py>,
    dimension: usize,
    state: &str,
    approximation: &str,
    alpha: A<'py>,
    beta: A<'py>,
    kappa: A<'py>,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    let (state, approximation) = rough_choice(state, approximation)?;
    map(py, [alpha, beta, kappa], |[a, b, k]| {
        rough_gas(dimension, a, b, k)
            .and_then(|g| g.temperature_ratio(state, approximation))
            .unwrap_or(f64::NAN)
    })
}

/// `RoughGas::reduced_cooling_rate` (ζ/ν of the total energy; RS-5 and its Sonine value)
/// element by element; NaN where the parameters are out of range or there is no solution.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn rough_cooling_rate<'py>(
    py: Python<'py>,
    dimension: usize,
    state: &str,
    approximation: &str,
    alpha: A<'py>,
    beta: A<'py>,
    kappa: A<'py>,
) -> Out<'py> {
    dimension_2_or_3(dimension)?;
    let (state, approximation) = rough_choice(state, approximation)?;
    map(py, [alpha, beta, kappa], |[a, b, k]| {
        rough_gas(dimension, a, b, k)
            .and_then(|g| g.reduced_cooling_rate(state, approximation))
            .unwrap_or(f64::NAN)
    })
}

/// The gas of [`SonineRelaxation`] as `granular.theory` passes it: `(dimension,
/// restitution, mass, number_density, radius, chi, particles)`.
#[derive(FromPyObject)]
struct GasArgs(usize, f64, f64, f64, f64, f64, Option<usize>);

/// The gas of [`SonineRelaxation`] from the Python arguments, checked.
fn relaxing_gas(args: GasArgs) -> PyResult<SonineRelaxation> {
    let GasArgs(dimension, restitution, mass, number_density, radius, chi, particles) = args;
    dimension_2_or_3(dimension)?;
    if !(0.0..=1.0).contains(&restitution) {
        return Err(value_error(format!(
            "restitution is {restitution}; give a normal restitution from 0 to 1"
        )));
    }
    for (name, v) in [
        ("mass", mass),
        ("number_density", number_density),
        ("radius", radius),
        ("chi", chi),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(value_error(format!(
                "{name} is {v}; give a positive number"
            )));
        }
    }
    if particles == Some(0) {
        return Err(value_error(
            "particles is 0; give the number of grains (or None for infinitely many)",
        ));
    }
    Ok(SonineRelaxation::new(
        dimension,
        restitution,
        mass,
        number_density,
        radius,
        chi,
        particles,
    ))
}

fn increasing(name: &str, x: &[f64]) -> PyResult<()> {
    if x.iter().any(|t| !(t.is_finite() && *t >= 0.0)) || x.windows(2).any(|w| w[1] < w[0]) {
        return Err(value_error(format!(
            "{name} must be finite times from 0 on, in increasing order"
        )));
    }
    Ok(())
}

/// `SonineRelaxation::trajectory` (KT-14, KT-15): the temperature and `a2` at `times` of a
/// gas starting from (`temperature`, `a2`) at time 0 under white noise of strength
/// `strengths[k]` from `change_times[k]` on.
#[pyfunction]
fn sonine_relaxation<'py>(
    py: Python<'py>,
    gas: GasArgs,
    temperature: f64,
    a2: f64,
    change_times: A<'py>,
    strengths: A<'py>,
    times: A<'py>,
) -> Pair<'py> {
    let gas = relaxing_gas(gas)?;
    if !(temperature.is_finite() && temperature > 0.0 && a2.is_finite()) {
        return Err(value_error(format!(
            "temperature is {temperature} and a2 is {a2}; give a positive temperature and a finite a2"
        )));
    }
    let contiguous = |a: &A<'py>| {
        a.as_slice()
            .map(|s| s.to_vec())
            .map_err(|_| value_error("the arrays must be contiguous"))
    };
    let (changes, strengths, times) = (
        contiguous(&change_times)?,
        contiguous(&strengths)?,
        contiguous(&times)?,
    );
    increasing("times", &times)?;
    increasing("the strength's change times", &changes)?;
    if changes.len() != strengths.len() || changes.first() != Some(&0.0) {
        return Err(value_error(
            "give the strength as a number or as (time, strength) pairs, the first at time 0",
        ));
    }
    if strengths.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
        return Err(value_error(
            "a strength is negative or not finite; give xi0^2 >= 0 (0: free cooling)",
        ));
    }
    let protocol: Vec<(f64, f64)> = changes.into_iter().zip(strengths).collect();
    let states = gas.trajectory(SonineState { temperature, a2 }, &protocol, &times);
    let t: Vec<f64> = states.iter().map(|s| s.temperature).collect();
    let a: Vec<f64> = states.iter().map(|s| s.a2).collect();
    Ok((PyArray1::from_vec(py, t), PyArray1::from_vec(py, a)))
}

/// `SonineRelaxation::strength_for_temperature` (KT-13 solved for `ξ0²`) element by
/// element.
#[pyfunction]
fn white_noise_strength<'py>(py: Python<'py>, gas: GasArgs, temperature: A<'py>) -> Out<'py> {
    let gas = relaxing_gas(gas)?;
    map(py, [temperature], |[t]| {
        if t > 0.0 {
            gas.strength_for_temperature(t)
        } else {
            f64::NAN
        }
    })
}

/// Adds the `theory` submodule.
pub fn register(parent: &Bound<'_, PyModule>) -> PyResult<()> {
    let m = PyModule::new(parent.py(), "theory")?;
    m.add_function(wrap_pyfunction!(speed_density, &m)?)?;
    m.add_function(wrap_pyfunction!(intruder_collision_rate, &m)?)?;
    m.add_function(wrap_pyfunction!(intruder_mean_collision_rate, &m)?)?;
    m.add_function(wrap_pyfunction!(maxwellian_kurtosis, &m)?)?;
    m.add_function(wrap_pyfunction!(speed_cdf, &m)?)?;
    m.add_function(wrap_pyfunction!(mean_speed, &m)?)?;
    m.add_function(wrap_pyfunction!(compressibility, &m)?)?;
    m.add_function(wrap_pyfunction!(collision_frequency_from_pressure, &m)?)?;
    m.add_function(wrap_pyfunction!(contact_value, &m)?)?;
    m.add_function(wrap_pyfunction!(packing_fraction, &m)?)?;
    m.add_function(wrap_pyfunction!(mean_free_path, &m)?)?;
    m.add_function(wrap_pyfunction!(collision_frequency, &m)?)?;
    m.add_function(wrap_pyfunction!(sonine_a2, &m)?)?;
    m.add_function(wrap_pyfunction!(cooling_rate, &m)?)?;
    m.add_function(wrap_pyfunction!(haff_time, &m)?)?;
    m.add_function(wrap_pyfunction!(haff_energy, &m)?)?;
    m.add_function(wrap_pyfunction!(martin_piasecki_ratio, &m)?)?;
    m.add_function(wrap_pyfunction!(bath, &m)?)?;
    m.add_function(wrap_pyfunction!(needle_flux, &m)?)?;
    m.add_function(wrap_pyfunction!(rough_temperature_ratio, &m)?)?;
    m.add_function(wrap_pyfunction!(rough_cooling_rate, &m)?)?;
    m.add_function(wrap_pyfunction!(sonine_relaxation, &m)?)?;
    m.add_function(wrap_pyfunction!(white_noise_strength, &m)?)?;
    parent.add_submodule(&m)?;
    Ok(())
}
