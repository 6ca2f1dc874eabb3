"""Exact theory on NumPy arrays: every function is the library's formula (crates/granular/src/theory
and src/intruder), applied element by element with NumPy broadcasting.

Array arguments may be Python numbers, lists or NumPy arrays of any shape; they are broadcast
together and the result has the broadcast shape (a 0-d input gives a Python float). Units:
``k_B = 1`` (a temperature is an energy), lengths and masses in the scenario's units.
Equation labels: HD-n (the hard-disk assignment), DSMC-n (Müller & Herrmann's DSMC paper), G-n (the Gillespie
intruder paper), RS-n (rough grains, docs/rough.md), KT-n (kinetic theory from the literature,
docs/equations.md).
"""

from __future__ import annotations

from typing import Any, Callable, Literal, Union

import numpy as np
import numpy.typing as npt

from . import _core

__all__ = [
    "speed_density",
    "speed_cdf",
    "mean_speed",
    "compressibility",
    "hard_disk_compressibility",
    "hard_sphere_compressibility",
    "collision_frequency_from_pressure",
    "contact_value",
    "packing_fraction",
    "mean_free_path",
    "collision_frequency",
    "sonine_a2",
    "cooling_rate",
    "haff_time",
    "haff_energy",
    "haff_temperature",
    "martin_piasecki_ratio",
    "intruder_collision_rate",
    "intruder_mean_collision_rate",
    "maxwellian_kurtosis",
    "bath_density",
    "bath_flux",
    "needle_flux",
    "rough_temperature_ratio",
    "rough_cooling_rate",
    "sonine_relaxation",
    "white_noise_strength",
]

ArrayLike = npt.ArrayLike
#: A float for 0-d inputs, otherwise a float64 array of the broadcast shape.
Result = Union[float, npt.NDArray[np.float64]]

_T = _core.theory


def _apply(func: Callable[..., Any], lead: tuple[Any, ...], *arrays: ArrayLike, **kw: Any) -> Result:
    """Broadcasts ``arrays``, calls the compiled ``func(*lead, *flat_arrays, **kw)`` and reshapes."""
    parts = np.broadcast_arrays(*[np.asarray(a, dtype=np.float64) for a in arrays])
    shape = parts[0].shape
    flat = [np.ascontiguousarray(p).reshape(-1) for p in parts]
    out = np.asarray(func(*lead, *flat, **kw)).reshape(shape)
    if out.ndim == 0:
        return float(out)
    return out


def speed_density(v: ArrayLike, mass: ArrayLike = 1.0, temperature: ArrayLike = 1.0, dimension: int = 2) -> Result:
    """Maxwell-Boltzmann probability density of the speed ``v`` in ``dimension`` (2 or 3) dimensions.

    ``p(v) = 2 (m/2T)^{D/2} / Gamma(D/2) v^{D-1} exp(-m v^2 / 2T)``; in 2D ``(m v / T) exp(-m v^2/2T)``,
    HD-12. Units: inverse speed.
    """
    return _apply(_T.speed_density, (dimension,), v, mass, temperature)


def speed_cdf(v: ArrayLike, mass: ArrayLike = 1.0, temperature: ArrayLike = 1.0, dimension: int = 2) -> Result:
    """Cumulative Maxwell-Boltzmann speed distribution ``P(D/2, m v^2 / 2T)`` (regularised incomplete gamma)."""
    return _apply(_T.speed_cdf, (dimension,), v, mass, temperature)


def mean_speed(mass: ArrayLike = 1.0, temperature: ArrayLike = 1.0, dimension: int = 2) -> Result:
    """Mean Maxwell-Boltzmann speed ``sqrt(2T/m) Gamma((D+1)/2) / Gamma(D/2)`` (``sqrt(pi T / 2m)`` in 2D)."""
    return _apply(_T.mean_speed, (dimension,), mass, temperature)


def compressibility(packing_fraction: ArrayLike, dimension: int = 2) -> Result:
    """Compressibility factor ``Z = P / (n T)`` of the hard-disk (Liu 2020) or hard-sphere (Carnahan-Starling) fluid."""
    return _apply(_T.compressibility, (dimension,), packing_fraction)


def hard_disk_compressibility(packing_fraction: ArrayLike) -> Result:
    """Hard-disk ``Z(eta) = (1 + eta^2/8 + eta^3/18 - 4 eta^4/21) / (1 - eta)^2`` (Liu 2020, Eq. 1)."""
    return compressibility(packing_fraction, dimension=2)


def hard_sphere_compressibility(packing_fraction: ArrayLike) -> Result:
    """Hard-sphere Carnahan-Starling ``Z(eta) = (1 + eta + eta^2 - eta^3) / (1 - eta)^3``."""
    return compressibility(packing_fraction, dimension=3)


