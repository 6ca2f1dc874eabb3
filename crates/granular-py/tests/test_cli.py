"""The command line from Python (``python -m granular``), and bit-identical results from Python and from the
command line for the same scenario and seed."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import granular
from conftest import SCENARIOS, cli


@pytest.mark.parametrize("name", ["edmd2d", "dsmc2d", "intruder1d"])
def test_python_run_equals_cli_run(name: str, tmp_path: Path) -> None:
    path = tmp_path / f"{name}.toml"
    path.write_text(SCENARIOS[name])
    cli("run", str(path), "--out", str(tmp_path / "cli"), "--seed", "17", "--quiet")
    sim = granular.Simulation(granular.Scenario.load(path), seed=17)
    summary = sim.run(out=tmp_path / "py")
    for f in ["timeseries.csv", "scenario.toml"]:
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    on_disk = json.loads((tmp_path / "cli" / "summary.json").read_text())
    timing = {"wall_seconds", "events_per_second", "collisions_per_second"}
    for key, value in on_disk.items():
        if key not in timing:
            assert summary[key] == value, key
    py_snaps = sorted((tmp_path / "py").glob("snapshots/*.npz"))
    cli_snaps = sorted((tmp_path / "cli").glob("snapshots/*.npz"))
    assert len(py_snaps) == len(cli_snaps)
    for a, b in zip(py_snaps, cli_snaps):
        assert a.read_bytes() == b.read_bytes(), a.name


def test_in_memory_run_equals_cli_run(tmp_path: Path) -> None:
    path = tmp_path / "edmd.toml"
    path.write_text(SCENARIOS["edmd2d"])
    cli("run", str(path), "--out", str(tmp_path / "cli"), "--quiet")
    sim = granular.Simulation(granular.Scenario.load(path))
    assert sim.run() == "collisions_per_particle"
    last = granular.Snapshot.load(sorted((tmp_path / "cli").glob("snapshots/*.npz"))[-1])
    assert sim.time == last.time
    np.testing.assert_array_equal(sim.positions, last.positions)
    np.testing.assert_array_equal(sim.velocities, last.velocities)
    final = json.loads((tmp_path / "cli" / "summary.json").read_text())["final"]
    columns = sim.columns()
    # columns() has no rates over an output interval (NaN): those need two observations.
    rates = {k for k, v in columns.items() if np.isnan(v)}
    assert rates == {"collision_frequency", "mean_free_time", "pressure", "wall_pressure"}
    for key, value in columns.items():
        if key not in rates:
            assert value == final[key], key


def test_python_m_granular_has_every_command() -> None:
    out = cli("--help").stdout
    for command in ["run", "check", "resume", "sweep", "plot", "compare", "reproduce", "bench"]:
        assert command in out
    bad = cli("frobnicate", check=False)
    assert bad.returncode == 2 and "frobnicate" in bad.stderr


def test_main_function_returns_the_exit_status(tmp_path: Path) -> None:
    assert granular.main(["check", str(tmp_path / "missing.toml")]) == 2
    path = tmp_path / "ok.toml"
    path.write_text(SCENARIOS["edmd3d"])
    assert granular.main(["check", str(path)]) == 0
