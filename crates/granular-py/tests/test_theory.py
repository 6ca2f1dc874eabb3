"""granular.theory: the library's exact formulas on NumPy arrays, against hand values and each other."""

from __future__ import annotations

import math

import numpy as np
import pytest

from granular import theory


def test_scalars_give_floats_and_arrays_keep_their_shape() -> None:
    assert isinstance(theory.speed_density(1.0), float)
    v = np.linspace(0, 3, 12).reshape(3, 4)
    assert theory.speed_density(v).shape == (3, 4)
    # Broadcasting: temperatures along a new axis.
    out = theory.speed_density(v[None], temperature=np.array([1.0, 2.0])[:, None, None])
    assert out.shape == (2, 3, 4)


def test_maxwell_boltzmann_by_hand() -> None:
    m, t, v = 2.0, 1.5, np.array([0.3, 0.7, 2.0])
    np.testing.assert_allclose(
        theory.speed_density(v, m, t), m * v / t * np.exp(-m * v**2 / (2 * t)), rtol=1e-14
    )
    # 3D: 4 pi v^2 (m / 2 pi T)^{3/2} exp(-m v^2 / 2T).
    np.testing.assert_allclose(
        theory.speed_density(v, m, t, dimension=3),
        4 * np.pi * v**2 * (m / (2 * np.pi * t)) ** 1.5 * np.exp(-m * v**2 / (2 * t)),
        rtol=1e-13,
    )
    assert theory.speed_cdf(np.inf) == 1.0
    # puruspe's incomplete gamma function: about 1e-11 relative.
    assert theory.speed_cdf(1.0) == pytest.approx(1 - math.exp(-0.5), rel=1e-10)
    assert theory.mean_speed(2.0, 1.5) == pytest.approx(math.sqrt(math.pi * 1.5 / 4.0), rel=1e-14)
    # Normalised (trapezoid on a fine grid).
    grid = np.linspace(0, 12, 200001)
    assert np.trapezoid(theory.speed_density(grid, 1.0, 1.0, dimension=3), grid) == pytest.approx(1.0, abs=1e-9)


def test_equations_of_state_and_contact_values() -> None:
    eta = 1e-6
    assert (theory.hard_disk_compressibility(eta) - 1) / eta == pytest.approx(2.0, rel=1e-4)
    assert (theory.hard_sphere_compressibility(eta) - 1) / eta == pytest.approx(4.0, rel=1e-4)
    assert theory.hard_sphere_compressibility(0.5) == pytest.approx((1 + 0.5 + 0.25 - 0.125) / 0.125)
    np.testing.assert_allclose(theory.contact_value([0.0, 0.5]), [1.0, 3.125], rtol=1e-15)
    assert theory.contact_value(0.5, dimension=3) == pytest.approx(6.0, rel=1e-15)
    with pytest.raises(ValueError, match="use 2"):
        theory.contact_value(0.1, dimension=4)
    z = theory.compressibility(0.3)
    nu = theory.collision_frequency_from_pressure(z, 0.02)
    assert nu == pytest.approx(4 * (z - 1) / math.sqrt(math.pi) / 0.02)


def test_haff_law_with_sonine_t0() -> None:
    # 2D, n = 2, R = 0.25, T = m = 1, e = 0.5: zeta0 = 1.329340388179137 (library test).
    zeta = theory.cooling_rate(2.0, 0.25, 1.0, 0.5, sonine=False)
    assert zeta == pytest.approx(1.329340388179137, rel=1e-14)
    a2 = theory.sonine_a2(0.5)
    assert a2 == pytest.approx(4.0 / 48.25, rel=1e-14)
    t0 = theory.haff_time(2.0, 0.25, 1.0, 0.5)
    assert t0 == pytest.approx(2.0 / (zeta * (1 + 3 * a2 / 16)), rel=1e-14)
    t = np.array([0.0, t0, 3 * t0])
    np.testing.assert_allclose(theory.haff_energy(t, 8.0, t0), [8.0, 2.0, 0.5], rtol=1e-15)
    np.testing.assert_allclose(theory.haff_temperature(t, 1.0, t0), [1.0, 0.25, 1 / 16], rtol=1e-15)
    # Vectorised over restitution.
    e = np.array([0.5, 0.9])
    np.testing.assert_allclose(theory.haff_time(2.0, 0.25, 1.0, e), [theory.haff_time(2.0, 0.25, 1.0, x) for x in e])
    chi = theory.contact_value(theory.packing_fraction(2.0, 0.25))
    assert theory.collision_frequency(2.0, 0.25, chi=chi) == pytest.approx(chi * 2 * math.sqrt(math.pi))
    assert theory.mean_free_path(1.0, 0.5) == pytest.approx(0.3535533905932737, rel=1e-14)


