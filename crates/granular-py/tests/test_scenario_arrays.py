"""Per-grain NumPy arrays in a Scenario without TOML text (``Scenario.from_dict``, ``Scenario.set``,
``update``): the same scenario and the same bits as the numbers written inline; a run directory
keeps them in ``initial_state.npz`` and ``granular run DIR/scenario.toml`` repeats it bit for bit;
bad arrays are refused naming the key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import granular
from conftest import cli

N = 100


def lattice(n: int, d: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Positions on a lattice (radius 0.01 grains well apart) and random velocities."""
    side = int(np.ceil(n ** (1.0 / d)))
    idx = np.array(np.unravel_index(np.arange(n), (side,) * d)).T
    x = (idx + 0.5) / side
    v = np.random.default_rng(seed).normal(size=(n, d))
    return x, v


def base(engine: str = "edmd", d: int = 2) -> dict:
    return {
        "engine": engine,
        "dimension": d,
        "seed": 4,
        "collisions": {"restitution": 0.9},
        "species": [{"name": "grain", "count": N, "radius": 0.01}],
        "stop": {"time": 0.4},
        "output": {"interval": 0.2},
    }


def final(sc: granular.Scenario) -> np.ndarray:
    sim = granular.Simulation(sc)
    sim.advance(0.4)
    return np.concatenate([sim.positions.ravel(), sim.velocities.ravel()])


@pytest.mark.parametrize(("engine", "d"), [("edmd", 2), ("edmd", 3), ("dsmc", 2)])
def test_arrays_equal_inline_numbers_bit_for_bit(engine: str, d: int) -> None:
    x, v = lattice(N, d)
    inline = base(engine, d)
    inline["species"][0]["positions"] = x.tolist()
    inline["species"][0]["velocity"] = {"distribution": "per_grain", "velocities": v.tolist()}
    written = granular.Scenario.from_dict(inline)

    arrays = base(engine, d)
    arrays["species"][0]["positions"] = x
    arrays["species"][0]["velocity"] = {"distribution": "per_grain", "velocities": v}
    given = granular.Scenario.from_dict(arrays)
    assert given == written
    assert "positions" in arrays["species"][0], "the caller's dict is left as it was"

    by_set = granular.Scenario.from_dict(base(engine, d))
    by_set.set("species[0].positions", x)
    by_set.set("species.0.velocity.velocities", v)
    assert by_set == written
    by_update = granular.Scenario.from_dict(base(engine, d))
    by_update.update({"species[0].positions": x, "species[0].velocity.velocities": v})
    assert by_update == written

    reference = final(written)
    for sc in (given, by_set, by_update):
        assert np.array_equal(final(sc), reference)

    back = given.to_dict()["species"][0]
    assert isinstance(back["positions"], np.ndarray) and np.array_equal(back["positions"], x)
    assert np.array_equal(back["velocity"]["velocities"], v)


def test_an_override_of_the_key_or_a_table_above_replaces_the_array() -> None:
    x, v = lattice(N, 2)
    sc = granular.Scenario.from_dict(base())
    sc.set("species[0].positions", x)
    sc.set("species[0].velocity.velocities", v)
    sc.set("species[0].velocity", {"distribution": "zero"})
    assert "velocities" not in sc.to_dict()["species"][0]["velocity"]
    assert np.array_equal(sc.to_dict()["species"][0]["positions"], x)
    sc.set("species[0].positions", x[:, ::-1].tolist())  # a list goes through TOML, as before
    assert np.array_equal(sc.to_dict()["species"][0]["positions"], x[:, ::-1])


