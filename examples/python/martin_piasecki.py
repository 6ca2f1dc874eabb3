"""The 1D Gillespie intruder in a Gaussian bath: its stationary temperature ratio T/T_B against the
Martin-Piasecki result (G-18) over the restitution coefficient, with batch-means error bars.

    python examples/python/martin_piasecki.py      # figure in docs/figures/python/
"""

import os
from pathlib import Path

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import granular  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
QUICK = os.environ.get("GRANULAR_EXAMPLE_QUICK") == "1"
FIGURES = Path(os.environ.get("GRANULAR_FIGURES", ROOT / "docs" / "figures" / "python"))

base = granular.Scenario.load(ROOT / "scenarios" / "intruder-1d.toml")
base.set("stop.collisions", 20000 if QUICK else 500000)
alphas = np.linspace(0.0, 1.0, 5 if QUICK else 11)
ratio, error = [], []
for alpha in alphas:
    sc = base.copy()
    sc.set("intruder.restitution", float(alpha))
    sim = granular.Simulation(sc)
    sim.run()
    cols = sim.columns()
    ratio.append(cols["temperature_ratio"])
    error.append(cols["temperature_ratio_error"])

fig, ax = plt.subplots(figsize=(6, 4))
fine = np.linspace(0, 1, 200)
ax.plot(fine, granular.theory.martin_piasecki_ratio(fine), "k-", label="Martin-Piasecki, G-18")
ax.errorbar(alphas, ratio, yerr=error, fmt="o", capsize=3, label="Gillespie intruder (M = m)")
ax.set_xlabel("restitution alpha")
ax.set_ylabel("T / T_B")
ax.set_title("1D intruder in a Gaussian bath")
ax.legend()
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "martin_piasecki.png", dpi=120)
z = (np.array(ratio) - granular.theory.martin_piasecki_ratio(alphas)) / np.array(error)
print("z-scores against G-18:", np.round(z, 2))
