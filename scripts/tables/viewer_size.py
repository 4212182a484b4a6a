#!/usr/bin/env python3
"""The "Page size" and "Load time" tables of docs/BENCHMARKS.md (Viewer): the size of `packbench
view`'s page for packings of 300, 10^4 and 10^5 spheres, and with --loads K the time each page
takes to draw in headless Chromium.

Usage:
  scripts/tables/viewer_size.py [--packbench BIN] [--out DIR] [--N-large 10000] [--tiles 10]
                                [--loads K] [--chromium chromium]

BIN defaults to $PACKBENCH, else target/release/packbench. The packings:

  packbench pack --method fire --N 300 --Ndim 3 --dist bidisperse --d1 1 --d2 1.4 --p 0.5 --seed 2 --output run300
  packbench pack --method fire --N 10000 --Ndim 3 --dist mono --d 1 --seed 1 --max-steps 3000 --output run10k

and the second tiled --tiles times along x (a periodic box, so still a valid packing), each
drawn by `packbench view RUN.json --no-force-balance --output RUN.html`. Contacts from
`packbench analyze`; "of which three.js" is the base64 size of the vendored three.js and
OrbitControls (crates/bench/assets/three/) that every page embeds. Sizes in MiB.

Load time (--loads K > 0): each page loaded K times by `chromium --headless --use-angle=swiftshader
--enable-unsafe-swiftshader --window-size=1200,800 --dump-dom file://…/RUN.html`, a fresh profile
each time; the time is the page's own `data-load-ms` (navigation to drawn, `performance.now()`),
read from the dumped DOM. Software WebGL: the GPU of a desktop draws faster.
"""

import argparse
import json
import os
import re
import subprocess
import tempfile
from pathlib import Path

from common import run

THREE = Path(__file__).resolve().parents[2] / "crates" / "bench" / "assets" / "three"


def tile(src, dst, tiles):
    """Writes dst.txt and dst.json: the packing of src repeated `tiles` times along x."""
    record = json.loads(Path(f"{src}.json").read_text())
    lx = record["container"]["lengths"][0]
    rows = [line.split() for line in open(f"{src}.txt") if line.strip() and not line.startswith("#")]
    with open(f"{dst}.txt", "w") as f:
        for k in range(tiles):
            for r in rows:
                f.write(" ".join([repr(float(r[0]) + k * lx)] + r[1:]) + "\n")
    record["container"]["lengths"][0] = lx * tiles
    record["trace"] = []
    Path(f"{dst}.json").write_text(json.dumps(record))


def load_ms(chromium, page):
    """Milliseconds from navigation to the drawn page (its `data-load-ms`), one fresh load."""
    with tempfile.TemporaryDirectory() as profile:
        dom = subprocess.run(
            [chromium, "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
             "--ignore-gpu-blocklist", "--no-first-run", "--window-size=1200,800",
             f"--user-data-dir={profile}", "--dump-dom", f"file://{page.resolve()}"],
            capture_output=True, text=True, timeout=600).stdout
    m = re.search(r'<html[^>]*\sdata-load-ms="(\d+)"', dom)
    ready = re.search(r'<html[^>]*\sdata-ready="1"', dom)
    return int(m.group(1)) if m and ready else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--N-large", type=int, default=10000)
    ap.add_argument("--tiles", type=int, default=10)
    ap.add_argument("--loads", type=int, default=0, help="page loads per page for the load-time table")
    ap.add_argument("--chromium", default="chromium")
    a = ap.parse_args()
    pb, out = a.packbench, a.out
    out.mkdir(parents=True, exist_ok=True)
    three = sum((THREE / f).stat().st_size for f in ("three.module.min.js", "OrbitControls.js")) * 4 / 3
    small = ["--method", "fire", "--N", "300", "--Ndim", "3", "--dist", "bidisperse", "--d1", "1", "--d2", "1.4",
             "--p", "0.5", "--seed", "2"]
    large = ["--method", "fire", "--N", str(a.N_large), "--Ndim", "3", "--dist", "mono", "--d", "1", "--seed", "1",
             "--max-steps", "3000"]
    rows = []
    for name, args in (("run300", small), (f"run{a.N_large}", large)):
        if not (out / f"{name}.json").exists():
            run([pb, "pack"] + args + ["--quiet", "--no-force-balance", "--output", str(out / name)])
        rows.append((name, f"`pack {' '.join(args)}`"))
    tiled = f"run{a.N_large}x{a.tiles}"
    tile(out / f"run{a.N_large}", out / tiled, a.tiles)
    rows.append((tiled, f"the {a.N_large} packing tiled {a.tiles} times along x"))
    print("| N | packing | contacts | page | of which three.js |")
    print("|---|---|---|---|---|")
    counts = {}
    for name, label in rows:
        m = json.loads(run([pb, "analyze", str(out / f"{name}.txt"), "--no-force-balance"]
                           + ["--box", ",".join(str(v) for v in json.loads((out / f"{name}.json").read_text())
                                                ["container"]["lengths"])]))
        run([pb, "view", str(out / f"{name}.json"), "--no-force-balance", "--output", str(out / f"{name}.html")])
        page = (out / f"{name}.html").stat().st_size
        counts[name] = m["n"]
        print(f"| {m['n']} | {label} (φ = {m['phi']:.4f}) | {m['contacts']} | {page / 2**20:.2f} MB "
              f"| {three / 2**20:.2f} MB |", flush=True)
    if a.loads > 0:
        print(f"\n| N | page | load to drawn, ms ({a.loads} fresh loads) |")
        print("|---|---|---|")
        for name, _ in rows:
            page = out / f"{name}.html"
            times = [load_ms(a.chromium, page) for _ in range(a.loads)]
            shown = ", ".join("not drawn" if t is None else str(t) for t in times)
            print(f"| {counts[name]} | {page.stat().st_size / 2**20:.2f} MB | {shown} |", flush=True)


if __name__ == "__main__":
    main()
