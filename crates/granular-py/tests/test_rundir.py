"""load_run / load_sweep / run_sweep: run and sweep directories read in pure Python."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import granular
from conftest import DSMC_2D, EDMD_2D, INTRUDER_1D, cli


@pytest.fixture(scope="module")
def edmd_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("edmd") / "run"
    granular.Simulation(granular.Scenario.from_toml(EDMD_2D)).run(out=out)
    return out


def test_load_run_tables_and_summary(edmd_run: Path) -> None:
    run = granular.load_run(edmd_run)
    assert run.summary is not None and run.summary["engine"] == "edmd"
    ts = run.timeseries
    assert isinstance(ts, pd.DataFrame)
    assert list(ts.columns)[:3] == ["time", "kinetic_energy", "temperature"]
    assert ts["time"].iloc[0] == 0.0
    assert ts["kinetic_energy"].iloc[-1] == run.summary["final"]["kinetic_energy"]
    assert ts["time"].dtype == np.float64
    assert "speed" in run.histograms and "impact_parameter" in run.histograms
    assert run.histograms["speed"]["species"].iloc[0] in {"small", "big"}
    assert run.scenario() == granular.Scenario.from_toml(run.scenario_toml or "")


def test_load_run_without_pandas(edmd_run: Path) -> None:
    run = granular.load_run(edmd_run, frame=False)
    ts = run.timeseries
    assert isinstance(ts, np.ndarray) and ts.dtype.names is not None
    assert ts.dtype["time"] == np.float64
    assert ts["time"][0] == 0.0
    assert run.histograms["speed"]["species"].dtype.kind == "U"
    table = granular.read_table(edmd_run / "timeseries.csv", frame=False)
    np.testing.assert_array_equal(table["kinetic_energy"], ts["kinetic_energy"])


def test_snapshots(edmd_run: Path) -> None:
    run = granular.load_run(edmd_run)
    assert len(run.snapshot_paths) >= 2
    first = run.snapshot(0)
    assert first.time == 0.0
    assert first.positions.shape == (400, 2) and first.positions.dtype == np.float64
    assert first.species.dtype == np.uint32 and first.species_names == ["small", "big"]
    sim = granular.Simulation(granular.Scenario.from_toml(EDMD_2D))
    np.testing.assert_array_equal(first.positions, sim.positions)
    np.testing.assert_array_equal(first.velocities, sim.velocities)
    times = [s.time for s in run.snapshots()]
    assert times == sorted(times) and run.snapshot().time == times[-1]


def test_intruder_run(tmp_path: Path) -> None:
    granular.Simulation(granular.Scenario.from_toml(INTRUDER_1D)).run(out=tmp_path / "i")
    run = granular.load_run(tmp_path / "i")
    assert run.summary is not None and run.summary["intruder"]["model"] == "1d"
    assert "intruder" in run.histograms and "intruder_histograms" in run.arrays
    assert "velocity_edges" in run.arrays["intruder_histograms"]
    with pytest.raises(IndexError, match="no snapshots"):
        run.snapshot()


def test_opt_in_arrays(tmp_path: Path) -> None:
    sc = granular.Scenario.from_toml(DSMC_2D)
    sc.update({"output.structure_factor": True, "output.impact_histograms": True, "stop.collisions_per_particle": 2})
    granular.Simulation(sc).run(out=tmp_path / "d")
    run = granular.load_run(tmp_path / "d")
    s = run.arrays["structure_factor"]
    assert s["s"].shape == (s["times"].shape[0], s["k"].shape[0])
    assert "impact_histograms" in run.arrays


def test_load_errors(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        granular.load_run(tmp_path / "nothing")
    with pytest.raises(FileNotFoundError, match="load_sweep"):
        granular.load_run(tmp_path)
    with pytest.raises(FileNotFoundError, match="sweep.csv"):
        granular.load_sweep(tmp_path)


def test_run_sweep_equals_cli_sweep(tmp_path: Path) -> None:
    text = EDMD_2D.replace("collisions_per_particle = 20.0", "collisions_per_particle = 2.0") + (
        '\n[sweep]\nkey = "collisions.restitution"\nvalues = [0.7, 0.9]\nseeds = 2\nobservable = "temperature"\n'
    )
    path = tmp_path / "sweep.toml"
    path.write_text(text)
    sweep = granular.run_sweep(granular.Scenario.load(path), tmp_path / "py", threads=2)
    cli("sweep", str(path), "--out", str(tmp_path / "cli"), "--threads", "1")
    assert (tmp_path / "py" / "sweep.csv").read_bytes() == (tmp_path / "cli" / "sweep.csv").read_bytes()
    assert sweep.key == "collisions.restitution" and sweep.keys == ["collisions.restitution"]
    assert list(sweep.table["collisions.restitution"]) == [0.7, 0.9]
    assert list(sweep.table["members"]) == [2.0, 2.0]
    assert len(sweep.members) == 2 and len(sweep.members[0]) == 2
    member = sweep.member(1, 0)
    assert member.summary is not None
    assert sweep.summaries()[1][0] == member.summary
    # Lower restitution, colder gas.
    t = sweep.table["temperature_mean"]
    assert t.iloc[0] < t.iloc[1]
    with pytest.raises(granular.SimulationError, match="no \\[sweep\\] table"):
        granular.run_sweep(granular.Scenario.from_toml(EDMD_2D), tmp_path / "none")


GRID = """
[sweep]
seeds = 2
observable = "temperature"
[[sweep.vary]]
key = "collisions.restitution"
values = [0.6, 0.95]
[[sweep.vary]]
key = "species[1].mass"
values = [2.0, 4.0, 8.0]
"""


def _grid(tmp_path: Path) -> granular.Scenario:
    text = EDMD_2D.replace("collisions_per_particle = 20.0", "collisions_per_particle = 1.0") + GRID
    return granular.Scenario.from_toml(text)


def test_multi_key_sweep_csv_reads_as_it_is(tmp_path: Path) -> None:
    sweep = granular.run_sweep(_grid(tmp_path), tmp_path / "grid", threads=2)
    assert sweep.keys == ["collisions.restitution", "species[1].mass"]
    assert sweep.meta["mode"] == "grid" and sweep.meta["seeds"] == 2 and sweep.missing == []
    assert sweep.meta["granular_version"] == granular.__version__
    assert [k["dimension"] for k in sweep.meta["keys"]] == ["1", "mass"]
    assert len(sweep.members) == 6 and sweep.member(5, 1).summary is not None
    path = tmp_path / "grid" / "sweep.csv"
    # pandas, as it is: one header row, a column per key.
    df = pd.read_csv(path)
    assert list(df.columns[:4]) == ["point", "collisions.restitution", "species[1].mass", "members"]
    assert list(df["collisions.restitution"]) == [0.6, 0.6, 0.6, 0.95, 0.95, 0.95]
    assert list(df["species[1].mass"]) == [2.0, 4.0, 8.0, 2.0, 4.0, 8.0]
    assert (df["members"] == 2).all()
    pd.testing.assert_frame_equal(df, sweep.table, check_dtype=False)
    # NumPy, as it is (genfromtxt drops '.', '[' and ']' from names unless deletechars="").
    a = np.genfromtxt(path, names=True, delimiter=",")
    assert a.shape == (6,) and list(a["collisionsrestitution"]) == list(df["collisions.restitution"])
    b = np.genfromtxt(path, names=True, delimiter=",", deletechars="")
    assert b.dtype.names is not None and b.dtype.names[:3] == ("point", "collisions.restitution", "species[1].mass")
    np.testing.assert_array_equal(b["temperature_mean"], df["temperature_mean"].to_numpy())
    # Lower restitution, colder gas, at every mass ratio.
    t = df["temperature_mean"].to_numpy()
    assert (t[:3] < t[3:]).all()


def test_shards_merge_to_the_whole_sweep(tmp_path: Path) -> None:
    sc = _grid(tmp_path)
    granular.run_sweep(sc, tmp_path / "all", threads=1)
    for i in (1, 2, 3):
        granular.run_shard(sc, tmp_path / "three", f"{i}/3", threads=1)
    assert not (tmp_path / "three" / "sweep.csv").exists()
    merged = granular.merge_sweep(tmp_path / "three")
    for f in ("sweep.csv", "sweep.json"):
        assert (tmp_path / "all" / f).read_bytes() == (tmp_path / "three" / f).read_bytes()
    assert merged.missing == []
    # A lone shard: the merge names the missing members, or lists them with allow_missing.
    granular.run_shard(sc, tmp_path / "one", "2/4", threads=1)
    with pytest.raises(granular.SimulationError, match="point_000/seed_000 \\(not started\\)"):
        granular.merge_sweep(tmp_path / "one")
    part = granular.merge_sweep(tmp_path / "one", allow_missing=True)
    assert len(part.missing) == 9 and list(part.table["members"]) == [1, 0, 1, 0, 1, 0]
    for bad in ("0/3", "4/3", "a/b"):
        with pytest.raises(ValueError, match="shard"):
            granular.run_shard(sc, tmp_path / "bad", bad)


def test_output_md_snapshot_snippet_runs(edmd_run: Path, root: Path) -> None:
    """The snapshot snippet of docs/output.md runs as written on a real run directory (it
    once called ``json.loads`` on the species names, which are a string array)."""
    text = (root / "docs" / "output.md").read_text()
    blocks = [b.split("```", 1)[0] for b in text.split("```python\n")[1:]]
    snippet = next(b for b in blocks if "species_names" in b)
    first = sorted((edmd_run / "snapshots").glob("*.npz"))[0]
    snippet = snippet.replace("runs/maxwell-boltzmann/snapshots/snapshot_000000.npz", str(first))
    namespace: dict[str, object] = {}
    exec(compile(snippet, "docs/output.md", "exec"), namespace)
    assert namespace["names"] == ["small", "big"]