def test_martin_piasecki_and_intruder_fluxes() -> None:
    np.testing.assert_allclose(theory.martin_piasecki_ratio([0.0, 0.5, 1.0]), [1 / 3, 0.6, 1.0], rtol=1e-15)
    assert theory.martin_piasecki_ratio(0.3, 2.0, 4.0) == pytest.approx(theory.martin_piasecki_ratio(0.3, 0.5, 1.0))
    # Gaussian bath, a = m / 2T = 1: rate of an intruder at rest = rho <|v|> = rho / sqrt(pi a).
    assert theory.bath_flux(0.0, temperature=0.5, density=2.0) == pytest.approx(2.0 / math.sqrt(math.pi), rel=1e-14)
    v1 = np.linspace(-3, 3, 7)
    both = theory.bath_flux(v1)
    np.testing.assert_allclose(both, theory.bath_flux(v1, side="plus") + theory.bath_flux(v1, side="minus"))
    # phi_+(v1) - phi_-(v1) = v1 (the mean bath velocity is zero).
    np.testing.assert_allclose(
        theory.bath_flux(v1, side="plus") - theory.bath_flux(v1, side="minus"), v1, atol=1e-14
    )
    assert theory.bath_density(0.0, temperature=0.5) == pytest.approx(1 / math.sqrt(math.pi), rel=1e-14)
    assert theory.bath_density(0.0, bath="power_law") > 0
    with pytest.raises(ValueError, match="gaussian"):
        theory.bath_density(0.0, bath="uniform")  # type: ignore[arg-type]
    # Needle at rest: Phi = rho L <|v|> (both faces).
    assert theory.needle_flux(0.0, 0.0, length=2.0, density=3.0, temperature=0.5) == pytest.approx(
        3.0 * 2.0 * theory.bath_flux(0.0, temperature=0.5), rel=1e-12
    )


def test_disk_and_sphere_collision_rates() -> None:
    # At rest (a = m / 2T_B = 1): rho sigma_d <|u|>, the bath's mean speed sqrt(pi)/2 (2D), 2/sqrt(pi) (3D).
    assert theory.intruder_collision_rate(0.0, radius=0.5, dimension=2) == pytest.approx(
        math.sqrt(math.pi) / 2, rel=1e-12
    )
    assert theory.intruder_collision_rate(0.0, radius=0.5, bath_density=2.0, dimension=3) == pytest.approx(
        2.0 * math.pi * 0.25 * 2 / math.sqrt(math.pi), rel=1e-12
    )
    # Far away: rho sigma_d (|V| + (d - 1)/(4 a |V|)).
    v = 200.0
    for d, sigma in [(2, 1.0), (3, math.pi / 4)]:
        assert theory.intruder_collision_rate(v, dimension=d) == pytest.approx(
            sigma * (v + (d - 1) / (4 * v)), rel=1e-8
        )
    # 1D: G-7 (the radius does not enter).
    v1 = np.linspace(-2, 2, 5)
    np.testing.assert_allclose(
        theory.intruder_collision_rate(np.abs(v1), radius=7.0, dimension=1), theory.bath_flux(v1, temperature=0.5)
    )
    # G-42 is the average of G-32 over the intruder's Maxwellian (mass 2, T = 0.3): quadrature in NumPy.
    c = np.linspace(0.0, 12.0, 24001)
    for d in (2, 3):
        rates = theory.intruder_collision_rate(c, radius=0.7, bath_density=1.5, temperature=0.4, bath_mass=0.5, dimension=d)
        weights = theory.speed_density(c, mass=2.0, temperature=0.3, dimension=d)
        mean = np.trapezoid(rates * weights, c) if hasattr(np, "trapezoid") else np.trapz(rates * weights, c)
        want = theory.intruder_mean_collision_rate(
            0.3, radius=0.7, bath_density=1.5, bath_temperature=0.4, bath_mass=0.5, mass=2.0, dimension=d
        )
        assert mean == pytest.approx(want, rel=1e-5)
    assert theory.maxwellian_kurtosis(2) == 2.0 and theory.maxwellian_kurtosis(3) == pytest.approx(5 / 3)
    np.testing.assert_allclose(theory.martin_piasecki_ratio(0.5, [0.5, 1.0, 2.0]), [0.5, 0.6, 2 / 3])
    with pytest.raises(ValueError, match="dimension is 4"):
        theory.intruder_collision_rate(1.0, dimension=4)
