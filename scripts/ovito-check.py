"""Open one run's trajectories in all four formats with OVITO's Python module, render the same
frame (the last) from each headless, and screenshot our report's player at that frame: the
documented check of docs/output.md ("Checked with OVITO"). Not a CI test (it needs ovito).

    pip install ovito playwright pillow   # a separate environment: the ovito wheel is about 116 MB
    granular run scenarios/problem2-mixture.toml --out RUN --quiet \\
        --set species.0.count=200 --set species.1.count=200 \\
        --set species.0.radius=0.012 --set species.1.radius=0.02 \\
        --set stop.collisions_per_particle=30 --set output.interval=0.05 \\
        --set output.snapshot_every=4 --set output.equilibration_collisions_per_particle=10 \\
        --set 'box.boundary=["periodic","wall"]' \\
        --set 'output.trajectory=["xyz","lammps","gsd","vtk"]'
    granular report RUN
    python scripts/ovito-check.py RUN [FOLDER]

It prints one Markdown table row per format (what OVITO read) and writes FOLDER/ovito-xyz.png,
ovito-lammps.png, ovito-gsd.png, ovito-vtp.png and report-player.png (400 x 400; FOLDER defaults
to docs/figures/trajectory; quantised to 64 colours where Pillow is installed). The grains are
coloured by species with the report's colours in every picture. The report's screenshot needs
the `playwright` package and Debian's `chromium`; without them it is left out and the script
says so.

Rendering needs a Vulkan driver, even for the software ray tracer (on Debian: libvulkan1 and
mesa-vulkan-drivers); without one the check still opens every format and says why it did not
render (exit status 1).
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np
import ovito
from ovito.io import import_file
from ovito.vis import TachyonRenderer, Viewport

SIZE = 400
# OVITO reads the .vtp files as particles with its "vtk/vtp/particles" reader, given as a
# wildcard series; its .pvd reader hands the frames to the mesh reader, which finds no mesh.
FORMATS = {
    "xyz": ("trajectory.xyz", None),
    "lammps": ("trajectory.lammpstrj", None),
    "gsd": ("trajectory.gsd", None),
    "vtp": ("vtp/snapshot_*.vtp", "vtk/vtp/particles"),
}


def open_format(run: Path, name: str, fmt: str | None) -> ovito.pipeline.Pipeline:
    path = str(run / "trajectory" / name)
    return import_file(path, input_format=fmt) if fmt else import_file(path)


def describe(key: str, name: str, pipeline: ovito.pipeline.Pipeline, frame: int) -> str:
    """The Markdown row: file, frames, particles, dimensions and periodicity, properties, time."""
    data = pipeline.compute(frame)
    cell = data.cell
    if cell is None:
        dims = "no cell"
    else:
        pbc = ", ".join("T" if p else "F" for p in cell.pbc)
        dims = f"{'2D' if cell.is2D else '3D'}, pbc ({pbc})"
    time = next((f"{data.attributes[k]:g}" for k in ("Time", "time", "TimeValue") if k in data.attributes), "-")
    props = ", ".join(sorted(data.particles.keys()))
    return (
        f"| `{name}` | {pipeline.source.num_frames} | {data.particles.count} | {dims} | {props} | {time} "
        f"| ![{key}](figures/trajectory/ovito-{key}.png) |"
    )


# The report player's species colours (crates/granular-report/src/html/player.js).
SPECIES_COLOURS = [(0x1F, 0x77, 0xB4), (0xFF, 0x7F, 0x0E), (0x2C, 0xA0, 0x2C), (0xD6, 0x27, 0x28)]


def colour_by_species(frame: int, data: ovito.data.DataCollection) -> None:
    """Colours the grains as the report does: the species index is the `species` array of the
    .vtp files, else the place of the particle's type among the types OVITO made (the order of
    [[species]] for GSD and LAMMPS, the order of first appearance for extended XYZ)."""
    particles = data.particles_
    if "species" in particles:
        species = np.asarray(particles["species"]).astype(int)
    else:
        types = particles.particle_types
        place = {t.id: k for k, t in enumerate(types.types)}
        species = np.array([place[t] for t in np.asarray(types)])
    palette = np.array(SPECIES_COLOURS, dtype=float) / 255
    particles_colour = particles.create_property("Color")
    particles_colour[...] = palette[species % len(palette)]


def small_png(picture: Path) -> None:
    """Quantises to 64 colours (a few tens of KB) where Pillow is installed."""
    try:
        from PIL import Image
    except ImportError:
        return
    Image.open(picture).convert("RGB").quantize(64).save(picture, optimize=True)


def render(pipeline: ovito.pipeline.Pipeline, frame: int, picture: Path) -> None:
    pipeline.modifiers.append(colour_by_species)
    pipeline.add_to_scene()
    try:
        viewport = Viewport(type=Viewport.Type.Top)
        viewport.zoom_all(size=(SIZE, SIZE))
        viewport.render_image(
            size=(SIZE, SIZE), filename=str(picture), frame=frame, renderer=TachyonRenderer(antialiasing=False)
        )
    finally:
        pipeline.remove_from_scene()
    small_png(picture)


def report_screenshot(run: Path, picture: Path) -> str:
    """The report's player at its last frame (the run's last snapshot), the canvas alone."""
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        return "no report screenshot: the playwright package is missing (pip install playwright)"
    if chromium is None:
        return "no report screenshot: no chromium on PATH (Debian: apt-get install chromium)"
    page_path = run / "report.html"
    if not page_path.is_file():
        return f"no report screenshot: {page_path} is missing (run `granular report {run}` first)"
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, args=["--no-sandbox", "--disable-gpu"])
        try:
            # The player's canvas is the window's width less 620 CSS pixels: 400 here.
            page = browser.new_page(viewport={"width": 620 + SIZE, "height": 900}, device_scale_factor=1)
            page.goto(page_path.resolve().as_uri())
            page.wait_for_selector("#grains[data-ready='1']", timeout=20000)
            page.focus("#frame")
            page.keyboard.press("End")
            grains = page.locator("#grains")
            grains.screenshot(path=str(picture))
            small_png(picture)
            info = grains.evaluate("c => [c.dataset.frame, c.dataset.time, c.dataset.drawn, c.width, c.height]")
        finally:
            browser.close()
    frame, time, drawn, width, height = info
    return f"report player: frame {frame}, t = {float(time):g}, {drawn} grains drawn, {width} x {height} -> {picture}"


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    run = Path(sys.argv[1])
    folder = Path(sys.argv[2]) if len(sys.argv) > 2 else Path(__file__).resolve().parents[1] / "docs/figures/trajectory"
    folder.mkdir(parents=True, exist_ok=True)
    print(f"ovito {ovito.version_string}")
    print("| file | frames | particles | cell | properties | time | picture |")
    print("|---|---|---|---|---|---|---|")
    pipelines = {}
    for key, (name, fmt) in FORMATS.items():
        pipeline = open_format(run, name, fmt)
        last = pipeline.source.num_frames - 1
        pipelines[key] = (pipeline, last)
        print(describe(key, name, pipeline, last))
    status = 0
    for key, (pipeline, last) in pipelines.items():
        picture = folder / f"ovito-{key}.png"
        try:
            render(pipeline, last, picture)
        except RuntimeError as e:
            print(f"could not render {key}: {e}")
            status = 1
            continue
        print(f"rendered frame {last} of {key} to {picture} ({picture.stat().st_size // 1024} KB)")
    print(report_screenshot(run, folder / "report-player.png"))
    return status


if __name__ == "__main__":
    sys.exit(main())
