"""Simulation.set_state and Simulation.from_snapshot: a state set at time t goes on exactly, bit for bit,
as a simulation started from the same arrays at t, in every engine with grains; bad arrays are refused and
change nothing."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import granular
from conftest import DSMC_2D, EDMD_2D, EDMD_3D, INTRUDER_1D

DSMC_3D = DSMC_2D.replace("dimension = 2", "dimension = 3").replace("lengths = [1.0, 1.0]", "lengths = [1.0, 1.0, 1.0]")
DRIVEN = "\n[driving]\nkind = \"white_noise\"\nstrength = 1.0\n"
# [driving]'s steady states are those of one species: the event-driven gas without its big disks.
EDMD_2D_ONE = EDMD_2D[: EDMD_2D.index('[[species]]\nname = "big"')] + EDMD_2D[EDMD_2D.index("[collisions]") :]

CASES = {
    "edmd2d": EDMD_2D,
    "edmd3d": EDMD_3D,
    "dsmc2d": DSMC_2D,
    "dsmc3d": DSMC_3D,
    "edmd2d-driven": EDMD_2D_ONE.replace("[stop]", DRIVEN + "[stop]"),
    "dsmc2d-driven": DSMC_2D.replace("[stop]", DRIVEN + "[stop]"),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_set_state_goes_on_as_from_snapshot(name: str) -> None:
    scenario = granular.Scenario.from_toml(CASES[name])
    t, t_end = 0.03, 0.06
    sim = granular.Simulation(scenario)
    sim.advance(t)
    snap = sim.snapshot()
    # A temperature step and a shear flow along the first axis.
    v = snap["velocities"].copy()
    v[:, 0] = 1.5 * v[:, 0] + 0.2 * (snap["positions"][:, 1] - 0.5)
    snap["velocities"] = v
    before = sim.collisions
    resolved = sim.resolved
    sim.set_state(velocities=v)
    assert sim.time == t and sim.collisions == before
    np.testing.assert_array_equal(sim.velocities, v)
    started = granular.Simulation.from_snapshot(scenario, snap)
    assert started.time == t
    # The resolved record stays the scenario's, at its drawn initial state (docs/python.md).
    assert sim.resolved == started.resolved == resolved
    np.testing.assert_array_equal(started.positions, sim.positions)
    sim.advance(t_end)
    started.advance(t_end)
    assert sim.collisions - before == started.collisions > 0
    assert sim.positions.tobytes() == started.positions.tobytes()
    assert sim.velocities.tobytes() == started.velocities.tobytes()


def test_from_a_run_directory_snapshot(tmp_path: Path) -> None:
    scenario = granular.Scenario.from_toml(EDMD_2D)
    granular.Simulation(scenario).run(out=tmp_path / "run")
    run = granular.load_run(tmp_path / "run")
    snap = run.snapshot(1)
    assert snap.time > 0.0
    by_path = granular.Simulation.from_snapshot(scenario, run.snapshot_paths[1])
    by_object = granular.Simulation.from_snapshot(scenario, snap)
    live = granular.Simulation(scenario)
    live.advance(snap.time)
    live.set_state(positions=snap.positions, velocities=snap.velocities)
    for sim in (by_path, by_object, live):
        assert sim.time == snap.time
        sim.advance(snap.time + 0.05)
    assert by_path.positions.tobytes() == by_object.positions.tobytes() == live.positions.tobytes()
    assert by_path.velocities.tobytes() == by_object.velocities.tobytes() == live.velocities.tobytes()


def test_bad_arrays_are_refused_and_change_nothing() -> None:
    scenario = granular.Scenario.from_toml(EDMD_2D)
    sim = granular.Simulation(scenario)
    twin = granular.Simulation(scenario)
    sim.advance(0.02)
    twin.advance(0.02)
    x, v = sim.positions, sim.velocities
    with pytest.raises(TypeError, match=r"`velocities` has dtype float32; give float64"):
        sim.set_state(velocities=v.astype(np.float32))
    with pytest.raises(ValueError, match=r"`positions` has shape \(399, 2\); give shape \(400, 2\)"):
        sim.set_state(positions=x[:-1])
    with pytest.raises(ValueError, match=r"`positions` has shape \(800,\)"):
        sim.set_state(positions=x.ravel())
    bad = v.copy()
    bad[12, 1] = np.nan
    with pytest.raises(ValueError, match=r"`velocities\[12, 1\]` is NaN; give finite numbers"):
        sim.set_state(velocities=bad)
    outside = x.copy()
    outside[3, 0] = 1.25
    with pytest.raises(ValueError, match=r"`positions\[3, 0\]` = 1.25 lies outside the box"):
        sim.set_state(positions=outside, velocities=v)
    overlap = x.copy()
    overlap[9] = overlap[4] + [0.001, 0.0]
    with pytest.raises(ValueError, match=r"grains 4 and 9 overlap \(distance 0\.00(1|0999)"):
        sim.set_state(positions=overlap)
    with pytest.raises(TypeError, match="snapshot must be"):
        granular.Simulation.from_snapshot(scenario, 3.0)
    sim.advance(0.05)
    twin.advance(0.05)
    assert sim.positions.tobytes() == twin.positions.tobytes()
    assert sim.velocities.tobytes() == twin.velocities.tobytes()
    # A list of rows is taken as float64.
    sim.set_state(velocities=sim.velocities.tolist())


def test_the_intruder_engine_has_no_grains() -> None:
    scenario = granular.Scenario.from_toml(INTRUDER_1D)
    sim = granular.Simulation(scenario)
    with pytest.raises(granular.SimulationError, match="intruder engine has no grain state"):
        sim.set_state(velocities=np.zeros((1, 1)))
    with pytest.raises(granular.SimulationError, match="intruder engine has no grain state"):
        granular.Simulation.from_snapshot(scenario, {"time": 0.0, "positions": [], "velocities": []})


def test_a_walled_box_takes_centres_a_radius_from_the_walls() -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(EDMD_3D))
    x = sim.positions
    r = sim.radii[0]
    x[0, 2] = 0.5 * r
    with pytest.raises(ValueError, match=r"walls; radius"):
        sim.set_state(positions=x)


def _interrupted_run(scenario: granular.Scenario, out: Path) -> None:
    """A run directory left as a killed run (Ctrl-C after half a second), with its checkpoint."""
    import _thread
    import signal
    import threading

    # A process started without job control inherits SIGINT ignored, and then Python installs
    # no handler (as in test_threads.py): install Python's own for the test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            granular.Simulation(scenario).run(out=out)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_resume_goes_on_as_granular_resume(tmp_path: Path) -> None:
    import shutil
    import time

    # An elastic gas (collisions at a steady rate) run for about two seconds of this machine's
    # wall time, interrupted after half a second. (A stop on collisions per particle of the
    # cooling gas would be refused by the pre-flight estimate: Haff's law makes thousands of
    # collisions per grain take an astronomically long time.)
    scenario = granular.Scenario.from_toml(EDMD_2D)
    scenario.set("collisions.restitution", 1.0)
    probe = granular.Simulation(scenario)
    probe.advance(0.05)
    start = time.perf_counter()
    probe.advance(0.55)
    stop = 2.0 * 0.5 / max(time.perf_counter() - start, 1e-6)
    scenario.set("stop.time", stop)
    scenario.set("stop.collisions_per_particle", 1e6)  # beyond the time: the time stops the run
    scenario.set("output.interval", stop / 40)
    scenario.set("output.checkpoint_seconds", 1e-9)
    _interrupted_run(scenario, tmp_path / "a")
    assert any((tmp_path / "a").glob("checkpoint*"))
    shutil.copytree(tmp_path / "a", tmp_path / "b")
    shutil.copytree(tmp_path / "a", tmp_path / "c")
    assert granular.main(["resume", str(tmp_path / "a"), "--quiet"]) == 0
    by_cli = granular.load_run(tmp_path / "a").snapshot(-1)
    in_memory = granular.Simulation.resume(tmp_path / "b")
    assert 0.0 < in_memory.time < by_cli.time
    assert in_memory.run() == "time"
    assert in_memory.time == by_cli.time
    assert in_memory.positions.tobytes() == by_cli.positions.tobytes()
    assert in_memory.velocities.tobytes() == by_cli.velocities.tobytes()
    # Into its own directory: the files of `granular resume`.
    recorded = granular.Simulation.resume(tmp_path / "c")
    recorded.run(out=tmp_path / "c")
    by_python = granular.load_run(tmp_path / "c")
    assert by_python.snapshot(-1).positions.tobytes() == by_cli.positions.tobytes()
    np.testing.assert_array_equal(
        np.asarray(by_python.timeseries["kinetic_energy"]), np.asarray(granular.load_run(tmp_path / "a").timeseries["kinetic_energy"])
    )
    with pytest.raises(granular.SimulationError, match="finished"):
        granular.Simulation.resume(tmp_path / "a")


def test_set_state_needs_an_array() -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(EDMD_2D))
    with pytest.raises(TypeError, match="positions=..., velocities=..., angular_velocities=..."):
        sim.set_state()


def test_set_in_flight_is_validated_and_recorded(tmp_path: Path) -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(EDMD_2D))
    sim.advance(0.02)
    change = sim.set("collisions.restitution", 0.5)
    assert change == {"time": 0.02, "key": "collisions.restitution", "old": "0.95", "new": "0.5"}
    assert sim.changes == [change]
    assert sim.scenario.to_dict()["collisions"]["restitution"] == 0.5
    # The resolved record follows the new restitution at the same initial temperature: the
    # same as a simulation of the same seed built with e = 0.5 from the start.
    quenched = granular.Scenario.from_toml(EDMD_2D)
    quenched.set("collisions.restitution", 0.5)
    assert sim.resolved == granular.Simulation(quenched).resolved
    with pytest.raises(granular.ScenarioError, match="cannot change in flight") as err:
        sim.set("species[0].count", 10)
    assert err.value.key == "species[0].count"
    with pytest.raises(granular.ScenarioError, match="collisions.restitution"):
        sim.set("collisions.restitution", 1.5)
    with pytest.raises(granular.ScenarioError, match="no \\[driving\\]"):
        sim.set("driving.strength", 1.0)
    assert sim.changes == [change]
    summary = sim.run(out=tmp_path / "run")
    assert summary["changes"] == [change]
    log = (tmp_path / "run" / "log.txt").read_text()
    assert "set collisions.restitution from 0.95 to 0.5 at t = 0.02" in log


def test_set_on_the_intruder_engine_is_refused() -> None:
    sim = granular.Simulation(granular.Scenario.from_toml(INTRUDER_1D))
    with pytest.raises(granular.ScenarioError, match="intruder engine"):
        sim.set("collisions.restitution", 0.5)


def _rough(engine: str, dimension: int) -> str:
    count = 2000 if engine == "dsmc" else 300
    return f"""
