"""The Kovacs memory effect of a granular gas heated by white noise (Prados and Trizac, Phys. Rev. Lett.
112, 198001 (2014)): the gas, steady under the noise strength xi1 (T = 1), is cooled under a weak
strength xi0 until its temperature reaches the steady value T2 = 0.3 of an intermediate strength xi2,
which is then switched on (`Simulation.set` in flight). Although already at its new steady
temperature, the gas leaves it and comes back: its velocity distribution (a2) remembers the cooling.
With restitution 0.3 the theory's hump is "anomalous" (downwards) and small, a few tenths of a
percent. The temperatures are shown relative to the DSMC's own steady temperature under xi2 (a
second run, held there), which differs from KT-13 by the DSMC step's bias and the Sonine
truncation; the band is one standard deviation of that steady temperature's fluctuations. The line
is the first Sonine relaxation of granular.theory (KT-14, KT-15) from the a2 measured at the switch
(at the theory's own steady temperature); the dashed line the same theory for the whole protocol
from the steady state. DSMC, 2D.

    python examples/python/kovacs.py      # figure in docs/figures/python/ (a few minutes)
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

N = 5_000 if QUICK else 400_000
E, PHI = 0.3, 0.01
T1, T2, T0 = 1.0, 0.3, 0.05

sc = granular.Scenario.from_toml(f"""
engine = "dsmc"
dimension = 2
seed = 14
box = {{ boundary = "periodic" }}
[[species]]
name = "grain"
count = {N}
packing_fraction = {PHI}
velocity = {{ distribution = "maxwell_boltzmann", temperature = {T1} }}
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
xi1, xi2, xi0 = (float(theory.white_noise_strength(t, **gas)) for t in (T1, T2, T0))
sc.set("driving.strength", xi1)
sc.set("dsmc.time_step", 0.01 / omega)
sc.set("dsmc.cell_size", 0.02 if not QUICK else 0.05)

# The DSMC's own steady temperature under xi2: a second gas started at T2 and held there.
held = sc.copy()
held.set("driving.strength", xi2)
held.set("species[0].velocity.temperature", T2)
ref_sim = granular.Simulation(held)
ref_sim.advance(8.0 / omega)
ref = []
for k in range(1, 81):
    ref_sim.advance((8.0 + 0.1 * k) / omega)
    ref.append(ref_sim.observe()["temperature"])
T_ref, T_sd = float(np.mean(ref)), float(np.std(ref))
print(f"steady under xi2 (DSMC): T = {T_ref:.5f} +- {T_sd:.5f} (single values), KT-13: {T2}")

sim = granular.Simulation(sc)
relax = 8.0 / omega  # eight mean free times: T and a2 at the steady state of xi1
sim.advance(relax)
steady = sim.observe()
sim.set("driving.strength", xi0)
# Cool under xi0 until T reaches T2, in steps of a thousandth of the mean free time.
t = relax
while sim.observe()["temperature"] > T_ref:
    t += 0.001 / omega
    sim.advance(t)
sim.set("driving.strength", xi2)
switch = sim.observe()
t_w = t
print(f"steady under xi1: T = {steady['temperature']:.4f}, a2 = {steady['a2']:+.4f}")
print(f"switch after {(t_w - relax) * omega:.3f} mean free times: T = {switch['temperature']:.4f}, "
      f"a2 = {switch['a2']:+.4f}")

after = np.linspace(0.0, 8.0, 81) / omega
temps = []
for dt in after:
    sim.advance(t_w + float(dt))
    temps.append(sim.observe()["temperature"])
measured = np.array(temps) / T_ref - 1
# The theory from its own steady temperature under xi2 with the a2 measured at the switch, relative
# to that temperature (the DSMC curve is relative to its own).
theory_end = float(theory.sonine_relaxation([200.0 / omega], T2, 0.0, xi2, **gas)[0][0])
from_switch = theory.sonine_relaxation(after, theory_end, switch["a2"], xi2, **gas)[0] / theory_end - 1

# The whole protocol in the theory alone: steady state of xi1, cooling under xi0 to T2, then xi2.
fine = np.linspace(0.0, 20.0, 4001) / omega
a2_steady = float(theory.sonine_relaxation([200.0 / omega], T1, 0.0, xi1, **gas)[1][0])
cooling, _ = theory.sonine_relaxation(fine, T1, a2_steady, xi0, **gas)
t_w_theory = float(fine[np.argmax(cooling <= T2)])
protocol = [(0.0, xi0), (t_w_theory, xi2)]
ideal, _ = theory.sonine_relaxation(t_w_theory + after, T1, a2_steady, protocol, **gas)

fig, ax = plt.subplots(figsize=(6, 4))
x = after * omega
ax.fill_between(x, -T_sd / T_ref, T_sd / T_ref, color="0.9", label="DSMC steady fluctuations (1 sd)")
ax.plot(x, measured, "o", mfc="none", ms=4, label=f"DSMC, N = {N}")
ax.plot(x, from_switch, "k-", label="Sonine theory from the a2 measured at the switch")
ax.plot(x, ideal / theory_end - 1, "k--", label="Sonine theory of the whole protocol")
ax.axhline(0.0, color="grey", lw=0.8)
ax.set_xlabel("time since the switch to xi2 (mean free times at T = 1)")
ax.set_ylabel("T / T_steady(xi2) - 1 (dimensionless)")
ax.set_title(f"Kovacs protocol, 2D DSMC, e = {E}, T: {T1} -> {T2} (under T0 = {T0})", fontsize=10)
ax.legend(fontsize=8)
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "kovacs.png", dpi=120)
hump = ideal / theory_end - 1
print(f"hump of the theory: {hump.min():+.5f} at {x[np.argmin(hump)]:.1f} mean free times; "
      f"DSMC mean over 0.5-2 mean free times: {measured[(x >= 0.5) & (x <= 2.0)].mean():+.5f}")
