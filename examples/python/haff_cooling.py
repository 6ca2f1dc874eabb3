"""Homogeneous cooling: the DSMC and event-driven engines on one plot with Haff's law (DSMC-3), the cooling time
t0 from granular.theory with the first Sonine correction and the Enskog contact value.

    python examples/python/haff_cooling.py      # figure in docs/figures/python/
"""

import os
from pathlib import Path

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import granular  # noqa: E402
from granular import theory  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
QUICK = os.environ.get("GRANULAR_EXAMPLE_QUICK") == "1"
FIGURES = Path(os.environ.get("GRANULAR_FIGURES", ROOT / "docs" / "figures" / "python"))

N = 2000 if QUICK else 20000
PHI, E, T0 = 0.05, 0.9, 1.0

base = granular.Scenario.load(ROOT / "scenarios" / "dsmc-cooling.toml")
base.update({"species[0].count": N, "species[0].packing_fraction": PHI, "collisions.restitution": E})
sim0 = granular.Simulation(base)
radius = float(sim0.radii[0])
density = N / 1.0  # unit box
chi = theory.contact_value(PHI)
t0_enskog = theory.haff_time(density, radius, T0, E, chi=chi)
t0_boltzmann = theory.haff_time(density, radius, T0, E)

times = np.linspace(0.0, 3.0 * t0_enskog, 7 if QUICK else 31)
curves = {}
for engine in ["dsmc", "edmd"]:
    sc = base.copy()
    sc.set("engine", engine)
    sim = granular.Simulation(sc)
    k0 = sim.observe()["kinetic_energy"]
    k = []
    for t in times:
        sim.advance(float(t))
        k.append(sim.observe()["kinetic_energy"] / k0)
    curves[engine] = np.array(k)

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(times, curves["edmd"], "o", label="event-driven MD")
ax.plot(times, curves["dsmc"], "s", mfc="none", label="DSMC (Boltzmann, no Enskog factor)")
fine = np.linspace(0, times[-1], 200)
ax.plot(fine, theory.haff_energy(fine, 1.0, t0_enskog), "k-", label=f"Haff, Enskog t0 = {t0_enskog:.3g}")
ax.plot(fine, theory.haff_energy(fine, 1.0, t0_boltzmann), "k--", label=f"Haff, Boltzmann t0 = {t0_boltzmann:.3g}")
ax.set_xlabel("time t")
ax.set_ylabel("K(t) / K(0)")
ax.set_title(f"Homogeneous cooling, N = {N}, phi = {PHI}, e = {E}")
ax.legend()
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "haff_cooling.png", dpi=120)
print(f"K(3 t0)/K0: edmd {curves['edmd'][-1]:.4f}, dsmc {curves['dsmc'][-1]:.4f}, Haff 0.0625")
