#!/usr/bin/env python3
"""Renders two `packbench export` files with OVITO, off screen (Tachyon, no GPU needed), for
README's export paragraph: a jammed 3D packing with walls on x and z (LAMMPS dump: its cell
and pp/ff flags) and a jammed 2D packing with walls on y (extended XYZ, read as 2D).

Usage: VENV/bin/python scripts/render_exports.py [OUT_DIR]   (default docs/figures)
Needs the `ovito` module (pip install ovito; crates/python/tests/run.sh puts it in the test
environment), which renders through a Vulkan loader even with Tachyon (Debian: apt-get install
libvulkan1 mesa-vulkan-drivers, a software driver), and a release `packbench` binary:
PACKBENCH_BIN, else CARGO_TARGET_DIR's or target/'s release build.
"""

import os
import pathlib
import subprocess
import sys
import tempfile

from ovito.io import import_file
from ovito.modifiers import ColorCodingModifier
from ovito.vis import TachyonRenderer, Viewport
from PIL import Image

REPO = pathlib.Path(__file__).resolve().parents[1]
TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
PACKBENCH = os.environ.get("PACKBENCH_BIN", str(TARGET / "release" / "packbench"))

# name: (size flags of init, container flags of init and pack, export format, camera direction)
SCENES = {
    "export_walled_3d": (["--N", "400", "--Ndim", "3"], ["--walls", "1,0,1"], "lammps-dump",
                         (-1.0, -1.6, -0.9)),
    "export_2d": (["--N", "300", "--Ndim", "2"], ["--walls", "0,1"], "xyz", None),
}
SIZE = (560, 420)


def packbench(*args):
    subprocess.run([PACKBENCH, *map(str, args)], check=True, capture_output=True, text=True)


def render(name, size, container, fmt, direction, out_dir, work):
    start, jammed, exported = work / f"{name}_start.txt", work / f"{name}.txt", work / f"{name}.{fmt}"
    packbench("init", *size, *container, "--dist", "bidisperse", "--d1", "1", "--d2", "1.4", "--p", "0.5",
              "--seed", "3", "--output", start)
    packbench("pack", "--method", "fire", "--file", start, *container, "--seed", "3",
              "--output", jammed)
    # The container comes from the sidecar pack wrote beside the packing.
    packbench("export", jammed, "--format", fmt, "--output", exported)
    pipeline = import_file(str(exported))
    pipeline.modifiers.append(ColorCodingModifier(property="Radius", gradient=ColorCodingModifier.Viridis()))
    pipeline.add_to_scene()
    cell_vis = pipeline.compute().cell.vis
    cell_vis.rendering_color = (0.1, 0.1, 0.1)
    cell_vis.line_width = pipeline.compute().cell[0, 0] * 0.006
    if direction is None:
        viewport = Viewport(type=Viewport.Type.Top)
    else:
        viewport = Viewport(type=Viewport.Type.Perspective, camera_dir=direction)
    viewport.zoom_all(size=SIZE)
    png = out_dir / f"{name}.png"
    viewport.render_image(size=SIZE, filename=str(png), background=(1, 1, 1),
                          renderer=TachyonRenderer(ambient_occlusion=direction is not None))
    pipeline.remove_from_scene()
    # A 128-colour palette keeps each figure well under 200 KB.
    Image.open(png).convert("RGB").quantize(colors=128).save(png, optimize=True)
    print(f"{png}: {png.stat().st_size // 1024} KB")


def main():
    out_dir = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "docs" / "figures"
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for name, (size, container, fmt, direction) in SCENES.items():
            render(name, size, container, fmt, direction, out_dir, pathlib.Path(tmp))


if __name__ == "__main__":
    main()
