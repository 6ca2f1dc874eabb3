"""The pre-flight cost limits from Python: refused without ``insist``, with the command line's text;
lifted by ``insist=True`` (``--insist``) in ``Scenario.check``, ``Simulation(...)`` and the sweeps."""

from __future__ import annotations

from pathlib import Path

import pytest

import granular
from conftest import EDMD_2D, cli

# 400 disks written out every 1e-9 time units up to 20 collisions per grain: about 10^10 outputs, above the
# limit of 10^6 (`output.interval` is the key to change).
TOO_MANY_OUTPUTS = EDMD_2D.replace("interval = 0.05", "interval = 1e-9")

# A cooling gas of 200 disks with the TC model, stopped when half its energy is gone (a few collisions per
# grain), swept over `stop.time`. With the TC model the estimate does not use Haff's law and the energy rule
# gives no lower bound on the end time, so at `stop.time = 1e13` it expects about 10^16 collisions (above
# the limit of 10^12), although the energy rule ends the run early.
SWEEP_OVER_A_LIMIT = """
engine = "edmd"
dimension = 2
seed = 7
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "disk"
count = 200
radius = 0.01
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[collisions]
restitution = 0.8
contact_duration = 1e-6
[stop]
time = 10.0
energy_fraction = 0.5
[output]
interval = 0.01
[sweep]
key = "stop.time"
values = [10.0, 1e13]
seeds = 1
observable = "temperature"
"""


def test_a_scenario_above_a_limit_can_be_built_but_not_checked_or_simulated(tmp_path: Path) -> None:
    path = tmp_path / "many.toml"
    path.write_text(TOO_MANY_OUTPUTS)
    sc = granular.Scenario.load(path)
    for attempt in (sc.check, lambda: granular.Simulation(sc), lambda: granular.Simulation(path)):
        with pytest.raises(granular.ScenarioError) as info:
            attempt()
        assert info.value.key == "output.interval"
        assert "outputs" in info.value.reason and "--insist" in info.value.reason
    # The command line's text: `granular check` shows the same message as its headline.
    with pytest.raises(granular.ScenarioError) as info:
        sc.check()
    out = cli("check", str(path), check=False)
    assert out.returncode == 2
    assert " ".join(info.value.reason.split()[:12]) in " ".join(out.stderr.split())
    # Lifted by insist=True; a `set` that brings it back under the limits needs no insist.
    assert sc.check(insist=True) == "valid (400 grains, 2 species)"
    sim = granular.Simulation(sc, seed=3, insist=True)
    sim.advance(0.01)
    assert sim.time == 0.01
    sc.set("output.interval", 0.05)
    assert sc.check() == "valid (400 grains, 2 species)"
    assert granular.Simulation(sc).particle_count == 400


def test_sweep_point_above_a_limit_needs_insist(tmp_path: Path) -> None:
    sc = granular.Scenario.from_toml(SWEEP_OVER_A_LIMIT)
    for run in (
        lambda: granular.run_sweep(sc, tmp_path / "refused", threads=1),
        lambda: granular.run_shard(sc, tmp_path / "refused", "1/2", threads=1),
    ):
        with pytest.raises(granular.ScenarioError) as info:
            run()
        assert info.value.key == "sweep.values[1]"
        assert "stop.time = 10000000000000.0 gives an invalid scenario: `stop.time`" in str(info.value)
        assert "pair collisions" in str(info.value) and "--insist" in str(info.value)
    assert not (tmp_path / "refused" / "point_000").exists()
    sweep = granular.run_sweep(sc, tmp_path / "insisted", threads=1, frame=False, insist=True)
    assert list(sweep.table["members"]) == [1, 1]
    for point in (0, 1):
        assert sweep.member(point).summary["stop_reason"] == "energy_fraction"
    for shard in ("1/2", "2/2"):
        granular.run_shard(sc, tmp_path / "sharded", shard, threads=1, insist=True)
    merged = granular.merge_sweep(tmp_path / "sharded", frame=False)
    assert list(merged.table["members"]) == [1, 1]
    assert (tmp_path / "sharded" / "sweep.csv").read_bytes() == (tmp_path / "insisted" / "sweep.csv").read_bytes()
