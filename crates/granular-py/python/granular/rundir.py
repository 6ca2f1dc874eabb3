"""Reading run and sweep directories (the files of ``granular run`` and ``granular sweep``, docs/output.md):
summaries as dicts, tables as pandas DataFrames when pandas is installed (NumPy structured arrays
otherwise), snapshots and histograms as NumPy arrays.

The files are named, listed and read by the compiled core (the library's run directory,
``granular::run::RunDir``); this module only shapes what it returns into Python objects."""

from __future__ import annotations

import importlib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Optional, Union

import numpy as np

from . import _core

__all__ = ["RunData", "SweepData", "load_run", "load_sweep", "read_table"]

#: A table: a pandas DataFrame when pandas is installed (and ``frame`` is not False), otherwise a NumPy
#: structured array with one named field per column.
Table = Any


def _pandas(frame: Optional[bool]) -> Any:
    """The pandas module when tables should be DataFrames, else None."""
    if frame is False:
        return None
    try:
        return importlib.import_module("pandas")
    except ImportError:
        if frame:
            raise ImportError("frame=True needs pandas: pip install pandas") from None
        return None


def read_table(path: Union[str, Path], frame: Optional[bool] = None) -> Table:
    """Reads one of the run directory's CSV files (``#`` comment lines skipped, header row first).

    Numeric columns become float64, others str. Returns a pandas DataFrame when pandas is installed
    (``frame=None``) or asked for (``frame=True``), a NumPy structured array with ``frame=False``.
    """
    header, cells = _core.read_table(Path(path))
    if not header:
        raise ValueError(f"{path}: the table is empty (no header row)")
    columns = {
        name: col if isinstance(col, np.ndarray) else np.array(col, dtype=str) for name, col in zip(header, cells)
    }
    rows = len(next(iter(columns.values())))
    pd = _pandas(frame)
    if pd is not None:
        return pd.DataFrame(columns)
    dtype = [(name, col.dtype) for name, col in columns.items()]
    out = np.empty(rows, dtype=dtype)
    for name, col in columns.items():
        out[name] = col
    return out


def _load_npz(path: Union[str, Path]) -> dict[str, np.ndarray]:
    return dict(_core.read_arrays(Path(path)))


@dataclass
class Snapshot:
    """One snapshot file: arrays in input order (grain ``i`` is the ``i``-th grain of the scenario).

    ``positions`` and ``velocities`` are float64 ``(N, D)``, ``radii`` and ``masses`` float64 ``(N,)``,
    ``species`` uint32 ``(N,)`` indices into ``species_names``; ``time`` the simulation time;
    ``angular_velocities`` (rough grains only, else None) float64 ``(N,)`` in 2D, ``(N, 3)`` in 3D.
    """

    time: float
    positions: np.ndarray
    velocities: np.ndarray
    radii: np.ndarray
    masses: np.ndarray
    species: np.ndarray
    species_names: list[str]
    angular_velocities: Optional[np.ndarray] = None
    arrays: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    @classmethod
    def load(cls, path: Union[str, Path]) -> "Snapshot":
        """Reads ``snapshot_NNNNNN.npz`` (checked: consistent shapes, a name for every species index)."""
        s = _core.read_snapshot(Path(path))
        names = list(s["species_names"])
        # The file's arrays, as it holds them.
        arrays = {
            "time": np.array(s["time"], dtype=np.float64),
            "dimension": np.array(s["dimension"], dtype=np.uint64),
            "positions": s["positions"],
            "velocities": s["velocities"],
            "radii": s["radii"],
            "masses": s["masses"],
            "species": s["species"],
            "species_names": np.array(names, dtype=str),
        }
        spins = s.get("angular_velocities")
        if spins is not None:
            arrays["angular_velocities"] = spins
        return cls(
            time=float(s["time"]),
            positions=s["positions"],
            velocities=s["velocities"],
            radii=s["radii"],
            masses=s["masses"],
            species=s["species"],
            species_names=names,
            angular_velocities=spins,
            arrays=arrays,
        )


@dataclass
class RunData:
    """A run directory, read: see :func:`load_run`."""

    #: The directory.
    path: Path
    #: ``summary.json`` as a dict (None while the run has not finished).
    summary: Optional[dict[str, Any]]
    #: ``timeseries.csv`` (one row per output time; see docs/output.md for the columns).
    timeseries: Table
    #: The CSV histograms present: ``speed``, ``velocity``, ``impact_parameter``, ``intruder``.
    histograms: dict[str, Table]
    #: The NumPy files present (``impact_histograms``, ``structure_factor``, ``density_maps``,
    #: ``intruder_histograms``), each a dict of arrays.
    arrays: dict[str, dict[str, np.ndarray]]
    #: ``scenario.toml`` (the resolved scenario), as text.
    scenario_toml: Optional[str]
    #: The snapshot files, in output order.
    snapshot_paths: list[Path]
    #: The opt-in correlation tables present (docs/output.md): ``pair_correlation`` (``r``,
    #: ``g.<a>.<b>``), ``mean_square_displacement`` (``lag``, ``origins``, ``msd.<s>``,
    #: ``msd_error.<s>``), ``velocity_autocorrelation`` (``lag``, ``origins``, ``vacf.<s>``, ...).
    correlations: dict[str, Table] = field(default_factory=dict)

    def snapshot(self, index: int = -1) -> Snapshot:
        """Snapshot number ``index`` in output order (default: the last), read from its file."""
        if not self.snapshot_paths:
            raise IndexError(f"{self.path}: the run has no snapshots (intruder runs write none)")
        return Snapshot.load(self.snapshot_paths[index])

    def snapshots(self) -> Iterator[Snapshot]:
        """Every snapshot in output order, read one at a time."""
        for p in self.snapshot_paths:
            yield Snapshot.load(p)

    @property
    def box(self) -> dict[str, Any]:
        """The run's box as a dict that freud (``freud.box.Box.from_box(run.box)``) and HOOMD-blue take:
        ``Lx``, ``Ly``, ``Lz`` (0 in 2D), ``xy``, ``xz``, ``yz`` (0), ``dimensions``. granular's box runs from 0 to
        L along each axis, freud's from -L/2 to L/2: shift the positions by L/2."""
        return dict(self.scenario().box)

    def scenario(self) -> Any:
        """The run's resolved scenario as a :class:`granular.Scenario`."""
        from . import Scenario

        if self.scenario_toml is None:
            raise FileNotFoundError(
                f"{self.path / _core.file_name('scenario')}: no scenario file in the run directory"
            )
        return Scenario.from_toml(self.scenario_toml)


