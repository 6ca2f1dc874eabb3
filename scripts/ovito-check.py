"""Open a run's trajectories (all four formats) with OVITO's Python module and render the last
frame of the GSD file headless: the documented check of docs/output.md ("Checked with OVITO").

    pip install ovito            # in a separate environment: the wheel is about 116 MB
    granular run scenarios/... --out RUN --set 'output.trajectory=["xyz","lammps","gsd","vtk"]'
    python scripts/ovito-check.py RUN [PICTURE.png]

Rendering needs a Vulkan driver, even for the software ray tracer (on Debian: libvulkan1 and
mesa-vulkan-drivers); without one the check still opens every format and says why it did not render.
"""

from __future__ import annotations

import sys
from pathlib import Path

import ovito
from ovito.io import import_file
from ovito.vis import TachyonRenderer, Viewport

# OVITO reads the .vtp files as particles with its "vtk/vtp/particles" reader, given as a
# wildcard series; its .pvd reader hands the frames to the mesh reader, which finds no mesh.
FILES = {
    "trajectory.xyz": None,
    "trajectory.lammpstrj": None,
    "trajectory.gsd": None,
    "vtp/snapshot_*.vtp": "vtk/vtp/particles",
}


def main() -> int:
    run = Path(sys.argv[1]) / "trajectory"
    picture = sys.argv[2] if len(sys.argv) > 2 else "ovito-gsd.png"
    print(f"ovito {ovito.version_string}")
    for name, fmt in FILES.items():
        pipeline = import_file(str(run / name), input_format=fmt) if fmt else import_file(str(run / name))
        last = pipeline.source.num_frames - 1
        data = pipeline.compute(last)
        cell = data.cell
        print(
            f"{name}: {pipeline.source.num_frames} frames, {data.particles.count} particles, "
            f"properties {sorted(data.particles.keys())}, "
            + (f"2D {cell.is2D}, pbc {cell.pbc}" if cell is not None else "no cell")
        )
    pipeline = import_file(str(run / "trajectory.gsd"))
    pipeline.add_to_scene()
    viewport = Viewport(type=Viewport.Type.Top)
    viewport.zoom_all()
    try:
        last = pipeline.source.num_frames - 1
        viewport.render_image(size=(800, 440), filename=picture, frame=last, renderer=TachyonRenderer())
    except RuntimeError as e:
        print(f"could not render: {e}")
        return 1
    print(f"rendered the last GSD frame to {picture}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
