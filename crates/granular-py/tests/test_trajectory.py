"""Trajectories (``[output] trajectory``, ``granular export``) read back with the reference readers
of each format and compared with the run's ``.npz`` snapshots: ``gsd`` (GSD, HOOMD schema), ASE
(extended XYZ, LAMMPS dump) and VTK's own XML reader (``.vtp``, from the ``vtk`` wheel; meshio reads
only the UnstructuredGrid ``.vtu``, not PolyData). The test command installs all three."""

from __future__ import annotations

import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import granular

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    tomllib = pytest.importorskip("tomli")
from conftest import EDMD_2D, EDMD_3D, INTRUDER_1D, cli

gsd_hoomd = pytest.importorskip("gsd.hoomd")
ase_io = pytest.importorskip("ase.io")

# EDMD_2D with a box periodic along x and walled along y, and every format written as it runs.
TRAJECTORY_2D = EDMD_2D.replace('boundary = "periodic"', 'boundary = ["periodic", "wall"]').replace(
    "lengths = [1.0, 1.0]", "lengths = [1.0, 0.5]"
) + 'trajectory = ["xyz", "lammps", "gsd", "vtk"]\n'


def snapshots(run: Path) -> list[granular.Snapshot]:
    shots = list(granular.load_run(run).snapshots())
    assert len(shots) >= 2
    return shots


def padded(a: np.ndarray) -> np.ndarray:
    """(n, D) as (n, 3), with zeros along z in 2D."""
    return np.pad(a, ((0, 0), (0, 3 - a.shape[1])))