def load_run(path: Union[str, Path], frame: Optional[bool] = None) -> RunData:
    """Reads a run directory written by ``granular run`` or ``Simulation.run(out=...)``.

    ``frame``: tables as pandas DataFrames (None: when pandas is installed) or NumPy structured arrays.
    Snapshots are not read until asked for (:meth:`RunData.snapshot`).
    """
    d = Path(path)
    if not d.is_dir():
        raise FileNotFoundError(f"{d}: no such run directory")
    files = _core.run_files(d)
    if files["timeseries"] is None:
        name = _core.file_name("timeseries")
        raise FileNotFoundError(f"{d / name}: not a run directory (no {name}); a sweep? use load_sweep")
    return RunData(
        path=d,
        summary=json.loads(_core.read_summary(d)) if files["summary"] is not None else None,
        timeseries=read_table(files["timeseries"], frame),
        histograms={k: read_table(f, frame) for k, f in files["histograms"].items()},
        arrays={k: _load_npz(f) for k, f in files["arrays"].items()},
        scenario_toml=Path(files["scenario"]).read_text() if files["scenario"] is not None else None,
        snapshot_paths=[Path(p) for p in files["snapshots"]],
        correlations={k: read_table(f, frame) for k, f in files["correlations"].items()},
    )


@dataclass
class SweepData:
    """A sweep directory, read: see :func:`load_sweep`."""

    #: The directory.
    path: Path
    #: The first swept key (the only one of a one-key sweep), e.g. ``collisions.restitution``.
    key: str
    #: Every swept key, in column order.
    keys: list[str]
    #: ``sweep.csv``: ``point``, one column per swept key (named by the key), ``members``, and
    #: ``<observable>_mean`` / ``<observable>_stderr`` for every scalar observable.
    table: Table
    #: Member directories ``[point][seed]`` (``point_PPP/seed_SSS``; those in :attr:`missing` have not
    #: finished).
    members: list[list[Path]]
    #: ``sweep.json``: scenario, seed, mode, keys with their values and dimensions, member seeds,
    #: observables, points, missing members, granular version (docs/output.md).
    meta: dict[str, Any] = field(default_factory=dict)
    #: Members without a finished run when the table was merged (``point_001/seed_002 (not started)``).
    missing: list[str] = field(default_factory=list)

    def member(self, point: int, seed: int = 0, frame: Optional[bool] = None) -> RunData:
        """The run directory of member ``(point, seed)``, read with :func:`load_run`."""
        return load_run(self.members[point][seed], frame)

    def summaries(self) -> list[list[dict[str, Any]]]:
        """``summary.json`` of every finished member, ``[point][seed]``."""
        summary = _core.file_name("summary")
        return [[json.loads(_core.read_summary(m)) for m in row if (m / summary).exists()] for row in self.members]


def load_sweep(path: Union[str, Path], frame: Optional[bool] = None) -> SweepData:
    """Reads a sweep directory written by ``granular sweep`` (or ``granular merge``) or
    :func:`granular.run_sweep`: ``sweep.csv`` as a table and its sidecar ``sweep.json``."""
    d = Path(path)
    table_name = _core.file_name("sweep_table")
    table_path = d / table_name
    if not table_path.exists():
        raise FileNotFoundError(
            f"{table_path}: not a finished sweep directory (no {table_name}; after sharded runs: granular merge {d})"
        )
    meta_path = d / _core.file_name("sweep_meta")
    if meta_path.exists():
        meta = json.loads(meta_path.read_text())
        keys = [k["key"] for k in meta["keys"]]
        members = [[d / _core.sweep_member(p["point"], s) for s in range(meta["seeds"])] for p in meta["points"]]
    else:  # an older sweep: the key in a comment line, members from the directory
        meta = {}
        first = table_path.read_text().splitlines()[0]
        m = re.match(r"#\s*sweep of\s+(.*)", first)
        keys = [m.group(1).strip()] if m else []
        points = sorted(p for p in d.glob("point_*") if p.is_dir())
        members = [sorted(s for s in p.glob("seed_*") if s.is_dir()) for p in points]
    return SweepData(
        path=d,
        key=keys[0] if keys else "",
        keys=keys,
        table=read_table(table_path, frame),
        members=members,
        meta=meta,
        missing=list(meta.get("missing", [])),
    )
