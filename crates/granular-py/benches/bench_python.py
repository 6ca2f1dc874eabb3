"""Speed of the Python layer (a benchmark, not a test): does Python tax the engine?

1. ``advance`` called 10^4 times in small steps against one call over the same time (same scenario, same seed,
   so the same events): the overhead per call.
2. Copying the positions of 10^6 grains into a NumPy array (``Simulation.positions``), and a whole snapshot.

    .venv/bin/python crates/granular-py/benches/bench_python.py [--grains N] [--steps S] [--big N]

Results and the machine they were measured on: docs/performance.md.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import granular


def scenario(n: int, phi: float, placement: str = "random") -> granular.Scenario:
    return granular.Scenario.from_dict(
        {
            "engine": "edmd",
            "dimension": 2,
            "seed": 1,
            "box": {"lengths": [1.0, 1.0], "boundary": "periodic"},
            "species": [
                {
                    "name": "disk",
                    "count": n,
                    "packing_fraction": phi,
                    "velocity": {"distribution": "maxwell_boltzmann", "temperature": 1.0},
                }
            ],
            "initial": {"placement": placement},
            "stop": {"time": 1e9, "wall_seconds": 86400.0},
        }
    )


def bench_steps(n: int, steps: int, total: float, repeat: int) -> None:
    sc = scenario(n, 0.2)
    one, many, events = [], [], 0
    for _ in range(repeat):
        sim = granular.Simulation(sc, insist=True)
        start = time.perf_counter()
        sim.advance(total)
        one.append(time.perf_counter() - start)
        events = sim.events
        sim = granular.Simulation(sc, insist=True)
        dt = total / steps
        start = time.perf_counter()
        for k in range(1, steps + 1):
            sim.advance(k * dt)
        many.append(time.perf_counter() - start)
        assert sim.time == total
    a, b = min(one), min(many)
    print(f"advance: N = {n}, t = {total}, {events} events")
    print(f"  one call:        {a:.3f} s (best of {repeat})")
    print(f"  {steps} calls:    {b:.3f} s (best of {repeat})  ->  {100 * (b / a - 1):+.2f} %"
          f"  ({(b - a) / steps * 1e6:.1f} us per call)")


def bench_copy(n: int, repeat: int) -> None:
    start = time.perf_counter()
    sim = granular.Simulation(scenario(n, 0.1, "lattice"), insist=True)
    built = time.perf_counter() - start
    positions, snapshots = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        x = sim.positions
        positions.append(time.perf_counter() - start)
        start = time.perf_counter()
        sim.snapshot()
        snapshots.append(time.perf_counter() - start)
    assert x.shape == (n, 2)
    print(f"copy: N = {n} (built in {built:.1f} s)")
    print(f"  positions (N, 2) float64: median {1e3 * statistics.median(positions):.2f} ms, "
          f"best {1e3 * min(positions):.2f} ms ({repeat} runs)")
    print(f"  snapshot() (all arrays):  median {1e3 * statistics.median(snapshots):.2f} ms, "
          f"best {1e3 * min(snapshots):.2f} ms")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--grains", type=int, default=10_000, help="grains of the advance benchmark")
    p.add_argument("--steps", type=int, default=10_000, help="small steps")
    p.add_argument("--time", type=float, default=0.5, help="simulated time of the advance benchmark")
    p.add_argument("--big", type=int, default=1_000_000, help="grains of the copy benchmark")
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args()
    print(f"granular {granular.__version__}, Python {platform.python_version()}, {platform.machine()}, "
          f"{platform.processor() or platform.platform()}")
    bench_steps(args.grains, args.steps, args.time, args.repeat)
    bench_copy(args.big, max(args.repeat, 10))


if __name__ == "__main__":
    main()