def collision_frequency_from_pressure(
    z: ArrayLike, diameter: ArrayLike, mass: ArrayLike = 1.0, temperature: ArrayLike = 1.0, dimension: int = 2
) -> Result:
    """Collision frequency per grain implied by a compressibility factor: ``2D (Z - 1) sqrt(T/(pi m)) / sigma``."""
    return _apply(_T.collision_frequency_from_pressure, (dimension,), z, diameter, mass, temperature)


def contact_value(packing_fraction: ArrayLike, dimension: int = 2) -> Result:
    """Enskog pair correlation at contact ``chi(phi)``: Henderson ``(1 - 7phi/16)/(1 - phi)^2`` for disks,
    Carnahan-Starling ``(1 - phi/2)/(1 - phi)^3`` for spheres."""
    return _apply(_T.contact_value, (dimension,), packing_fraction)


def packing_fraction(number_density: ArrayLike, radius: ArrayLike, dimension: int = 2) -> Result:
    """Packing (area or volume) fraction ``phi = n v_p`` of grains of radius ``radius`` at number density ``n``."""
    return _apply(_T.packing_fraction, (dimension,), number_density, radius)


def mean_free_path(number_density: ArrayLike, radius: ArrayLike, chi: ArrayLike = 1.0, dimension: int = 2) -> Result:
    """Mean free path ``1 / (sqrt(2) chi n sigma)`` of a Maxwellian gas (``sigma`` the cross-section, 4R in 2D)."""
    return _apply(_T.mean_free_path, (dimension,), number_density, radius, chi)


def collision_frequency(
    number_density: ArrayLike,
    radius: ArrayLike,
    temperature: ArrayLike = 1.0,
    mass: ArrayLike = 1.0,
    chi: ArrayLike = 1.0,
    dimension: int = 2,
) -> Result:
    """Collisions per grain per unit time ``chi n sigma <|v_12|>`` of a Maxwellian gas (chi = 1: Boltzmann)."""
    return _apply(_T.collision_frequency, (dimension,), number_density, radius, temperature, mass, chi)


def sonine_a2(restitution: ArrayLike, dimension: int = 2) -> Result:
    """First Sonine coefficient of the homogeneous cooling state (van Noije & Ernst 1998, Eq. 36)."""
    return _apply(_T.sonine_a2, (dimension,), restitution)


def cooling_rate(
    number_density: ArrayLike,
    radius: ArrayLike,
    temperature: ArrayLike,
    restitution: ArrayLike,
    mass: ArrayLike = 1.0,
    chi: ArrayLike = 1.0,
    sonine: bool = True,
    dimension: int = 2,
) -> Result:
    """Cooling rate ``zeta`` of ``dT/dt = -zeta T``: ``(1 - e^2)/D * omega * (1 + 3 a2/16)`` (DSMC-3's rate)."""
    return _apply(
        _T.cooling_rate, (dimension,), number_density, radius, temperature, mass, restitution, chi, sonine=sonine
    )


def haff_time(
    number_density: ArrayLike,
    radius: ArrayLike,
    temperature: ArrayLike,
    restitution: ArrayLike,
    mass: ArrayLike = 1.0,
    chi: ArrayLike = 1.0,
    sonine: bool = True,
    dimension: int = 2,
) -> Result:
    """Haff's time ``t0 = 2 / zeta(T(0))`` (time units), with the Sonine correction unless ``sonine=False``."""
    return _apply(
        _T.haff_time, (dimension,), number_density, radius, temperature, mass, restitution, chi, sonine=sonine
    )


def haff_energy(t: ArrayLike, initial_energy: ArrayLike, t0: ArrayLike) -> Result:
    """Haff's law, DSMC-3: ``K(t) = K(0) / (1 + t/t0)^2``."""
    return _apply(_T.haff_energy, (), initial_energy, t, t0)


def haff_temperature(t: ArrayLike, initial_temperature: ArrayLike, t0: ArrayLike) -> Result:
    """Haff's law for the temperature, ``T(t) = T(0) / (1 + t/t0)^2`` (DSMC-3; ``T`` is proportional to ``K``)."""
    return haff_energy(t, initial_temperature, t0)


def martin_piasecki_ratio(restitution: ArrayLike, mass: ArrayLike = 1.0, bath_mass: ArrayLike = 1.0) -> Result:
    """Stationary ``T/T_B`` of an intruder of mass ``M = mass`` in a Gaussian bath of particles of mass
    ``m = bath_mass``, in any dimension (G-18 in 1D, G-40 for a disk or sphere; Martin and Piasecki 1999):
    ``(1 + alpha) M / (2M + (1 - alpha) m)``."""
    return _apply(_T.martin_piasecki_ratio, (), restitution, mass, bath_mass)


