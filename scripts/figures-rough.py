#!/usr/bin/env python3
"""Figures of rough grains cooling freely (docs/rough.md, docs/figures/rough/): the bundled
scenarios rough-hcs-edmd (event-driven, 1000 grains) and rough-hcs-dsmc (DSMC, 10^4 grains) in
2D (disks) and 3D (spheres), T_t and T_r against the collisions per grain s, and their ratio,
beside the kinetic theory of the homogeneous cooling state.

With s as the clock the theory is a straight line: in the cooling state every temperature decays
as d ln T / ds = -zeta/nu (RS-5; granular.theory.rough_cooling_rate), and the ratio is constant
(RS-4 Maxwellian, RS-8 Sonine; granular.theory.rough_temperature_ratio). The lines start at the
measured temperatures at s = 20, after the transient.

Usage: scripts/figures-rough.py [GRANULAR]   (the release binary, default target/release/granular;
needs the granular Python package, pandas and matplotlib, as scripts/test installs them)
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from granular import theory  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
GRANULAR = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "target/release/granular"
OUT = ROOT / "docs/figures/rough"
START = 20.0

# The --set of each engine's scenario in 3D (the scenario headers').
CASES = {
    ("edmd", 2): [],
    ("edmd", 3): ["dimension=3", "box.lengths=[1.0,1.0,1.0]", "species[0].packing_fraction=0.01"],
    ("dsmc", 2): [],
    ("dsmc", 3): ["dimension=3", "box.lengths=[1.0,1.0,1.0]", "species[0].radius=0.008", "dsmc.cell_size=0.08"],
}
LABEL = {"edmd": "event-driven", "dsmc": "DSMC"}


def run(engine: str, d: int) -> pd.DataFrame:
    out = ROOT / f"runs/rough-hcs-{engine}-{d}d"
    sets = [a for s in CASES[(engine, d)] for a in ("--set", s)]
    scenario = ROOT / f"scenarios/rough-hcs-{engine}.toml"
    subprocess.run(
        [str(GRANULAR), "run", str(scenario), "--out", str(out), "--replace", "--quiet", *sets],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return pd.read_csv(out / "timeseries.csv")


def figure(d: int, runs: dict[str, pd.DataFrame]) -> None:
    alpha, beta = 0.9, 0.0
    zeta = {a: theory.rough_cooling_rate(alpha, beta, dimension=d, approximation=a) for a in ("maxwell", "sonine")}
    theta = {a: theory.rough_temperature_ratio(alpha, beta, dimension=d, approximation=a) for a in ("maxwell", "sonine")}
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for (engine, ts), marker in zip(runs.items(), (".", "x")):
        s = ts["collisions_per_particle"].to_numpy()
        tt, tr = ts["translational_temperature"].to_numpy(), ts["rotational_temperature"].to_numpy()
        ax1.semilogy(s, tt, marker, ms=3, label=f"$T_t$ ({LABEL[engine]})")
        ax1.semilogy(s, tr, marker, ms=3, label=f"$T_r$ ({LABEL[engine]})")
        ax2.plot(s, tr / tt, marker, ms=3, label=rf"$\theta = T_r/T_t$ ({LABEL[engine]})")
        k = int(np.searchsorted(s, START))
        grid = np.linspace(START, s[-1], 50)
        for t0 in (tt[k], tr[k]):
            ax1.semilogy(grid, t0 * np.exp(-zeta["maxwell"] * (grid - s[k])), "k-", lw=0.8)
            ax1.semilogy(grid, t0 * np.exp(-zeta["sonine"] * (grid - s[k])), "k--", lw=0.8)
        late = s >= START
        print(f"{d}D {engine}: theta after s = {START}: {np.mean(tr[late] / tt[late]):.4f} (samples {late.sum()});"
              f" theory Maxwell {theta['maxwell']:.4f}, Sonine {theta['sonine']:.4f}")
    ax1.plot([], [], "k-", lw=0.8, label=rf"Maxwellian $\zeta/\nu$ = {zeta['maxwell']:.4f} (RS-5)")
    ax1.plot([], [], "k--", lw=0.8, label=rf"Sonine $\zeta/\nu$ = {zeta['sonine']:.4f} (RS-8)")
    ax1.set_xlabel("collisions per grain $s$ (dimensionless)")
    ax1.set_ylabel("temperature (energy units, $k_B = 1$)")
    ax1.legend(fontsize=7)
    ax2.axhline(theta["maxwell"], color="k", lw=0.8, label=f"Maxwellian {theta['maxwell']:.4f} (RS-4)")
    ax2.axhline(theta["sonine"], color="k", ls="--", lw=0.8, label=f"Sonine {theta['sonine']:.4f} (RS-8)")
    ax2.set_xlabel("collisions per grain $s$ (dimensionless)")
    ax2.set_ylabel(r"temperature ratio $T_r/T_t$ (dimensionless)")
    ax2.legend(fontsize=7)
    name = "disks" if d == 2 else "spheres"
    fig.suptitle(rf"Rough {name} cooling freely, $\alpha$ = {alpha}, $\beta$ = {beta} (rough-hcs-edmd, rough-hcs-dsmc)")
    fig.tight_layout()
    OUT.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT / f"hcs_{d}d.png", dpi=110)


def main() -> None:
    for d in (2, 3):
        figure(d, {engine: run(engine, d) for engine in ("edmd", "dsmc")})


if __name__ == "__main__":
    main()
