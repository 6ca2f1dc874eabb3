"""The Kovacs memory effect of a granular gas heated by white noise (Prados and Trizac, Phys. Rev. Lett.
112, 198001 (2014)): the gas, steady under the noise strength xi1 (T = 1), is cooled under a weak
strength xi0 until its temperature reaches the steady value T_s of an intermediate strength xi2 (that
of T = 0.3), which is then switched on (`Simulation.set` in flight). Although already at its new
steady temperature, the gas leaves it and comes back: its velocity distribution (a2, raised by the
cooling) remembers the protocol. With restitution 0.3 the hump is "anomalous" (downwards) and small,
a few tenths of a percent, against fluctuations of T of 0.3 % for 10^5 grains: the example averages
many protocols, each started from a state of one steady run (`Simulation.from_snapshot` with its own
seed).

The gas is homogeneous as in the theory: one DSMC cell holds the whole box (the homogeneous
Boltzmann equation). T_s is the DSMC's own steady temperature under xi2 (a held run); the lines are
the first Sonine relaxation of granular.theory (KT-14, KT-15): from each protocol's measured switch
state (solid), and of the whole protocol from the steady state (dashed). DSMC, 2D. The library test
`memory_effects::the_temperature_leaves_its_steady_value_and_comes_back` is the same measurement.

    python examples/python/kovacs.py      # figure in docs/figures/python/ (about 4 minutes)
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

N = 5_000 if QUICK else 100_000
PROTOCOLS = 4 if QUICK else 120
HELD = 40.0 if QUICK else 1600.0  # mean free times (at T = 1) of the held run
E = 0.3
T1, T2, T0 = 1.0, 0.3, 0.05


def scenario(seed: int, temperature: float = T1) -> granular.Scenario:
    return granular.Scenario.from_toml(f"""
