"""granular.Simulation: every call, array shapes, dtypes and input order, all engines, errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import granular
from conftest import EDMD_2D, INTRUDER_NEEDLE_PATH


def test_every_engine_advances_and_observes(any_scenario: granular.Scenario) -> None:
    sim = granular.Simulation(any_scenario)
    assert sim.engine == any_scenario.engine
    assert sim.time == 0.0 and sim.events == 0 and sim.collisions == 0
    until = 0.02 if sim.engine != "intruder" else 100.0
    sim.advance(until)
    assert sim.time == until
    assert sim.events > 0
    obs = sim.observe()
    assert obs["engine"] == sim.engine
    assert obs["time"] == until
    assert obs["events"] == sim.events and obs["collisions"] == sim.collisions
    assert obs["particles"] == sim.particle_count
    assert obs["dimension"] == sim.dimension
    cols = sim.columns()
    assert next(iter(cols)) == "time" and cols["time"] == until
    assert 0.0 <= sim.fraction_done <= 1.0
    assert sim.wall_seconds >= 0.0
    assert "granular.Simulation" in repr(sim)
    reason = sim.run()
    assert reason in {"time", "collisions_per_particle", "collisions"}
    assert sim.fraction_done == pytest.approx(1.0)


def test_arrays_shapes_dtypes_and_copies(edmd2d: granular.Scenario) -> None:
    sim = granular.Simulation(edmd2d)
    n, d = 400, 2
    snap = sim.snapshot()
    for key, shape, dtype in [
        ("positions", (n, d), np.float64),
        ("velocities", (n, d), np.float64),
        ("radii", (n,), np.float64),
        ("masses", (n,), np.float64),
        ("species", (n,), np.uint32),
    ]:
        a = snap[key]
        assert a.shape == shape and a.dtype == dtype, key
        b = getattr(sim, key)
        assert b.shape == shape and b.dtype == dtype, key
        np.testing.assert_array_equal(a, b)
        assert b.flags.c_contiguous and b.flags.writeable and b.flags.owndata or b.base is not None
    assert snap["time"] == 0.0
    assert snap["species_names"] == ["small", "big"] == sim.species_names
    # A copy: writing into it does not touch the simulation.
    p = sim.positions
    p[:] = -1.0
    assert (sim.positions >= 0.0).all()


def test_input_order_is_kept(edmd2d: granular.Scenario) -> None:
    sim = granular.Simulation(edmd2d)
    expect_species = np.repeat(np.array([0, 1], dtype=np.uint32), [300, 100])
    x0, v0 = sim.positions, sim.velocities
    sim.advance(1.0)  # thousands of collisions, and the engine re-sorts its records in space
    assert sim.collisions > 2000
    np.testing.assert_array_equal(sim.species, expect_species)
    np.testing.assert_array_equal(sim.radii, np.where(expect_species == 0, 0.005, 0.01))
    np.testing.assert_array_equal(sim.masses, np.where(expect_species == 0, 1.0, 4.0))
    # Each grain moved at most (its fastest possible speed) x t: grain i is the same grain.
    energy = 0.5 * (sim.masses[:, None] * v0**2).sum()
    vmax = np.sqrt(2 * energy / sim.masses)
    dx = sim.positions - x0
    dx -= np.round(dx)  # periodic unit box: minimum image
    assert (np.linalg.norm(dx, axis=1) <= vmax * 1.0 + 1e-12).all()


def test_given_positions_come_back_in_order() -> None:
    sc = granular.Scenario.from_dict(
        {
            "engine": "edmd",
            "box": {"lengths": [1.0, 1.0], "boundary": "wall"},
            "species": [
                {
                    "name": "a",
                    "count": 3,
                    "radius": 0.01,
                    "positions": [[0.9, 0.9], [0.1, 0.1], [0.5, 0.2]],
                    "velocity": {"distribution": "per_grain", "velocities": [[0.1, 0.0], [0.0, 0.2], [-0.3, 0.0]]},
                },
                {
                    "name": "b",
                    "count": 2,
                    "radius": 0.02,
                    "mass": 3.0,
                    "positions": [[0.2, 0.8], [0.7, 0.5]],
                    "velocity": {"distribution": "zero"},
                },
            ],
            "stop": {"time": 1.0},
        }
    )
    sim = granular.Simulation(sc)
    x = np.array([[0.9, 0.9], [0.1, 0.1], [0.5, 0.2], [0.2, 0.8], [0.7, 0.5]])
    v = np.array([[0.1, 0.0], [0.0, 0.2], [-0.3, 0.0], [0.0, 0.0], [0.0, 0.0]])
    np.testing.assert_array_equal(sim.positions, x)
    np.testing.assert_array_equal(sim.velocities, v)
    np.testing.assert_array_equal(sim.species, [0, 0, 0, 1, 1])
    np.testing.assert_array_equal(sim.masses, [1, 1, 1, 3, 3])
    sim.advance(0.25)  # free flight: no grain reaches another or a wall
    assert sim.collisions == 0
    np.testing.assert_allclose(sim.positions, x + 0.25 * v, rtol=0, atol=1e-14)


def test_seed_argument_and_determinism(edmd2d: granular.Scenario) -> None:
    a = granular.Simulation(edmd2d, seed=11)
    b = granular.Simulation(edmd2d, seed=11)
    c = granular.Simulation(edmd2d, seed=12)
    assert a.scenario.seed == 11 and edmd2d.seed == 5
    for s in (a, b, c):
        s.advance(0.1)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert not np.array_equal(a.positions, c.positions)


def test_advance_in_steps_is_advance_at_once(edmd2d: granular.Scenario) -> None:
    a = granular.Simulation(edmd2d)
    b = granular.Simulation(edmd2d)
    for t in np.linspace(0.01, 0.2, 20):
        a.advance(float(t))
    b.advance(0.2)
    assert a.events == b.events
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.velocities, b.velocities)


def test_observation_is_typed_and_consistent(edmd2d: granular.Scenario) -> None:
    sim = granular.Simulation(edmd2d)
    sim.advance(0.1)
    obs = sim.observe()
    v, m = sim.velocities, sim.masses
    k = 0.5 * (m[:, None] * v**2).sum()
    assert obs["kinetic_energy"] == pytest.approx(k, rel=1e-12)
    assert obs["temperature"] == pytest.approx(2 * k / (2 * 400), rel=1e-12)
    assert [s["name"] for s in obs["species"]] == ["small", "big"]
    assert obs["collisions_per_particle"] == pytest.approx(2 * sim.collisions / 400)
    assert sim.initial_kinetic_energy > obs["kinetic_energy"]  # restitution 0.95
    assert obs == sim.observe()  # no side effect


def test_resolved_record_matches_the_state(edmd2d: granular.Scenario) -> None:
    sim = granular.Simulation(edmd2d)
    r = sim.resolved
    g = r["grains"]
    assert r["dimension"] == 2 and g["particles"] == 400
    # The packing fraction and temperature of the drawn state, from its own arrays.
    assert g["packing_fraction"] == pytest.approx((np.pi * sim.radii**2).sum(), rel=1e-12)
    assert g["temperature"] == pytest.approx(sim.observe()["temperature"], rel=1e-12)
    assert [s["name"] for s in g["species"]] == ["small", "big"]
    assert g["mean_free_time"] == pytest.approx(1.0 / g["collision_frequency"], rel=1e-12)
    assert g["cooling"]["haff_time"] > 0.0 and g["dsmc"] is None and g["driving"] is None
    assert sim.resolved == r  # a copy, the same each time


def test_resolved_record_of_dsmc_and_intruder(
    dsmc2d: granular.Scenario, intruder1d: granular.Scenario
) -> None:
    g = granular.Simulation(dsmc2d).resolved["grains"]
    assert g["dsmc"]["cell_size"] > 0.0 and len(g["dsmc"]["cell_edges"]) == 2
    if g["dsmc"]["follows_mean_free_time"]:
        assert g["dsmc"]["time_step"] == pytest.approx(0.1 * g["mean_free_time"], rel=1e-12)
    r = granular.Simulation(intruder1d).resolved
    assert r == {"dimension": 1, "grains": None}


def test_path_argument(root: Path) -> None:
    sim = granular.Simulation(root / "scenarios" / "maxwell-boltzmann.toml", seed=4)
    assert sim.particle_count == 10000 and sim.scenario.seed == 4


def test_impact_histogram(dsmc2d: granular.Scenario) -> None:
    sim = granular.Simulation(dsmc2d)
    sim.advance(0.02)
    h = sim.impact_histogram()
    assert h is not None
    assert h["edges"].shape == (h["counts"].shape[0] + 1,)
    assert h["counts"].dtype == np.uint64
    assert int(h["counts"].sum()) + h["underflow"] + h["overflow"] == sim.collisions


def test_intruder_has_no_grain_state(intruder1d: granular.Scenario) -> None:
    sim = granular.Simulation(intruder1d)
    sim.advance(50.0)
    assert sim.particle_count == 1 and sim.dimension == 1
    with pytest.raises(granular.SimulationError, match="intruder engine has no grain state"):
        sim.positions
    with pytest.raises(granular.SimulationError):
        sim.snapshot()
    assert sim.impact_histogram() is None


def test_intruder_statistics_against_martin_piasecki(intruder1d: granular.Scenario) -> None:
    intruder1d.set("stop.collisions", 200000)
    sim = granular.Simulation(intruder1d)
    assert sim.run() == "collisions"
    cols = sim.columns()
    ratio, err = cols["temperature_ratio"], cols["temperature_ratio_error"]
    theory = granular.theory.martin_piasecki_ratio(0.5)
    assert theory == pytest.approx(0.6)
    assert abs(ratio - theory) < 5 * err, (ratio, err)


def test_needle(root: Path) -> None:
    sc = granular.Scenario.load(INTRUDER_NEEDLE_PATH)
    sc.set("stop.collisions", 2000)
    sim = granular.Simulation(sc)
    sim.run()
    assert sim.dimension == 2
    assert "rotational_temperature" in sim.columns()


@pytest.mark.parametrize("model, dimension", [("disk", 2), ("sphere", 3)])
def test_disk_and_sphere_against_martin_piasecki(root: Path, model: str, dimension: int) -> None:
    sc = granular.Scenario.load(root / "scenarios" / f"intruder-{model}.toml")
    sc.set("intruder.restitution", 0.2)
    sc.set("intruder.mass", 2.0)
    sc.set("stop.collisions", 200000)
    sim = granular.Simulation(sc)
    assert sim.run() == "collisions"
    assert sim.dimension == dimension
    cols = sim.columns()
    assert ("velocity_z" in cols) == (dimension == 3)
    theory = granular.theory.martin_piasecki_ratio(0.2, 2.0, 1.0)
    assert cols["martin_piasecki_ratio"] == pytest.approx(theory, rel=1e-15)
    ratio, err = cols["temperature_ratio"], cols["temperature_ratio_error"]
    assert abs(ratio - theory) < 5 * err, (ratio, err, theory)
    rate = granular.theory.intruder_mean_collision_rate(
        theory * 0.5, radius=0.5, bath_temperature=0.5, mass=2.0, dimension=dimension
    )
    assert cols["theory_collision_rate"] == pytest.approx(rate, rel=1e-12)
    assert abs(cols["collision_rate"] - rate) < 5 * cols["collision_rate_error"]
    assert abs(cols["kurtosis"] - granular.theory.maxwellian_kurtosis(dimension)) < 5 * cols["kurtosis_error"]


def test_sphere_in_two_dimensions_is_refused(root: Path) -> None:
    text = (root / "scenarios" / "intruder-sphere.toml").read_text().replace("dimension = 3", "dimension = 2")
    with pytest.raises(granular.ScenarioError, match="set dimension = 3"):
        granular.Scenario.from_toml(text)


def test_errors(edmd2d: granular.Scenario) -> None:
    sim = granular.Simulation(edmd2d)
    sim.advance(0.05)
    with pytest.raises(ValueError, match="not before the current time"):
        sim.advance(0.01)
    with pytest.raises(ValueError, match="finite"):
        sim.advance(float("nan"))
    with pytest.raises(TypeError):
        granular.Simulation(42)  # type: ignore[arg-type]
    crowded = EDMD_2D.replace("radius = 0.005", "radius = 0.04")
    with pytest.raises(granular.SimulationError, match="small"):
        granular.Simulation(granular.Scenario.from_toml(crowded))


def test_run_out_hands_the_simulation_over(edmd2d: granular.Scenario, tmp_path: Path) -> None:
    sim = granular.Simulation(edmd2d)
    summary = sim.run(out=tmp_path / "run")
    assert summary["stop_reason"] == "collisions_per_particle"
    assert summary["n"] == 400
    with pytest.raises(granular.SimulationError, match="load_run"):
        sim.advance(10.0)
    assert "run to its end" in repr(sim)


ROUGH = """
engine = "edmd"
dimension = {d}
seed = 5
[box]
lengths = {lengths}
boundary = "periodic"
[[species]]
name = "grain"
count = 200
packing_fraction = 0.05
angular_velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[collisions]
restitution = 0.9
tangential_restitution = 0.5
[stop]
time = 0.05
"""


@pytest.mark.parametrize("d", [2, 3])
def test_angular_velocities_of_rough_grains(d: int, edmd2d: granular.Scenario) -> None:
    """Rough grains: (N,) in 2D, (N, 3) in 3D, also in snapshot(); None for smooth grains."""
    lengths = "[1.0, 1.0]" if d == 2 else "[1.0, 1.0, 1.0]"
    sim = granular.Simulation(granular.Scenario.from_toml(ROUGH.format(d=d, lengths=lengths)))
    w = sim.angular_velocities
    assert w is not None and w.dtype == np.float64
    assert w.shape == ((200,) if d == 2 else (200, 3))
    np.testing.assert_array_equal(sim.snapshot()["angular_velocities"], w)
    sim.run()
    assert not np.array_equal(sim.angular_velocities, w)
    cols = sim.columns()
    assert cols["translational_temperature"] == cols["temperature"]
    assert cols["temperature_ratio"] == pytest.approx(cols["rotational_temperature"] / cols["temperature"])
    smooth = granular.Simulation(edmd2d)
    assert smooth.angular_velocities is None
    assert "angular_velocities" not in smooth.snapshot()
