"""Problem 1 of the hard-disk assignment from Python: disks that all start with the same speed relax to the 2D
Maxwell-Boltzmann distribution (HD-12). The speeds of several snapshots are pooled into a histogram and drawn
against granular.theory.speed_density at the measured temperature.

    python examples/python/maxwell_boltzmann.py      # figure in docs/figures/python/
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

scenario = granular.Scenario.load(ROOT / "scenarios" / "maxwell-boltzmann.toml")
if QUICK:
    scenario.set("species[0].count", 2000)
sim = granular.Simulation(scenario, seed=1)
n = sim.particle_count

# Equilibrate for 10 collisions per grain, then pool the speeds of 20 snapshots taken one collision per grain
# apart (consecutive snapshots are then nearly independent).
speeds = []
initial = np.linalg.norm(sim.velocities, axis=1)
t, dt = 0.0, 0.002
while sim.observe()["collisions_per_particle"] < 10.0:
    t += dt
    sim.advance(t)
for _ in range(20):
    target = sim.observe()["collisions_per_particle"] + 1.0
    while sim.observe()["collisions_per_particle"] < target:
        t += dt
        sim.advance(t)
    speeds.append(np.linalg.norm(sim.velocities, axis=1))
v = np.concatenate(speeds)
temperature = sim.observe()["temperature"]

fig, ax = plt.subplots(figsize=(6, 4))
ax.hist(v, bins=60, density=True, alpha=0.6, label=f"EDMD, {n} disks, 20 snapshots")
grid = np.linspace(0, v.max(), 300)
ax.plot(grid, granular.theory.speed_density(grid, mass=1.0, temperature=temperature), "k-",
        label=f"Maxwell-Boltzmann, T = {temperature:.4f}")
ax.axvline(initial.mean(), color="C3", ls="--", label="initial speed (all grains)")
ax.set_xlabel("speed v")
ax.set_ylabel("probability density p(v)")
ax.set_title("Problem 1: relaxation to Maxwell-Boltzmann (HD-12)")
ax.legend()
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "maxwell_boltzmann.png", dpi=120)

# A number to check: the mean speed against sqrt(pi T / 2m).
print(f"<v> = {v.mean():.4f}, theory {granular.theory.mean_speed(1.0, temperature):.4f}")