engine = "dsmc"
dimension = 2
seed = {seed}
box = {{ boundary = "periodic" }}
[[species]]
name = "grain"
count = {N}
packing_fraction = 0.01
velocity = {{ distribution = "maxwell_boltzmann", temperature = {temperature} }}
[collisions]
restitution = {E}
[driving]
kind = "white_noise"
strength = 1.0
[dsmc]
cell_size = 1.0
[stop]
time = 1e4
""")


radius = float(granular.Simulation(scenario(1)).radii[0])
gas = dict(restitution=E, number_density=float(N), radius=radius, particles=N)
omega = float(theory.collision_frequency(float(N), radius, 1.0))  # at T = 1
xi1, xi2, xi0 = (float(theory.white_noise_strength(t, **gas)) for t in (T1, T2, T0))
step = 0.1 / omega  # the DSMC step: a tenth of the mean free time at T = 1


def with_noise(sc: granular.Scenario, xi: float) -> granular.Scenario:
    sc.set("driving.strength", xi)
    sc.set("dsmc.time_step", step)
    return sc


# The DSMC's own steady temperature under xi2: a gas started at T2 and held there.
held = granular.Simulation(with_noise(scenario(2, T2), xi2))
held.advance(8.0 / omega)
series = []
for k in range(1, int(10 * HELD) + 1):
    held.advance((8.0 + 0.1 * k) / omega)
    series.append(held.observe()["temperature"])
batches = np.array(series[: len(series) // 20 * 20]).reshape(20, -1).mean(axis=1)
T_s, T_s_se = float(batches.mean()), float(batches.std(ddof=1) / np.sqrt(20))
print(f"steady under xi2 (DSMC): T_s = {T_s:.5f} +- {T_s_se:.5f}, KT-13: {T2}")

after = np.linspace(0.0, 8.0, 81)  # mean free times at T = 1 after the switch
steady_run = granular.Simulation(with_noise(scenario(3), xi1))
steady_run.advance(8.0 / omega)
temps, a2s, switches = [], [], []
for k in range(PROTOCOLS):
    t0 = steady_run.time + 2.0 / omega
    steady_run.advance(t0)
    sim = granular.Simulation.from_snapshot(with_noise(scenario(1000 + k), xi0), steady_run.snapshot())
    # Cool under xi0 until T < T_s, in sixteenths of a step near it.
    t, temp, drop = t0, sim.observe()["temperature"], 0.0
    while temp > T_s:
        t += step / 16 if temp - T_s < 2 * drop else step
        sim.advance(t)
        now = sim.observe()["temperature"]
        drop, temp = max(drop, temp - now), now
    sim.set("driving.strength", xi2)
    o = sim.observe()
    switches.append((o["temperature"], o["a2"], (t - t0) * omega))
    row_t, row_a = [], []
    for dt in after:
        sim.advance(t + dt / omega)
        o = sim.observe()
        row_t.append(o["temperature"])
        row_a.append(o["a2"])
    temps.append(row_t)
    a2s.append(row_a)
temps, a2s, switches = np.array(temps), np.array(a2s), np.array(switches)

deviation = temps / T_s - 1
mean, se = deviation.mean(0), np.hypot(deviation.std(0, ddof=1) / np.sqrt(PROTOCOLS), T_s_se / T_s)
a2_mean, a2_se = a2s.mean(0), a2s.std(0, ddof=1) / np.sqrt(PROTOCOLS)

# The theory: its own steady state under xi2, then from each protocol's switch state (T / T_s, a2).
end_T, end_a2 = (float(x[0]) for x in theory.sonine_relaxation([400.0 / omega], T2, 0.0, xi2, **gas))
from_switch = [theory.sonine_relaxation(after / omega, end_T * T_sw / T_s, a2_sw, xi2, **gas)
               for T_sw, a2_sw, _ in switches]
th_dev = np.mean([T / end_T - 1 for T, _ in from_switch], axis=0)
th_a2 = np.mean([a for _, a in from_switch], axis=0)
# The whole protocol in the theory alone: steady state of xi1, cooling under xi0 to its T_s, then xi2.
fine = np.linspace(0.0, 20.0, 8001) / omega
a2_1 = float(theory.sonine_relaxation([400.0 / omega], T1, 0.0, xi1, **gas)[1][0])
cooling, _ = theory.sonine_relaxation(fine, T1, a2_1, xi0, **gas)
t_w = float(fine[np.argmax(cooling <= end_T)])
ideal_T, ideal_a2 = theory.sonine_relaxation(t_w + after / omega, T1, a2_1, [(0.0, xi0), (t_w, xi2)], **gas)

fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
ax.fill_between(after, mean - se, mean + se, color="C0", alpha=0.3, lw=0,
                label=f"DSMC, {PROTOCOLS} x {N} disks (mean ± 1 se)")
ax.plot(after, mean, "C0-", lw=1)
ax.plot(after, th_dev, "k-", label="Sonine theory from the measured switch states")
ax.plot(after, ideal_T / end_T - 1, "k--", label="Sonine theory of the whole protocol")
ax.axhline(0.0, color="grey", lw=0.8)
ax.set_xlabel("time since the switch to xi2 (mean free times at T = 1)")
ax.set_ylabel("T / T_s - 1 (dimensionless)")
ax.legend(fontsize=8)
bx.fill_between(after, a2_mean - a2_se, a2_mean + a2_se, color="C1", alpha=0.4, lw=0, label="DSMC")
bx.plot(after, th_a2, "k-", label="Sonine theory from the measured switch states")
bx.plot(after, ideal_a2, "k--", label="Sonine theory of the whole protocol")
bx.axhline(end_a2, color="grey", lw=0.8, label="steady a2 (theory)")
bx.set_xlabel("time since the switch to xi2 (mean free times at T = 1)")
bx.set_ylabel("a2 (dimensionless)")
bx.legend(fontsize=8)
fig.suptitle(f"Kovacs protocol, homogeneous 2D DSMC, e = {E}, T: {T1} -> {T2} (under T0 = {T0})",
             fontsize=10)
fig.tight_layout()
FIGURES.mkdir(parents=True, exist_ok=True)
fig.savefig(FIGURES / "kovacs.png", dpi=120)
window = (after >= 0.5) & (after <= 2.5)
w_dev = deviation[:, window].mean(1)
print(f"switch after {switches[:, 2].mean():.3f} mean free times (theory {t_w * omega:.3f}), "
      f"a2 = {switches[:, 1].mean():+.4f} (theory {float(ideal_a2[0]):+.4f})")
print(f"T/T_s - 1 over 0.5-2.5 mean free times: {w_dev.mean():+.5f} +- "
      f"{np.hypot(w_dev.std(ddof=1) / np.sqrt(PROTOCOLS), T_s_se / T_s):.5f}; theory from the switch "
      f"states {th_dev[window].mean():+.5f}, of the whole protocol {(ideal_T / end_T - 1)[window].mean():+.5f}")