@pytest.fixture(scope="module")
def run_2d(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("traj2d") / "run"
    granular.Simulation(granular.Scenario.from_toml(TRAJECTORY_2D)).run(out=out)
    return out


@pytest.fixture(scope="module")
def run_3d(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 3D run without trajectories, exported afterwards with the command line."""
    out = tmp_path_factory.mktemp("traj3d") / "run"
    granular.Simulation(granular.Scenario.from_toml(EDMD_3D)).run(out=out)
    cli("export", str(out), "--format", "xyz,lammps", "--format", "gsd", "--format", "vtk")
    return out


def box(run: Path) -> tuple[np.ndarray, np.ndarray]:
    table = tomllib.loads((run / "scenario.toml").read_text())["box"]
    lengths = np.array(table["lengths"], dtype=float)
    boundary = table["boundary"]
    kinds = [boundary] * len(lengths) if isinstance(boundary, str) else boundary
    return lengths, np.array([k == "periodic" for k in kinds])


@pytest.mark.parametrize("which", ["run_2d", "run_3d"])
def test_gsd_reads_back_in_single_precision(which: str, request: pytest.FixtureRequest) -> None:
    run = request.getfixturevalue(which)
    shots = snapshots(run)
    lengths, periodic = box(run)
    dim = len(lengths)
    with gsd_hoomd.open(run / "trajectory" / "trajectory.gsd") as traj:
        assert len(traj) == len(shots)
        for frame, shot in zip(traj, shots):
            assert frame.configuration.dimensions == dim
            lz = lengths[2] if dim == 3 else 0.0
            np.testing.assert_array_equal(
                frame.configuration.box, np.array([lengths[0], lengths[1], lz, 0, 0, 0], dtype=np.float32)
            )
            assert frame.particles.N == len(shot.radii)
            assert frame.particles.types == shot.species_names
            np.testing.assert_array_equal(frame.particles.typeid, shot.species)
            # HOOMD's box is centred on the origin.
            centred = padded(shot.positions - lengths / 2)
            np.testing.assert_array_equal(frame.particles.position, centred.astype(np.float32))
            np.testing.assert_array_equal(frame.particles.velocity, padded(shot.velocities).astype(np.float32))
            np.testing.assert_array_equal(frame.particles.mass, shot.masses.astype(np.float32))
            np.testing.assert_array_equal(frame.particles.diameter, (2 * shot.radii).astype(np.float32))
            assert frame.log["time"][0] == shot.time
            # Walls and ids, which the HOOMD schema lacks, in its free log namespace.
            np.testing.assert_array_equal(frame.log["box/periodic"], np.pad(periodic, (0, 3 - dim)).astype(np.uint8))
            np.testing.assert_array_equal(frame.log["particles/id"], np.arange(len(shot.radii), dtype=np.uint64))
    steps = gsd_hoomd.read_log(run / "trajectory" / "trajectory.gsd")["configuration/step"]
    names = sorted((run / "snapshots").glob("snapshot_*.npz"))
    assert [int(s) for s in steps] == [int(p.stem.split("_")[1]) for p in names]


@pytest.mark.parametrize("which", ["run_2d", "run_3d"])
def test_extended_xyz_reads_back_exactly_with_ase(which: str, request: pytest.FixtureRequest) -> None:
    run = request.getfixturevalue(which)
    shots = snapshots(run)
    lengths, periodic = box(run)
    path = run / "trajectory" / "trajectory.xyz"
    frames = ase_io.read(path, index=":", format="extxyz")
    assert len(frames) == len(shots)
    steps = [int(p.stem.split("_")[1]) for p in sorted((run / "snapshots").glob("snapshot_*.npz"))]
    properties = "Properties=type:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:id:I:1"
    assert path.read_text().count(properties) == len(shots)
    for atoms, shot, step in zip(frames, shots, steps):
        assert atoms.info["Time"] == shot.time
        assert atoms.info["Step"] == step
        # The Lattice: the box's edges along the axes (2D: a thin slab along z).
        np.testing.assert_array_equal(atoms.cell[:], np.diag(np.diag(atoms.cell[:])))
        np.testing.assert_array_equal(atoms.positions, padded(shot.positions))
        np.testing.assert_array_equal(atoms.arrays["velo"], padded(shot.velocities))
        np.testing.assert_array_equal(atoms.arrays["radius"], shot.radii)
        np.testing.assert_array_equal(atoms.arrays["mass"], shot.masses)
        np.testing.assert_array_equal(atoms.arrays["id"], np.arange(len(shot.radii)))
        assert list(atoms.arrays["type"]) == [shot.species_names[s] for s in shot.species]
        np.testing.assert_array_equal(np.diag(atoms.cell)[: len(lengths)], lengths)
        assert list(atoms.pbc) == list(np.pad(periodic, (0, 3 - len(periodic))))


@pytest.mark.parametrize("which", ["run_2d", "run_3d"])
def test_lammps_dump_reads_back_exactly_with_ase(which: str, request: pytest.FixtureRequest) -> None:
    from ase.calculators.lammps import convert

    run = request.getfixturevalue(which)
    shots = snapshots(run)
    lengths, periodic = box(run)
    path = run / "trajectory" / "trajectory.lammpstrj"
    frames = ase_io.read(path, index=":", format="lammps-dump-text")
    assert len(frames) == len(shots)
    # ASE converts velocities from LAMMPS' "metal" units; radius, mass and TIME it does not read.
    to_ase = convert(1.0, "velocity", "metal", "ASE")
    text = path.read_text()
    times = [float(t) for t in re.findall(r"ITEM: TIME\n(\S+)", text)]
    blocks = text.split("ITEM: ATOMS id type x y z vx vy vz radius mass\n")[1:]
    steps = [int(t) for t in re.findall(r"ITEM: TIMESTEP\n(\S+)", text)]
    assert steps == [int(p.stem.split("_")[1]) for p in sorted((run / "snapshots").glob("snapshot_*.npz"))]
    flags = " ".join("pp" if p else "ff" for p in np.pad(periodic, (0, 3 - len(periodic))))
    assert text.count(f"ITEM: BOX BOUNDS {flags}\n") == len(shots)
    for atoms, shot, time, step, block in zip(frames, shots, times, steps, blocks):
        assert time == shot.time
        assert atoms.info["timestep"] == step
        # ASE sorts the atoms by the id column (which it drops; the ids are read from the text below).
        order = np.arange(len(atoms))
        np.testing.assert_array_equal(atoms.positions[order], padded(shot.positions))
        np.testing.assert_allclose(atoms.get_velocities()[order] / to_ase, padded(shot.velocities), rtol=1e-15)
        np.testing.assert_array_equal(atoms.arrays["type"][order], shot.species + 1)
        np.testing.assert_array_equal(np.diag(atoms.cell)[: len(lengths)], lengths)
        assert list(atoms.pbc) == list(np.pad(periodic, (0, 3 - len(periodic))))
        rows = np.array([line.split() for line in block.splitlines()[: len(shot.radii)]], dtype=float)
        np.testing.assert_array_equal(rows[:, 0], np.arange(1, len(shot.radii) + 1))
        np.testing.assert_array_equal(rows[:, 8], shot.radii)
        np.testing.assert_array_equal(rows[:, 9], shot.masses)


@pytest.mark.parametrize("which", ["run_2d", "run_3d"])
def test_vtk_polydata_reads_back_exactly_with_vtk(which: str, request: pytest.FixtureRequest) -> None:
    vtk_xml = pytest.importorskip("vtkmodules.vtkIOXML", reason="the vtk wheel is missing (scripts/test installs it)")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    run = request.getfixturevalue(which)
    shots = snapshots(run)
    lengths, periodic = box(run)
    dim = len(lengths)
    # The .pvd index (plain XML): one DataSet per snapshot, its time and its file named as the .npz.
    root = ET.parse(run / "trajectory" / "trajectory.pvd").getroot()
    assert root.tag == "VTKFile" and root.attrib["type"] == "Collection"
    entries = root.findall("./Collection/DataSet")
    names = sorted((run / "snapshots").glob("snapshot_*.npz"))
    assert [e.attrib["file"] for e in entries] == [f"vtp/{p.stem}.vtp" for p in names]
    assert [float(e.attrib["timestep"]) for e in entries] == [s.time for s in shots]
    for entry, shot, name in zip(entries, shots, names):
        reader = vtk_xml.vtkXMLPolyDataReader()
        reader.SetFileName(str(run / "trajectory" / entry.attrib["file"]))
        reader.Update()
        assert reader.GetErrorCode() == 0
        data = reader.GetOutput()
        n = len(shot.radii)
        assert data.GetNumberOfPoints() == n and data.GetNumberOfVerts() == n
        field = data.GetFieldData()
        assert field.GetArray("TimeValue").GetValue(0) == shot.time
        assert field.GetArray("Step").GetValue(0) == int(name.stem.split("_")[1])
        np.testing.assert_array_equal(vtk_to_numpy(field.GetArray("BoxLengths")), np.pad(lengths, (0, 3 - dim)))
        np.testing.assert_array_equal(vtk_to_numpy(field.GetArray("Periodic")), np.pad(periodic, (0, 3 - dim)))
        points = data.GetPointData()
        arrays = {points.GetArrayName(k) for k in range(points.GetNumberOfArrays())}
        assert arrays == {"id", "species", "v", "radius", "mass"}
        np.testing.assert_array_equal(vtk_to_numpy(data.GetPoints().GetData()), padded(shot.positions))
        np.testing.assert_array_equal(vtk_to_numpy(points.GetArray("v")), padded(shot.velocities))
        np.testing.assert_array_equal(vtk_to_numpy(points.GetArray("radius")), shot.radii)
        np.testing.assert_array_equal(vtk_to_numpy(points.GetArray("mass")), shot.masses)
        np.testing.assert_array_equal(vtk_to_numpy(points.GetArray("species")), shot.species)
        np.testing.assert_array_equal(vtk_to_numpy(points.GetArray("id")), np.arange(n))
        # Every vertex cell is one grain, in order.
        verts = vtk_to_numpy(data.GetVerts().GetConnectivityArray())
        np.testing.assert_array_equal(verts, np.arange(n))


def test_export_rewrites_what_the_run_wrote(run_2d: Path, tmp_path: Path) -> None:
    """``granular export`` of the run's snapshots gives the same files as writing them as it ran."""
    import shutil

    copy = tmp_path / "run"
    shutil.copytree(run_2d, copy)
    shutil.rmtree(copy / "trajectory")
    cli("export", str(copy), "--format", "xyz,lammps,gsd,vtk")
    for name in ["trajectory.xyz", "trajectory.lammpstrj", "trajectory.gsd", "trajectory.pvd"]:
        assert (copy / "trajectory" / name).read_bytes() == (run_2d / "trajectory" / name).read_bytes(), name


def test_export_of_an_intruder_run_says_there_are_no_trajectories(tmp_path: Path) -> None:
    out = tmp_path / "run"
    granular.Simulation(granular.Scenario.from_toml(INTRUDER_1D)).run(out=out)
    result = cli("export", str(out), "--format", "xyz", check=False)
    assert result.returncode == 2
    assert "intruder engine, which has no grain trajectories" in result.stderr
    assert not (out / "trajectory").exists()


# Rough grains (docs/rough.md): a 2D event-driven run of two species with their own κ, every
# format written as it runs, and a 3D DSMC run exported afterwards by the command line.
ROUGH_2D = """
engine = "edmd"
dimension = 2
seed = 4
[box]
lengths = [1.0, 0.5]
boundary = ["periodic", "wall"]
[[species]]
name = "disk"
count = 150
radius = 0.005
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "maxwell_boltzmann", temperature = 0.5 }
[[species]]
name = "ring"
count = 50
radius = 0.01
mass = 4.0
inertia = 0.9
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "given", angular_velocity = [3.0] }
[collisions]
restitution = 0.9
tangential_restitution = 0.3
[stop]
collisions_per_particle = 8.0
[output]
interval = 0.02
snapshot_every = 3
trajectory = ["xyz", "lammps", "gsd", "vtk"]
"""

ROUGH_3D = """
engine = "dsmc"
dimension = 3
seed = 12
[box]
lengths = [1.0, 1.0, 1.0]
boundary = ["periodic", "periodic", "wall"]
[[species]]
name = "grain"
count = 3000
packing_fraction = 0.02
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "maxwell_boltzmann", temperature = 0.5 }
[collisions]
restitution = 0.8
tangential_restitution = 0.4
wall_restitution = 0.9
wall_tangential_restitution = -0.5
[stop]
collisions_per_particle = 3.0
[output]
interval = 0.02
snapshot_every = 3
"""


@pytest.fixture(scope="module")
def rough_2d(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("rough2d") / "run"
    granular.Simulation(granular.Scenario.from_toml(ROUGH_2D)).run(out=out)
    return out


@pytest.fixture(scope="module")
def rough_3d(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("rough3d") / "run"
    granular.Simulation(granular.Scenario.from_toml(ROUGH_3D)).run(out=out)
    cli("export", str(out), "--format", "xyz,lammps,gsd,vtk")
    return out


def spins(shot: granular.Snapshot) -> np.ndarray:
    """The snapshot's angular velocities as (N, 3): (0, 0, ω_z) for disks."""
    w = shot.angular_velocities
    assert w is not None
    return np.pad(w[:, None], ((0, 0), (2, 0))) if w.ndim == 1 else w


def kappas(run: Path) -> np.ndarray:
    """κ of each species: ``species[i].inertia`` or the uniform grain's (1/2 disk, 2/5 sphere)."""
    scenario = tomllib.loads((run / "scenario.toml").read_text())
    uniform = 0.5 if scenario["dimension"] == 2 else 0.4
    return np.array([sp.get("inertia", uniform) for sp in scenario["species"]])


@pytest.mark.parametrize("which", ["rough_2d", "rough_3d"])
def test_rough_gsd_has_moment_inertia_and_angmom_that_give_back_the_spins(
    which: str, request: pytest.FixtureRequest
) -> None:
    """HOOMD's ``particles/angmom`` is ``P = 2 q ⊗ (0, I ω)`` (identity orientation ``q``):
    ``ω_k = P_k / (2 I_k)`` from ``particles/moment_inertia``, ``(0, 0, I)`` for disks."""
    run = request.getfixturevalue(which)
    shots = snapshots(run)
    kappa = kappas(run)
    with gsd_hoomd.open(run / "trajectory" / "trajectory.gsd") as traj:
        assert len(traj) == len(shots)
        for frame, shot in zip(traj, shots):
            dim = frame.configuration.dimensions
            w = spins(shot)
            moment = kappa[shot.species] * shot.masses * shot.radii * shot.radii
            moments = np.stack([moment] * 3, axis=1)
            if dim == 2:
                moments[:, :2] = 0.0
            np.testing.assert_array_equal(frame.particles.moment_inertia, moments.astype(np.float32))
            angmom = frame.particles.angmom
            assert angmom.shape == (len(shot.radii), 4)
            np.testing.assert_array_equal(angmom[:, 0], 0.0)
            np.testing.assert_array_equal(angmom[:, 1:], (2.0 * moments * w).astype(np.float32))
            # ω back from the file's two single-precision arrays (two roundings to float32).
            axes = [2] if dim == 2 else [0, 1, 2]
            inertia = frame.particles.moment_inertia.astype(np.float64)
            back = angmom[:, 1:].astype(np.float64)[:, axes] / (2.0 * inertia[:, axes])
            np.testing.assert_allclose(back, w[:, axes], rtol=3e-7, atol=0)
            if dim == 2:
                np.testing.assert_array_equal(angmom[:, 1:3], 0.0)
            assert np.any(w != 0.0)


@pytest.mark.parametrize("which", ["run_2d", "run_3d"])
def test_smooth_gsd_has_no_spin_chunks(which: str, request: pytest.FixtureRequest) -> None:
    import gsd.fl

    run = request.getfixturevalue(which)
    with gsd.fl.open(run / "trajectory" / "trajectory.gsd", "r") as f:
        for name in ["particles/moment_inertia", "particles/angmom", "particles/orientation"]:
            assert not f.chunk_exists(frame=0, name=name), name


@pytest.mark.parametrize("which", ["rough_2d", "rough_3d"])
def test_rough_extended_xyz_has_omega_read_exactly_by_ase(which: str, request: pytest.FixtureRequest) -> None:
    run = request.getfixturevalue(which)
    shots = snapshots(run)
    path = run / "trajectory" / "trajectory.xyz"
    assert path.read_text().count("id:I:1:omega:R:3 ") == len(shots)
    frames = ase_io.read(path, index=":", format="extxyz")
    assert len(frames) == len(shots)
    for atoms, shot in zip(frames, shots):
        np.testing.assert_array_equal(atoms.arrays["omega"], spins(shot))
        np.testing.assert_array_equal(atoms.positions, padded(shot.positions))


@pytest.mark.parametrize("which", ["rough_2d", "rough_3d"])
def test_rough_lammps_dump_has_omega_columns(which: str, request: pytest.FixtureRequest) -> None:
    run = request.getfixturevalue(which)
    shots = snapshots(run)
    path = run / "trajectory" / "trajectory.lammpstrj"
    header = "ITEM: ATOMS id type x y z vx vy vz radius mass omegax omegay omegaz\n"
    text = path.read_text()
    blocks = text.split(header)[1:]
    assert len(blocks) == len(shots)
    for block, shot in zip(blocks, shots):
        rows = np.array([line.split() for line in block.splitlines()[: len(shot.radii)]], dtype=float)
        assert rows.shape[1] == 13
        np.testing.assert_array_equal(rows[:, 10:13], spins(shot))
    # ASE still reads the dump (positions as before; it keeps no omega).
    frames = ase_io.read(path, index=":", format="lammps-dump-text")
    for atoms, shot in zip(frames, shots):
        np.testing.assert_array_equal(atoms.positions, padded(shot.positions))


@pytest.mark.parametrize("which", ["rough_2d", "rough_3d"])
def test_rough_vtk_has_the_angular_velocity_array(which: str, request: pytest.FixtureRequest) -> None:
    vtk_xml = pytest.importorskip("vtkmodules.vtkIOXML", reason="the vtk wheel is missing (scripts/test installs it)")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    run = request.getfixturevalue(which)
    shots = snapshots(run)
    names = sorted((run / "snapshots").glob("snapshot_*.npz"))
    for shot, name in zip(shots, names):
        reader = vtk_xml.vtkXMLPolyDataReader()
        reader.SetFileName(str(run / "trajectory" / "vtp" / f"{name.stem}.vtp"))
        reader.Update()
        assert reader.GetErrorCode() == 0
        points = reader.GetOutput().GetPointData()
        arrays = {points.GetArrayName(k) for k in range(points.GetNumberOfArrays())}
        assert arrays == {"id", "species", "v", "radius", "mass", "angular_velocity"}
        np.testing.assert_array_equal(vtk_to_numpy(points.GetArray("angular_velocity")), spins(shot))


def test_rough_export_rewrites_what_the_run_wrote(rough_2d: Path, tmp_path: Path) -> None:
    import shutil

    copy = tmp_path / "run"
    shutil.copytree(rough_2d, copy)
    shutil.rmtree(copy / "trajectory")
    cli("export", str(copy), "--format", "xyz,lammps,gsd,vtk")
    for name in ["trajectory.xyz", "trajectory.lammpstrj", "trajectory.gsd", "trajectory.pvd"]:
        assert (copy / "trajectory" / name).read_bytes() == (rough_2d / "trajectory" / name).read_bytes(), name