engine = "{engine}"
dimension = {dimension}
seed = 9
box = {{ boundary = "periodic" }}
[collisions]
restitution = 0.9
tangential_restitution = 0.0
[[species]]
name = "grain"
count = {count}
packing_fraction = 0.1
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
angular_velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[stop]
time = 1.0
[output]
interval = 0.1
snapshot_every = 1
"""


@pytest.mark.parametrize("engine", ["edmd", "dsmc"])
@pytest.mark.parametrize("dimension", [2, 3])
def test_rough_grains_set_with_their_spins(engine: str, dimension: int, tmp_path: Path) -> None:
    """Positions, velocities and angular velocities set at t go on as from_snapshot of the same arrays
    (a dict, and a run directory's snapshot file of a rough run, which carries its spins)."""
    scenario = granular.Scenario.from_toml(_rough(engine, dimension))
    sim = granular.Simulation(scenario)
    sim.advance(0.2)
    snap = sim.snapshot()
    w = -2.0 * snap["angular_velocities"]
    assert w.shape == ((sim.particle_count,) if dimension == 2 else (sim.particle_count, 3))
    snap["angular_velocities"] = w
    snap["velocities"] = 0.5 * snap["velocities"]
    sim.set_state(velocities=snap["velocities"], angular_velocities=w)
    np.testing.assert_array_equal(sim.angular_velocities, w)
    started = granular.Simulation.from_snapshot(scenario, snap)
    np.testing.assert_array_equal(started.angular_velocities, w)
    for s in (sim, started):
        s.advance(0.4)
    assert sim.positions.tobytes() == started.positions.tobytes()
    assert sim.velocities.tobytes() == started.velocities.tobytes()
    assert sim.angular_velocities.tobytes() == started.angular_velocities.tobytes()
    assert sim.angular_velocities.tobytes() != w.tobytes()
    # A run directory's snapshot of a rough run restores the spins too.
    granular.Simulation(scenario).run(out=tmp_path / "run")
    run = granular.load_run(tmp_path / "run")
    k = 3
    snap = run.snapshot(k)
    assert snap.angular_velocities is not None and snap.angular_velocities.shape == w.shape
    by_path = granular.Simulation.from_snapshot(scenario, run.snapshot_paths[k])
    by_object = granular.Simulation.from_snapshot(scenario, snap)
    np.testing.assert_array_equal(by_path.angular_velocities, snap.angular_velocities)
    np.testing.assert_array_equal(by_object.angular_velocities, snap.angular_velocities)
    for s in (by_path, by_object):
        s.advance(snap.time + 0.1)
    assert by_path.angular_velocities.tobytes() == by_object.angular_velocities.tobytes()


def test_bad_angular_velocities_are_refused_and_change_nothing() -> None:
    scenario = granular.Scenario.from_toml(_rough("edmd", 3))
    sim = granular.Simulation(scenario)
    twin = granular.Simulation(scenario)
    for s in (sim, twin):
        s.advance(0.1)
    n = sim.particle_count
    w = sim.angular_velocities
    with pytest.raises(ValueError, match=rf"`angular_velocities` has shape \({n},\); give shape \({n}, 3\)"):
        sim.set_state(velocities=0.5 * sim.velocities, angular_velocities=w[:, 0].copy())
    bad = w.copy()
    bad[4, 2] = np.inf
    with pytest.raises(ValueError, match=r"`angular_velocities\[4, 2\]` is inf"):
        sim.set_state(velocities=0.5 * sim.velocities, angular_velocities=bad)
    with pytest.raises(TypeError, match="dtype"):
        sim.set_state(angular_velocities=w.astype(np.float32))
    for s in (sim, twin):
        s.advance(0.2)
    assert sim.velocities.tobytes() == twin.velocities.tobytes()
    assert sim.angular_velocities.tobytes() == twin.angular_velocities.tobytes()
    smooth = granular.Simulation(granular.Scenario.from_toml(EDMD_2D))
    with pytest.raises(ValueError, match="grains are smooth"):
        smooth.set_state(angular_velocities=np.zeros(smooth.particle_count))


def test_tangential_restitution_in_flight() -> None:
    """Rough grains made smooth in flight keep their spins; the scenario in force says so; smooth grains
    cannot become rough."""
    sim = granular.Simulation(granular.Scenario.from_toml(_rough("dsmc", 2)))
    sim.advance(0.1)
    change = sim.set("collisions.tangential_restitution", -1.0)
    assert (change["old"], change["new"]) == ("0.0", "-1.0")
    assert sim.scenario.to_dict()["collisions"]["tangential_restitution"] == -1.0
    w = sim.angular_velocities.copy()
    before = sim.collisions
    sim.advance(0.3)
    assert sim.collisions > before
    assert sim.angular_velocities.tobytes() == w.tobytes()
    smooth = granular.Simulation(granular.Scenario.from_toml(EDMD_2D))
    with pytest.raises(granular.ScenarioError, match="cannot become rough in flight"):
        smooth.set("collisions.tangential_restitution", 0.5)
    assert smooth.changes == []


def test_fortran_ordered_arrays_are_read_by_rows() -> None:
    """A transposed (Fortran-ordered) array is read row by row, as NumPy indexes it, not as it lies in
    memory."""
    sim = granular.Simulation(granular.Scenario.from_toml(DSMC_2D))
    v = sim.velocities
    fortran = np.asfortranarray(v[:, ::-1])
    assert fortran.flags.f_contiguous and not fortran.flags.c_contiguous
    sim.set_state(velocities=fortran)
    assert np.array_equal(sim.velocities, v[:, ::-1])
