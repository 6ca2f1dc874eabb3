"""freud interoperability: ``Simulation.box`` and ``RunData.box`` go into ``freud.box.Box.from_box``, and freud's
g(r) of a run's snapshots agrees with the run's ``pair_correlation.csv`` within the counting errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import granular

freud = pytest.importorskip("freud")

GAS = """
engine = "edmd"
dimension = 2
seed = 3
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "disk"
count = 600
packing_fraction = 0.3
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[stop]
time = 0.4
[output]
interval = 0.02
snapshot_every = 1
pair_correlation = true
pair_correlation_bins = 60
"""


def test_boxes_go_into_freud(tmp_path: Path) -> None:
    sc = granular.Scenario.from_toml(GAS)
    sim = granular.Simulation(sc)
    box = freud.box.Box.from_box(sim.box)
    assert box.is2D and box.Lx == 1.0 and box.Ly == 1.0
    # (Without g(r): 600 spheres at packing fraction 0.3 in this box are too big for its default range.)
    three = granular.Scenario.from_toml(
        GAS.replace("dimension = 2", "dimension = 3")
        .replace("[1.0, 1.0]", "[1.0, 2.0, 3.0]")
        .replace("pair_correlation = true\npair_correlation_bins = 60\n", "")
    )
    box3 = freud.box.Box.from_box(three.box)
    assert not box3.is2D and (box3.Lx, box3.Ly, box3.Lz) == (1.0, 2.0, 3.0)
    sim.run(out=tmp_path / "run")
    assert freud.box.Box.from_box(granular.load_run(tmp_path / "run").box) == box


def test_freud_pair_correlation_agrees_with_the_run(tmp_path: Path) -> None:
    sc = granular.Scenario.from_toml(GAS)
    granular.Simulation(sc).run(out=tmp_path / "run")
    run = granular.load_run(tmp_path / "run")
    table = run.correlations["pair_correlation"]
    r = np.asarray(table["r"])
    g = np.asarray(table["g.disk.disk"])
    width = r[1] - r[0]
    rdf = freud.density.RDF(bins=len(r), r_max=r[-1] + width / 2, r_min=r[0] - width / 2)
    box = freud.box.Box.from_box(run.box)
    frames = 0
    for snap in run.snapshots():
        points = np.zeros((len(snap.positions), 3))
        points[:, :2] = snap.positions - 0.5  # freud's box runs from -L/2 to L/2
        rdf.compute((box, points), reset=False)
        frames += 1
    assert frames == len(run.timeseries["time"])  # the same observation times
    # freud computes its bin centres in single precision.
    np.testing.assert_allclose(rdf.bin_centers, r, rtol=4 * np.finfo(np.float32).eps)
    counts = np.asarray(rdf.bin_counts, dtype=float)
    seen = counts > 0
    assert seen.sum() > len(r) // 2
    # Counting (Poisson) error of each bin: g / sqrt(pairs counted).
    error = rdf.rdf[seen] / np.sqrt(counts[seen])
    assert np.all(np.abs(rdf.rdf[seen] - g[seen]) <= 4.0 * error), np.max(np.abs(rdf.rdf[seen] - g[seen]) / error)
    # Where the grains cannot be (inside contact), both are zero.
    sigma = 2.0 * granular.Simulation(sc).radii[0]
    inside = rdf.bin_centers < 0.9 * sigma
    assert np.all(g[inside] == 0.0) and np.all(rdf.rdf[inside] == 0.0)
