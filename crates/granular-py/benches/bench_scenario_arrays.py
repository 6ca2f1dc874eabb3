"""Per-grain NumPy arrays into a Scenario (a benchmark, not a test): how long ``Scenario.from_dict`` with
NumPy ``positions`` and ``velocities`` takes for 10^6 grains (issue 36: "well under a second"), then
``Scenario.set`` of one array, and, for comparison, the same numbers as lists (which go through TOML text)
at a tenth of the size.

    .venv/bin/python crates/granular-py/benches/bench_scenario_arrays.py [--grains N] [--repeat R]

Results and the machine they were measured on: docs/performance.md.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

import granular


def scenario_dict(n: int, positions: object, velocities: object) -> dict:
    return {
        "engine": "dsmc",
        "dimension": 3,
        "seed": 1,
        "box": {"boundary": "periodic"},
        "species": [
            {
                "name": "grain",
                "count": n,
                "radius": 1e-4,
                "positions": positions,
                "velocity": {"distribution": "per_grain", "velocities": velocities},
            }
        ],
        "stop": {"time": 1.0},
    }


def best(f, repeat: int) -> tuple[float, float]:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grains", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    n = a.grains
    rng = np.random.default_rng(1)
    x, v = rng.random((n, 3)), rng.normal(size=(n, 3))
    print(f"{platform.processor() or platform.machine()}, {n} grains (3D DSMC), best and median of {a.repeat}")

    lo, med = best(lambda: granular.Scenario.from_dict(scenario_dict(n, x, v)), a.repeat)
    print(f"Scenario.from_dict, NumPy arrays:      {lo:7.3f} s  (median {med:.3f} s)")
    sc = granular.Scenario.from_dict(scenario_dict(n, x, v))
    lo, med = best(lambda: sc.set("species[0].velocity.velocities", v), a.repeat)
    print(f"Scenario.set, one NumPy array:         {lo:7.3f} s  (median {med:.3f} s)")

    m = max(n // 10, 1)
    xl, vl = x[:m].tolist(), v[:m].tolist()
    lo, med = best(lambda: granular.Scenario.from_dict(scenario_dict(m, xl, vl)), max(a.repeat // 2, 1))
    print(f"Scenario.from_dict, lists (TOML), {m} grains: {lo:7.3f} s  (median {med:.3f} s)")


if __name__ == "__main__":
    main()
