"""granular: granular gases — many hard grains that collide and lose energy — simulated by a compiled
Rust core (event-driven molecular dynamics ``edmd``, DSMC ``dsmc``, Gillespie intruders ``intruder``)
and checked against exact theory.

The tour is ``docs/python.md``. In short::

    import granular
    sc = granular.Scenario.load("scenarios/maxwell-boltzmann.toml")
    sc.set("collisions.restitution", 0.9)        # like `granular run --set`
    sim = granular.Simulation(sc, seed=3)
    sim.advance(1.0)                             # interpreter lock released, Ctrl-C works
    v = sim.velocities                           # float64 (N, D), input order, a copy
    sim.observe()["temperature"]
    granular.theory.speed_density(v, temperature=1.0)

Names:

* :class:`Scenario` — a validated scenario (TOML file, text or dict, with ``--set`` overrides);
* :class:`Simulation` — a simulation in memory: ``advance``, ``run``, ``observe``, NumPy state;
* :func:`load_run`, :func:`load_sweep` — read run and sweep directories;
* :func:`run_sweep` — a scenario's ``[sweep]`` on all cores; :func:`run_shard`, :func:`merge_sweep`;
* :func:`report` — the self-contained HTML page of a run or sweep (``granular report``);
* :mod:`granular.theory` — the exact theory on NumPy arrays;
* :class:`ScenarioError`, :class:`SimulationError` — the exceptions, with the command line's messages;
* :func:`main` — the command line (``python -m granular ...`` is ``granular ...``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional, Union

from . import _core, theory
from ._core import Scenario, ScenarioError, Simulation, SimulationError
from .rundir import RunData, Snapshot, SweepData, load_run, load_sweep, read_table

__version__: str = _core.__version__

__all__ = [
    "Scenario",
    "Simulation",
    "ScenarioError",
    "SimulationError",
    "RunData",
    "Snapshot",
    "SweepData",
    "load_run",
    "load_sweep",
    "read_table",
    "run_sweep",
    "merge_sweep",
    "run_shard",
    "report",
    "theory",
    "main",
    "__version__",
]


def run_sweep(
    scenario: Union[Scenario, str, Path],
    out: Union[str, Path],
    threads: int = 0,
    frame: Optional[bool] = None,
    insist: bool = False,
) -> SweepData:
    """Runs a scenario's ``[sweep]`` (every point of its key or keys, several seeds each) on ``threads``
    worker threads (0: all cores) into the directory ``out``, exactly as ``granular sweep``, and returns it
    read by :func:`load_sweep`. Members already finished in ``out`` are kept. The interpreter lock is
    released while the members run. Raises ScenarioError or SimulationError; ScenarioError also when the
    scenario or a point of its sweep is above the pre-flight cost limits, unless ``insist=True``
    (``granular sweep --insist``)."""
    if not isinstance(scenario, Scenario):
        scenario = Scenario.load(scenario)
    _core.run_sweep(scenario, Path(out), threads, None, insist)
    return load_sweep(out, frame)


def run_shard(
    scenario: Union[Scenario, str, Path],
    out: Union[str, Path],
    shard: str,
    threads: int = 0,
    insist: bool = False,
) -> None:
    """Runs share ``shard = "I/N"`` of the members of a scenario's ``[sweep]`` into ``out``, as
    ``granular sweep --shard I/N`` does (member ``m``, numbered point by point, seed by seed, belongs to
    shard ``m mod N + 1``); :func:`merge_sweep` builds the table once every shard has finished. Raises
    ValueError for a bad ``shard``, ScenarioError or SimulationError; ``insist=True`` lifts the pre-flight
    cost limits as in :func:`run_sweep`."""
    if not isinstance(scenario, Scenario):
        scenario = Scenario.load(scenario)
    _core.run_sweep(scenario, Path(out), threads, shard, insist)


def merge_sweep(out: Union[str, Path], allow_missing: bool = False, frame: Optional[bool] = None) -> SweepData:
    """Builds ``sweep.csv`` and ``sweep.json`` of the sweep directory ``out`` from its finished members, as
    ``granular merge`` does, and returns it read by :func:`load_sweep`. Members that have not finished raise
    SimulationError naming them, unless ``allow_missing`` (then they are listed in ``SweepData.missing``)."""
    _core.merge_sweep(Path(out), allow_missing)
    return load_sweep(out, frame)


def report(run_dir: Union[str, Path]) -> Path:
    """Writes the self-contained HTML report of a finished run or sweep directory, exactly as
    ``granular report run_dir`` (which also prints the pages it wrote), and returns the path of its page
    ``run_dir/report.html``. Raises SimulationError when the report cannot be written (the command
    line's message is on stderr)."""
    status = main(["report", str(run_dir)])
    if status != 0:
        raise SimulationError(f"granular report {run_dir} failed (exit status {status}); its message is above")
    return Path(run_dir) / "report.html"


def main(argv: Optional[list[str]] = None) -> int:
    """Runs the command line with ``argv`` (default: ``sys.argv[1:]``), as the ``granular`` binary does,
    and returns its exit status (0 on success, 2 on an error, whose message goes to stderr)."""
    import sys

    args = list(sys.argv[1:] if argv is None else argv)
    return int(_core.cli_main(["granular", *args]))
