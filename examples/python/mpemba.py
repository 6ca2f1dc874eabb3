"""The Mpemba effect of a granular gas heated by white noise (Lasanta, Vega Reyes, Prados and Santos,
Phys. Rev. Lett. 119, 148001 (2017)): two samples of the same gas under the same noise, whose steady
temperature is a tenth of theirs, start from velocities built with NumPy. Sample A is 5 % hotter and
has a positive Sonine coefficient a2 (a mixture of two Maxwellians), sample B a negative one (part of
its grains at one speed). A's larger a2 makes it cool faster (zeta ~ 1 + 3 a2/16, KT-8): it crosses
B and stays colder. The lines are the first Sonine relaxation of granular.theory (KT-14, KT-15),
integrated from each sample's measured initial T and a2. DSMC, 2D, restitution 0.3.

    python examples/python/mpemba.py      # figure in docs/figures/python/
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

N = 5_000 if QUICK else 200_000
E, PHI = 0.3, 0.01
rng = np.random.default_rng(2017)


def velocities(temperature: float, a2: float) -> np.ndarray:
    """(N, 2) velocities at `temperature` (m = 1) with Sonine coefficient about `a2`, zero momentum."""
    g = rng.standard_normal((N, 2))
    if a2 >= 0:
        # Two Maxwellians at T (1 +- sqrt(a2)): a2 = (sqrt(a2))^2.
        scale = np.where(rng.random(N) < 0.5, 1 + np.sqrt(a2), 1 - np.sqrt(a2))
        v = g * np.sqrt(scale)[:, None]
    else:
        # A fraction -2 a2 of grains at the speed sqrt(2) (a2 = -1/2 in 2D), the rest Maxwellian.
        one_speed = rng.random(N) < -2 * a2
        phi = rng.random(N) * 2 * np.pi
        ring = np.sqrt(2) * np.column_stack([np.cos(phi), np.sin(phi)])
        v = np.where(one_speed[:, None], ring, g)
    v -= v.mean(axis=0)
    return v * np.sqrt(temperature / (0.5 * (v**2).sum(axis=1).mean()))


sc = granular.Scenario.from_toml(f"""
engine = "dsmc"
dimension = 2
seed = 5
box = {{ boundary = "periodic" }}
[[species]]
name = "grain"
count = {N}
packing_fraction = {PHI}
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[collisions]
restitution = {E}
[driving]
kind = "white_noise"
strength = 1.0
[stop]
time = 100.0
[output]
interval = 10.0
""")
radius = float(granular.Simulation(sc).radii[0])
gas = dict(restitution=E, number_density=float(N), radius=radius, particles=N)
omega = float(theory.collision_frequency(float(N), radius, 1.0))  # at T = 1
strength = float(theory.white_noise_strength(0.1, **gas))
sc.set("driving.strength", strength)
sc.set("dsmc.time_step", 0.01 / omega)
sc.set("dsmc.cell_size", 0.02 if not QUICK else 0.05)

positions = rng.random((N, 2))
times = np.linspace(0.0, 4.0, 41) / omega  # four mean free times at T = 1
measured, predicted = {}, {}
for name, t0, a20 in [("A", 1.05, 0.3), ("B", 1.0, -0.3)]:
    sim = granular.Simulation(sc)
    sim.set_state(positions=positions, velocities=velocities(t0, a20))
    start = sim.observe()
    temps = []
    for t in times:
        sim.advance(float(t))
        temps.append(sim.observe()["temperature"])
    measured[name] = np.array(temps)
    predicted[name] = theory.sonine_relaxation(times, start["temperature"], start["a2"], strength, **gas)[0]
    print(f"sample {name}: T(0) = {start['temperature']:.4f}, a2(0) = {start['a2']:+.3f}")

fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 6), sharex=True)
x = times * omega
for name, style in [("A", "o"), ("B", "s")]:
    top.plot(x, measured[name], style, mfc="none", ms=4, label=f"DSMC, sample {name}")
    top.plot(x, predicted[name], "-", color=top.lines[-1].get_color(), label=f"Sonine theory, {name}")
top.set_ylabel("temperature T (energy units)")
top.set_title(f"Mpemba effect, white noise, 2D DSMC, N = {N}, e = {E}")
top.legend()
diff = measured["A"] / measured["B"] - 1
bottom.plot(x, diff, "o", mfc="none", ms=4, label="DSMC")
bottom.plot(x, predicted["A"] / predicted["B"] - 1, "k-", label="first Sonine relaxation (KT-14, KT-15)")
bottom.axhline(0.0, color="grey", lw=0.8)
bottom.set_xlabel("time t (mean free times at T = 1)")
bottom.set_ylabel("T_A / T_B - 1 (dimensionless)")
bottom.legend()
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "mpemba.png", dpi=120)
late = diff[x >= 2.5].mean()
print(f"late T_A/T_B - 1: DSMC {late:+.4f}, theory {(predicted['A'] / predicted['B'] - 1)[x >= 2.5].mean():+.4f}")
if not QUICK:
    assert diff[0] > 0.04 and late < -0.01, "the hotter sample A ends colder than B"
