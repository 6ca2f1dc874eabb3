"""The load-balance demonstration of docs/dsmc.md (issue 38): a clustering DSMC gas over 4 MPI
ranks, run once with the slab cuts fixed (`dsmc.balance = "off"`) and once re-cut by grain
count (`"count"`, the default), both from `scripts/load-balance.toml`. It reads the
`ranks:` lines that every output writes to each run's `log.txt` (the largest over the mean
number of grains per rank, and the range of the share of wall time the ranks spent inside
communication, waiting for the slowest included), checks that the two runs' `summary.json`
agree bit for bit (the cuts never change the result), and draws
docs/figures/dsmc/load_balance.png and .svg. Not a CI test (it needs `mpirun` and the MPI
build, and minutes):

    cargo build --release -p granular-cli --features mpi
    python scripts/load-balance.py [target/release/granular] [RANKS]

Needs matplotlib. Prints one Markdown table row per run.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scripts" / "load-balance.toml"
LINE = re.compile(
    r"\[\s*([0-9.]+) s\] ranks: grains per rank max/mean ([0-9.]+); time in communication "
    r"\(waiting included\) ([0-9.]+) to ([0-9.]+) % per rank; cuts moved ([0-9]+) times"
)
WALL_KEYS = {"wall_seconds", "events_per_second", "collisions_per_second", "version"}


def run(binary: str, ranks: int, balance: str, out: Path) -> list[tuple[float, ...]]:
    """Runs the scenario over `ranks` ranks with `balance`; returns the `ranks:` rows."""
    subprocess.run(
        ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", str(ranks), binary, "run",
         str(SCENARIO), "--out", str(out), "--quiet",
         "--set", f'dsmc.balance="{balance}"'],
        check=True,
    )
    rows = [tuple(float(g) for g in m.groups()) for m in LINE.finditer((out / "log.txt").read_text())]
    if not rows:
        sys.exit(f"no `ranks:` lines in {out / 'log.txt'}")
    return rows


def summary(out: Path) -> dict:
    s = json.loads((out / "summary.json").read_text())
    return {k: v for k, v in s.items() if k not in WALL_KEYS}


def main() -> None:
    binary = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "target" / "release" / "granular")
    ranks = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    interval = 0.05  # output.interval of the scenario: one `ranks:` line per output
    with tempfile.TemporaryDirectory() as tmp:
        runs = {b: (run(binary, ranks, b, Path(tmp) / b), summary(Path(tmp) / b)) for b in ("off", "count")}
    same = runs["off"][1] == runs["count"][1]
    print("| balance | outputs | max/mean grains per rank: first, largest, last | cuts moved | "
          "communication share, last output | summary.json of the two runs |")
    print("|---|---|---|---|---|---|")
    for b, (rows, _) in runs.items():
        ratio = [r[1] for r in rows]
        print(f"| `{b}` | {len(rows)} | {ratio[0]:.3f}, {max(ratio):.3f}, {ratio[-1]:.3f} | "
              f"{int(rows[-1][4])} | {rows[-1][2]:.1f}-{rows[-1][3]:.1f} % | "
              f"{'identical' if same else 'DIFFER'} |")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for b, (rows, _) in runs.items():
        t = [interval * k for k in range(len(rows))]
        label = "fixed cuts (balance = \"off\")" if b == "off" else "re-cut by count (balance = \"count\")"
        ax1.plot(t, [r[1] for r in rows], marker="o", ms=3, label=label)
        ax2.fill_between(t, [r[2] for r in rows], [r[3] for r in rows], alpha=0.35, label=label)
    ax1.set_xlabel("time t (simulation time units)")
    ax1.set_ylabel("grains per rank, largest / mean (dimensionless)")
    ax1.set_title(f"Clustering DSMC gas over {ranks} ranks")
    ax1.legend()
    ax2.set_xlabel("time t (simulation time units)")
    ax2.set_ylabel("share of wall time in communication (%)")
    ax2.set_title(f"Lowest to highest rank ({ranks} ranks on a 2-core machine)")
    ax2.legend()
    fig.tight_layout()
    out = ROOT / "docs" / "figures" / "dsmc"
    for ext in ("png", "svg"):
        fig.savefig(out / f"load_balance.{ext}", dpi=110)
    if not same:
        sys.exit("the two runs' summary.json differ: the cuts changed the result")


if __name__ == "__main__":
    main()
