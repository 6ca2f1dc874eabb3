"""Shared fixtures of the Python tests: small scenarios of every engine, the repository root, the
command line run through ``python -m granular``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

import granular  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]

EDMD_2D = """
engine = "edmd"
dimension = 2
seed = 5
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "small"
count = 300
radius = 0.005
mass = 1.0
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[[species]]
name = "big"
count = 100
radius = 0.01
mass = 4.0
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[collisions]
restitution = 0.95
[stop]
collisions_per_particle = 20.0
[output]
interval = 0.05
snapshot_every = 4
"""

EDMD_3D = """
engine = "edmd"
dimension = 3
seed = 2
[box]
lengths = [1.0, 1.0, 1.0]
boundary = "wall"
[[species]]
name = "ball"
count = 200
packing_fraction = 0.05
velocity = { distribution = "fixed_speed", speed = 1.0 }
[stop]
time = 0.2
[output]
interval = 0.05
"""

DSMC_2D = """
engine = "dsmc"
dimension = 2
seed = 7
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "grain"
count = 2000
packing_fraction = 0.05
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[initial]
zero_momentum = true
[collisions]
restitution = 0.9
[stop]
collisions_per_particle = 10.0
[output]
interval = 0.01
snapshot_every = 5
"""

INTRUDER_1D = """
engine = "intruder"
seed = 1
[intruder]
model = "1d"
mass = 1.0
bath_mass = 1.0
restitution = 0.5
bath_density = 1.0
bath = { kind = "gaussian", temperature = 0.5 }
[stop]
collisions = 20000
[output]
interval = 500.0
"""

INTRUDER_NEEDLE_PATH = ROOT / "scenarios" / "intruder-needle.toml"

SCENARIOS = {"edmd2d": EDMD_2D, "edmd3d": EDMD_3D, "dsmc2d": DSMC_2D, "intruder1d": INTRUDER_1D}


@pytest.fixture
def root() -> Path:
    """The repository root."""
    return ROOT


@pytest.fixture(params=sorted(SCENARIOS))
def any_scenario(request: pytest.FixtureRequest) -> granular.Scenario:
    """A small scenario of each engine."""
    return granular.Scenario.from_toml(SCENARIOS[request.param])


@pytest.fixture
def edmd2d() -> granular.Scenario:
    return granular.Scenario.from_toml(EDMD_2D)


@pytest.fixture
def dsmc2d() -> granular.Scenario:
    return granular.Scenario.from_toml(DSMC_2D)


@pytest.fixture
def intruder1d() -> granular.Scenario:
    return granular.Scenario.from_toml(INTRUDER_1D)


def cli(*args: str, cwd: Path | None = None, check: bool = True) -> subprocess.CompletedProcess[str]:
    """``python -m granular ARGS`` in a subprocess (the command line as a pip user has it)."""
    env = dict(os.environ, MPLBACKEND="Agg")
    result = subprocess.run(
        [sys.executable, "-m", "granular", *args], capture_output=True, text=True, cwd=cwd, env=env, timeout=600
    )
    if check and result.returncode != 0:
        raise AssertionError(f"granular {' '.join(args)} exited {result.returncode}:\n{result.stderr}")
    return result
