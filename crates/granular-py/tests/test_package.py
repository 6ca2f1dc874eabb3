"""The package as a whole: the stubs type-check (mypy), every public name has a docstring, the examples run."""

from __future__ import annotations

import inspect
import os
import subprocess
import sys
from pathlib import Path

import pytest

import granular
from conftest import ROOT

USES_THE_API = '''
from pathlib import Path
import numpy as np
import numpy.typing as npt
import granular
from granular import theory

sc: granular.Scenario = granular.Scenario.from_toml("engine = 'edmd'")
sc.set("collisions.restitution", 0.9)
sc.update({"seed": 3})
text: str = sc.to_toml()
d: dict = sc.to_dict()
n: int = sc.particle_count
sim = granular.Simulation(sc, seed=2)
sim.advance(1.0)
reason = sim.run()
x: npt.NDArray[np.float64] = sim.positions
s: npt.NDArray[np.uint32] = sim.species
t: float = sim.time
e: int = sim.events
obs: dict = sim.observe()
run: granular.RunData = granular.load_run(Path("runs/x"))
snap: granular.Snapshot = run.snapshot(0)
sweep: granular.SweepData = granular.run_sweep(sc, "out", threads=2)
y = theory.speed_density(np.linspace(0, 3, 10), temperature=2.0)
z = theory.haff_time(1000.0, 0.01, 1.0, 0.9)
code: int = granular.main(["--help"])
try:
    pass
except granular.ScenarioError as err:
    key: str = err.key
    line: int | None = err.line
'''

MISUSES_THE_API = '''
import granular
sim = granular.Simulation(granular.Scenario.from_toml(""), seed="three")
sim.advance("later")
n: str = sim.particle_count
'''


def _mypy(tmp_path: Path, code: str) -> subprocess.CompletedProcess[str]:
    f = tmp_path / "use.py"
    f.write_text(code)
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--allow-untyped-globals", "--disable-error-code",
         "type-arg", str(f)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=600,
    )


def test_stubs_type_check(tmp_path: Path) -> None:
    good = _mypy(tmp_path, USES_THE_API)
    assert good.returncode == 0, good.stdout + good.stderr
    bad = _mypy(tmp_path, MISUSES_THE_API)
    assert bad.returncode == 1
    assert bad.stdout.count("error:") == 3, bad.stdout


def test_package_sources_type_check() -> None:
    package = ROOT / "crates" / "granular-py" / "python" / "granular"
    result = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", str(package)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr


def _public(obj: object) -> list[tuple[str, object]]:
    """The public members a class defines itself (not those it inherits, e.g. from Exception)."""
    return [(n, getattr(obj, n)) for n in vars(obj) if not n.startswith("_")]


def test_every_public_name_has_a_docstring() -> None:
    missing = []
    for name in granular.__all__:
        obj = getattr(granular, name)
        if name != "__version__" and not inspect.getdoc(obj):
            missing.append(name)
        if inspect.isclass(obj):
            for member, value in _public(obj):
                if callable(value) or isinstance(value, property) or inspect.isgetsetdescriptor(value):
                    if not (getattr(value, "__doc__", None) or "").strip():
                        missing.append(f"{name}.{member}")
    for name in granular.theory.__all__:
        if not inspect.getdoc(getattr(granular.theory, name)):
            missing.append(f"theory.{name}")
    assert not missing, missing


EXAMPLES = sorted((ROOT / "examples" / "python").glob("*.py"))


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs(script: Path, tmp_path: Path) -> None:
    env = dict(os.environ, MPLBACKEND="Agg", GRANULAR_EXAMPLE_QUICK="1", GRANULAR_FIGURES=str(tmp_path))
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, cwd=tmp_path,
                            timeout=600)
    assert result.returncode == 0, result.stderr
    assert list(tmp_path.glob("*.png")), "the example saved no figure"


def test_there_are_examples() -> None:
    assert {p.stem for p in EXAMPLES} >= {"maxwell_boltzmann", "haff_cooling", "martin_piasecki", "parameter_scan"}