def intruder_collision_rate(
    speed: ArrayLike,
    radius: ArrayLike = 0.5,
    bath_density: ArrayLike = 1.0,
    temperature: ArrayLike = 0.5,
    bath_mass: ArrayLike = 1.0,
    dimension: int = 2,
) -> Result:
    """Collision rate (collisions per unit time) of a disk (``dimension=2``) or sphere (``dimension=3``) of
    radius ``R`` moving at ``speed = |V|`` through a Gaussian bath of number density ``rho``, temperature
    ``T_B`` and particle mass ``m``: ``rho sigma_d <|u - V|>`` (G-32 with the closed forms G-33;
    ``sigma_d = 2R``, ``pi R^2``). ``dimension=1`` is the 1D intruder's G-7 (``radius`` unused)."""
    return _apply(
        _T.intruder_collision_rate, (int(dimension),), speed, radius, bath_density, temperature, bath_mass
    )


def intruder_mean_collision_rate(
    temperature: ArrayLike,
    radius: ArrayLike = 0.5,
    bath_density: ArrayLike = 1.0,
    bath_temperature: ArrayLike = 0.5,
    bath_mass: ArrayLike = 1.0,
    mass: ArrayLike = 1.0,
    dimension: int = 2,
) -> Result:
    """Mean collision rate of a Maxwellian intruder (mass ``M``, temperature ``T``) in a Gaussian bath (G-42):
    ``rho sigma_d sqrt(2 (T_B/m + T/M)) Gamma((d+1)/2) / Gamma(d/2)``; the stationary rate with ``T`` from
    :func:`martin_piasecki_ratio`."""
    return _apply(
        _T.intruder_mean_collision_rate,
        (int(dimension),),
        radius,
        bath_density,
        bath_temperature,
        bath_mass,
        temperature,
        mass,
    )


def maxwellian_kurtosis(dimension: int = 2) -> float:
    """Kurtosis ``<|V|^4> / <|V|^2>^2 = (d + 2)/d`` of a ``d``-dimensional Maxwellian (G-41): 3, 2, 5/3."""
    return float(_T.maxwellian_kurtosis(int(dimension)))


Bath = Literal["gaussian", "power_law"]


def bath_density(v: ArrayLike, bath: Bath = "gaussian", temperature: float = 1.0, bath_mass: float = 1.0) -> Result:
    """Velocity density ``f(v)`` of one bath velocity component: Gaussian (G-14) or power law (G-19), at
    bath temperature ``T_B = m <v^2>``."""
    return _apply(_T.bath, (bath, "density"), v, t_b=temperature, m=bath_mass)


def bath_flux(
    v1: ArrayLike,
    bath: Bath = "gaussian",
    temperature: float = 1.0,
    bath_mass: float = 1.0,
    density: float = 1.0,
    side: Literal["both", "plus", "minus"] = "both",
) -> Result:
    """Collision rate of an intruder moving at ``v1`` with the bath: ``rho phi_+(v1)`` (G-5), ``rho phi_-(v1)``
    (G-6) or their sum (G-7), per unit time, for bath density ``rho = density``."""
    rate = _apply(_T.bath, (bath, side), v1, t_b=temperature, m=bath_mass)
    return density * rate


def needle_flux(
    normal_velocity: ArrayLike,
    angular_velocity: ArrayLike,
    length: ArrayLike = 1.0,
    density: ArrayLike = 1.0,
    temperature: ArrayLike = 1.0,
    bath_mass: ArrayLike = 1.0,
) -> Result:
    """Total collision rate ``Phi`` of a needle (G-21, closed form; G-22 is ``a = L = 1``) with normal velocity
    ``v_n`` and angular velocity ``omega`` in a Gaussian bath of density ``rho`` and ``a = m / (2 T_B)``."""
    a = np.asarray(bath_mass, dtype=np.float64) / (2.0 * np.asarray(temperature, dtype=np.float64))
    return _apply(_T.needle_flux, (), density, a, length, normal_velocity, angular_velocity)


RoughState = Literal["cooling", "white_noise"]
Approximation = Literal["maxwell", "sonine"]