def test_rough_grains_theory_on_arrays() -> None:
    """RS-4 to RS-9 on arrays: hand values of docs/rough.md's tables, limits, NaN outside the ranges."""
    # White noise (RS-6): kappa (1 + beta) / (1 + 2 kappa - beta), any alpha.
    beta = np.array([0.0, 0.5, -0.5, 1.0])
    np.testing.assert_allclose(
        theory.rough_temperature_ratio(0.9, beta, 0.5, state="white_noise"),
        0.5 * (1 + beta) / (2.0 - beta),
        rtol=1e-14,
    )
    # Homogeneous cooling state (RS-4, RS-5), docs/rough.md: disks and spheres.
    assert theory.rough_temperature_ratio(0.9, 0.0) == pytest.approx(0.4695, abs=5e-5)
    assert theory.rough_temperature_ratio(0.9, 0.0, dimension=3) == pytest.approx(0.5738, abs=5e-5)
    assert theory.rough_cooling_rate(0.9, 0.0) == pytest.approx(0.2078, abs=5e-5)
    assert theory.rough_temperature_ratio(0.5, 1.0, approximation="sonine") == pytest.approx(1.8095, abs=5e-5)
    # Perfectly rough elastic grains: equipartition, no cooling.
    assert theory.rough_temperature_ratio(1.0, 1.0, dimension=3) == pytest.approx(1.0, abs=1e-12)
    assert theory.rough_cooling_rate(1.0, 1.0) == pytest.approx(0.0, abs=1e-12)
    out = theory.rough_temperature_ratio(np.array([[0.9], [0.7]]), np.array([0.0, 0.5, 2.0]))
    assert out.shape == (2, 3) and np.isnan(out[:, 2]).all() and np.isfinite(out[:, :2]).all()
    assert math.isnan(theory.rough_temperature_ratio(0.9, 0.0, inertia=0.8, dimension=3))
    with pytest.raises(ValueError, match="white_noise"):
        theory.rough_temperature_ratio(0.9, 0.0, state="driven")  # type: ignore[arg-type]


def test_sonine_relaxation_of_a_heated_gas() -> None:
    """KT-14/KT-15 on NumPy: elastic grains heat at exactly m xi0^2 (1 - 1/N) and stay Maxwellian; an
    inelastic gas relaxes to the steady temperature of white_noise_strength (KT-13) and to KT-12's a2 up
    to order a2^2; a protocol of strengths is followed piecewise; bad input is a ValueError."""
    gas = dict(number_density=1e5, radius=1e-4, particles=1000)
    times = np.linspace(0.0, 2.0, 5)
    temps, a2 = theory.sonine_relaxation(times, 1.0, 0.0, 0.5, 1.0, mass=2.0, **gas)
    np.testing.assert_allclose(temps, 1.0 + 2.0 * 0.5 * (1 - 1 / 1000) * times, rtol=0, atol=1e-12)
    assert np.all(a2 == 0.0)
    omega = float(theory.collision_frequency(1e5, 1e-4, 1.0))
    for e in (0.3, 0.8):
        xi = float(theory.white_noise_strength(0.5, e, **gas))
        end_t, end_a2 = theory.sonine_relaxation([300.0 / omega], 2.0, 0.0, xi, e, **gas)
        kt12 = 16 * (1 - e) * (1 - 2 * e * e) / (73 + 56 * 2 - 3 * e * (35 + 8 * 2) + 30 * e * e * (1 - e))
        assert abs(end_a2[0] - kt12) < 2 * kt12**2
        assert abs(end_t[0] / 0.5 - 1) < kt12**2
    # A protocol: heating switched off at t = 1 (free cooling), against two calls.
    both, _ = theory.sonine_relaxation([1.0, 2.0], 1.0, 0.0, [(0.0, 0.5), (1.0, 0.0)], 1.0, **gas)
    assert both[1] == both[0]
    with pytest.raises(ValueError, match="strength"):
        theory.sonine_relaxation([1.0], 1.0, 0.0, -1.0, 0.5, **gas)
    with pytest.raises(ValueError, match="increasing"):
        theory.sonine_relaxation([2.0, 1.0], 1.0, 0.0, 1.0, 0.5, **gas)
    with pytest.raises(ValueError, match="restitution"):
        theory.sonine_relaxation([1.0], 1.0, 0.0, 1.0, 1.5, **gas)
    assert np.isnan(theory.white_noise_strength(-1.0, 0.5, **gas))