def test_bad_arrays_are_refused_naming_the_key_and_change_nothing() -> None:
    x, v = lattice(N, 2)
    sc = granular.Scenario.from_dict(base())
    before = sc.copy()
    with pytest.raises(TypeError, match=r"`species\[0\].positions` has dtype float32"):
        sc.set("species[0].positions", x.astype(np.float32))
    with pytest.raises(ValueError, match=r"`species\[0\].positions` has shape \(100,\)"):
        sc.set("species[0].positions", x[:, 0].copy())
    with pytest.raises(granular.ScenarioError, match=r"lists 99 positions for count = 100"):
        sc.set("species[0].positions", x[:-1])
    with pytest.raises(granular.ScenarioError, match=r"has 3 components per grain; give 2"):
        sc.set("species[0].positions", np.zeros((N, 3)) + 0.5)
    bad = x.copy()
    bad[7, 1] = np.nan
    with pytest.raises(granular.ScenarioError, match=r"position 7"):
        sc.set("species[0].positions", bad)
    with pytest.raises(granular.ScenarioError, match=r"needs 100 vectors of 2 components"):
        sc.set("species[0].velocity.velocities", v[:10])
    with pytest.raises(granular.ScenarioError, match=r"species 3, but the scenario has 1"):
        sc.set("species[3].positions", x)
    with pytest.raises(ValueError, match=r"goes with distribution = \"per_grain\""):
        d = base()
        d["species"][0]["velocity"] = {"distribution": "maxwell_boltzmann", "temperature": 1.0, "velocities": v}
        granular.Scenario.from_dict(d)
    assert sc == before


def test_a_run_directory_keeps_the_arrays_and_runs_again_bit_for_bit(tmp_path: Path) -> None:
    x, v = lattice(N, 2)
    d = base()
    d["species"][0]["positions"] = x
    d["species"][0]["velocity"] = {"distribution": "per_grain", "velocities": v}
    granular.Simulation(granular.Scenario.from_dict(d)).run(out=tmp_path / "py")
    stored = np.load(tmp_path / "py" / "initial_state.npz")
    assert np.array_equal(stored["species[0].positions"], x)
    assert np.array_equal(stored["species[0].velocity.velocities"], v)
    assert 'npz = "initial_state.npz"' in (tmp_path / "py" / "scenario.toml").read_text()
    # The command line from another working directory, from the run directory's scenario.
    cli("run", str(tmp_path / "py" / "scenario.toml"), "--out", str(tmp_path / "cli"), "--quiet", cwd=Path("/"))
    for f in ["timeseries.csv", "snapshots/snapshot_000002.npz", "initial_state.npz"]:
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    # Loaded from the file, the relative .npz is the run directory's.
    again = granular.Scenario.load(tmp_path / "py" / "scenario.toml")
    assert again == granular.Scenario.from_dict(d)


def test_a_scenario_names_an_npz_file_beside_it(tmp_path: Path) -> None:
    x, v = lattice(N, 2)
    np.savez(tmp_path / "start.npz", positions=x, speeds=v)
    text = """
engine = "edmd"
dimension = 2
seed = 4
[collisions]
restitution = 0.9
[[species]]
name = "grain"
count = 100
radius = 0.01
positions = { npz = "start.npz" }
velocity = { distribution = "per_grain", velocities = { npz = "start.npz", array = "speeds" } }
[stop]
time = 0.4
[output]
interval = 0.2
"""
    (tmp_path / "s.toml").write_text(text)
    sc = granular.Scenario.load(tmp_path / "s.toml")
    d = base()
    d["species"][0]["positions"] = x
    d["species"][0]["velocity"] = {"distribution": "per_grain", "velocities": v}
    assert sc == granular.Scenario.from_dict(d)
    (tmp_path / "s.toml").write_text(text.replace('array = "speeds"', 'array = "v"'))
    with pytest.raises(granular.ScenarioError, match=r"has no array \"v\"; its arrays are"):
        granular.Scenario.load(tmp_path / "s.toml")


def test_a_sweep_refuses_numpy_arrays_saying_what_to_do() -> None:
    x, _ = lattice(N, 2)
    d = base()
    d["species"][0]["positions"] = x
    d["sweep"] = {"key": "collisions.restitution", "values": [0.8, 0.9]}
    with pytest.raises(ValueError, match=r"numpy.savez"):
        granular.run_sweep(granular.Scenario.from_dict(d), "/tmp/never-written")
