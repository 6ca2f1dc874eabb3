"""A parameter scan with the results in a pandas DataFrame: the granular temperature reached after a fixed time
against the restitution coefficient, run as a [sweep] on all cores (granular.run_sweep) and read back with
load_sweep, compared with Haff's law at that time.

    python examples/python/parameter_scan.py      # figure in docs/figures/python/
"""

import os
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

import granular  # noqa: E402
from granular import theory  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
QUICK = os.environ.get("GRANULAR_EXAMPLE_QUICK") == "1"
FIGURES = Path(os.environ.get("GRANULAR_FIGURES", ROOT / "docs" / "figures" / "python"))

N, PHI, TIME = (1000 if QUICK else 5000), 0.05, 0.05
values = [0.5, 0.7, 0.9] if QUICK else [0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95]
scenario = granular.Scenario.from_dict(
    {
        "engine": "edmd",
        "dimension": 2,
        "seed": 3,
        "box": {"lengths": [1.0, 1.0], "boundary": "periodic"},
        "species": [
            {
                "name": "disk",
                "count": N,
                "packing_fraction": PHI,
                "velocity": {"distribution": "maxwell_boltzmann", "temperature": 1.0},
            }
        ],
        "initial": {"zero_momentum": True},
        "stop": {"time": TIME},
        "output": {"interval": TIME / 5},
        "sweep": {
            "key": "collisions.restitution",
            "values": values,
            "seeds": 2 if QUICK else 4,
            "observable": "temperature",
        },
    }
)
with tempfile.TemporaryDirectory() as out:
    sweep = granular.run_sweep(scenario, Path(out) / "scan")  # all cores
    table: pd.DataFrame = sweep.table
    # One row per value; add the theory to the DataFrame.
    radius = granular.Simulation(scenario).radii[0]
    t0 = theory.haff_time(N, radius, 1.0, table["collisions.restitution"].to_numpy(), chi=theory.contact_value(PHI))
    table["haff_temperature"] = theory.haff_temperature(TIME, 1.0, t0)
print(table[["collisions.restitution", "members", "temperature_mean", "temperature_stderr", "haff_temperature"]].to_string())

fig, ax = plt.subplots(figsize=(6, 4))
ax.errorbar(table["collisions.restitution"], table["temperature_mean"], yerr=table["temperature_stderr"], fmt="o", capsize=3,
            label=f"EDMD sweep, N = {N}, {int(table['members'][0])} seeds per point")
fine = np.linspace(min(values), max(values), 100)
ax.plot(fine, theory.haff_temperature(TIME, 1.0, theory.haff_time(N, radius, 1.0, fine, chi=theory.contact_value(PHI))),
        "k-", label="Haff's law (Enskog, Sonine t0)")
ax.set_xlabel("restitution e")
ax.set_ylabel(f"temperature at t = {TIME}")
ax.set_title("Parameter scan into a DataFrame")
ax.legend()
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "parameter_scan.png", dpi=120)