def rough_temperature_ratio(
    normal_restitution: ArrayLike,
    tangential_restitution: ArrayLike,
    inertia: ArrayLike | None = None,
    dimension: int = 2,
    state: RoughState = "cooling",
    approximation: Approximation = "maxwell",
) -> Result:
    """Temperature ratio ``T_rot / T_tr`` of a homogeneous gas of rough disks or spheres.

    ``state``: ``"cooling"`` (the homogeneous cooling state, RS-4 Maxwellian / RS-8 Sonine) or
    ``"white_noise"`` (heated on the translational velocities, RS-6 ``kappa (1+beta)/(1+2 kappa-beta)``
    / RS-9). ``inertia`` is kappa = 4I/(m sigma^2), default 1/2 (disks) or 2/5 (spheres). NaN where
    alpha is outside [0, 1], beta outside [-1, 1], kappa outside (0, 1] (disks) or (0, 2/3] (spheres),
    for smooth grains (beta = -1) in the cooling state, or where the Sonine equations have no solution.
    """
    if inertia is None:
        inertia = 0.5 if dimension == 2 else 0.4
    return _apply(
        _T.rough_temperature_ratio,
        (dimension, state, approximation),
        normal_restitution,
        tangential_restitution,
        inertia,
    )


def rough_cooling_rate(
    normal_restitution: ArrayLike,
    tangential_restitution: ArrayLike,
    inertia: ArrayLike | None = None,
    dimension: int = 2,
    state: RoughState = "cooling",
    approximation: Approximation = "maxwell",
) -> Result:
    """Cooling rate of the total (translational plus rotational) energy per collision of a grain,
    ``zeta / nu``, of a homogeneous gas of rough grains (RS-5; its Sonine value over the Sonine
    collision frequency). Arguments and NaN cases as :func:`rough_temperature_ratio`; multiply by the
    collision frequency (:func:`collision_frequency`) for a rate per unit time.
    """
    if inertia is None:
        inertia = 0.5 if dimension == 2 else 0.4
    return _apply(
        _T.rough_cooling_rate,
        (dimension, state, approximation),
        normal_restitution,
        tangential_restitution,
        inertia,
    )


Strength = Union[float, "list[tuple[float, float]]", npt.ArrayLike]


def _gas(
    dimension: int, restitution: float, mass: float, number_density: float, radius: float, chi: float,
    particles: int | None,
) -> tuple[int, float, float, float, float, float, int | None]:
    """The gas of KT-14/KT-15 as the compiled functions take it."""
    return (
        dimension, float(restitution), float(mass), float(number_density), float(radius), float(chi), particles
    )


def sonine_relaxation(
    times: ArrayLike,
    temperature: float,
    a2: float,
    strength: Strength,
    restitution: float,
    number_density: float,
    radius: float,
    mass: float = 1.0,
    chi: float = 1.0,
    particles: int | None = None,
    dimension: int = 2,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Temperature and ``a2`` at ``times`` of a homogeneous gas heated by white noise, relaxing
    from ``(temperature, a2)`` at time 0 in the first Sonine approximation (KT-14, KT-15:
    ``dT/dt = m xi0^2 - zeta T``, ``da2/dt = -(2 m xi0^2/T) a2 + (2 omega/(D(D+2)))[...]``;
    docs/equations.md). The theory of the Kovacs (Prados & Trizac 2014) and Mpemba (Lasanta et
    al. 2017) effects of driven granular gases.

    ``strength`` is ``xi0^2`` (length^2/time^3; 0 for free cooling), a number or a list of
    ``(time, strength)`` pairs, the first at time 0, for a protocol that changes it.
    ``particles`` (N) gives the kick variance ``xi0^2 (1 - 1/N)`` that the engines' zero-momentum
    kicks leave each grain; ``chi`` is the contact value (1 for a dilute gas and DSMC without
    Enskog's factor). ``times`` are increasing, from 0. Returns ``(T, a2)``, arrays of the
    shape of ``times``.
    """
    t = np.asarray(times, dtype=np.float64)
    if np.ndim(strength) == 0:
        pairs = np.array([[0.0, float(strength)]])  # type: ignore[arg-type]
    else:
        pairs = np.asarray(strength, dtype=np.float64).reshape(-1, 2)
    temps, a2s = _T.sonine_relaxation(
        _gas(dimension, restitution, mass, number_density, radius, chi, particles),
        float(temperature),
        float(a2),
        np.ascontiguousarray(pairs[:, 0]),
        np.ascontiguousarray(pairs[:, 1]),
        np.ascontiguousarray(t.reshape(-1)),
    )
    return np.asarray(temps).reshape(t.shape), np.asarray(a2s).reshape(t.shape)


def white_noise_strength(
    temperature: ArrayLike,
    restitution: float,
    number_density: float,
    radius: float,
    mass: float = 1.0,
    chi: float = 1.0,
    particles: int | None = None,
    dimension: int = 2,
) -> Result:
    """The white-noise strength ``xi0^2`` whose steady temperature is ``temperature`` (KT-13 solved
    for ``xi0^2``, at KT-12's ``a2``; ``particles`` as in :func:`sonine_relaxation`). NaN where the
    temperature is not positive."""
    return _apply(
        _T.white_noise_strength,
        (_gas(dimension, restitution, mass, number_density, radius, chi, particles),),
        temperature,
    )
