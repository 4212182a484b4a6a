#!/usr/bin/env python3
"""The per-method tables of docs/BENCHMARKS.md (fire, ls, mls, closest-jammed, calippso,
seq-fill), the Memory table and its bounded runs, from `packbench init` and `packbench pack`.

Usage:
  scripts/tables/methods.py TABLE [--packbench BIN] [--out DIR] [--n-small N] [--n-large N]
                                  [--mls-bound K]

TABLE is one of: adam, fire, ls, mls, closest-jammed, calippso, seq-fill, memory, bounded.
BIN defaults to $PACKBENCH, else target/release/packbench.

The scenes: 3D monodisperse (D = 1) and 2D bidisperse 50:50 with diameters 1 : 1.4, periodic
unit box, φ = 0.05 (`packbench init ... --seed S`); seeds 1, 2, 3 at N = 10^3 (--n-small) and
seed 1 at N = 10^4 (--n-large). Each run is

  RAYON_NUM_THREADS=1 packbench pack --method M --file START --seed S --no-force-balance --quiet

with START the init file, or for closest-jammed and calippso the adam or mls output of the same
seed. CPU time (user + sys) and peak resident memory are those of the pack process alone, from
GNU time (/usr/bin/time; a child of Python itself would inherit the interpreter's resident
set in its peak). Every run is kept in DIR (default packbench-tables/) with its timing beside it
(NAME.time.json) and reused when present, so `memory` after the method tables costs nothing
new. Prints one Markdown table.

`bounded` times the runs that stand for the hours-long methods at N = 10^4 in the Memory
table: mls for --mls-bound collisions (default 5e7), calippso for one LP and closest-jammed for
1000 steps from the adam packing of the same start.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from common import timed_pack

SCENES = {
    "3D mono": (["--Ndim", "3", "--dist", "mono", "--d", "1"], "m3"),
    "2D bi 1:1.4": (["--Ndim", "2", "--dist", "bidisperse", "--d1", "1", "--d2", "1.4", "--p", "0.5"], "b2"),
}
ORDER = ["adam", "fire", "ls", "mls", "closest-jammed", "calippso", "seq-fill"]


def rows_of(table, small, large):
    """The rows (scene, start, N, seeds) of a method's table, as recorded in BENCHMARKS.md."""
    plain = [(s, "init", n, seeds) for s in SCENES for n, seeds in ((small, [1, 2, 3]), (large, [1]))]
    if table in ("adam", "fire", "ls", "seq-fill"):
        return plain
    if table == "mls":
        # 3D at N = 10^3 is about 4 CPU min per seed; 10^4 takes hours (runs of record).
        return [("3D mono", "init", small, [1]), ("2D bi 1:1.4", "init", small, [1, 2, 3])]
    if table in ("closest-jammed", "calippso"):
        return [("3D mono", "adam", small, [1, 2, 3]), ("3D mono", "mls", small, [1]),
                ("2D bi 1:1.4", "adam", small, [1, 2, 3]), ("2D bi 1:1.4", "mls", small, [1, 2, 3])]
    sys.exit(f"unknown table {table}")


class Runner:
    def __init__(self, pb, out):
        self.pb, self.out = pb, out
        self.env = dict(os.environ, RAYON_NUM_THREADS="1")
        out.mkdir(parents=True, exist_ok=True)

    def start(self, scene, n, seed):
        flags, tag = SCENES[scene]
        path = self.out / f"{tag}_{n}_s{seed}.txt"
        if not path.exists():
            subprocess.run([self.pb, "init", "--N", str(n), "--phi", "0.05", "--seed", str(seed),
                            "--output", str(path)] + flags, check=True, capture_output=True)
        return path

    def pack(self, method, scene, start, n, seed, extra=(), label=""):
        """Runs (or reuses) one pack; returns its record with cpu_s and rss_kb added."""
        start_file = (self.start(scene, n, seed) if start == "init"
                      else self.out / (self.pack(start, scene, "init", n, seed)["name"] + ".txt"))
        name = f"{SCENES[scene][1]}_{n}_s{seed}_{start}_{method}{label}"
        timing = self.out / f"{name}.time.json"
        if timing.exists():
            return json.loads(timing.read_text())
        cmd = [self.pb, "pack", "--method", method, "--file", str(start_file), "--seed", str(seed),
               "--no-force-balance", "--quiet", "--output", str(self.out / name)] + list(extra)
        meta, cpu, rss_kb = timed_pack(cmd, self.out, name, self.env)
        shown = [c.replace(f"{self.out}/", "") for c in cmd[1:]]
        r = dict(name=name, cmd=" ".join(shown), cpu_s=cpu, rss_kb=rss_kb,
                 steps=meta["steps"], termination=meta["termination"], metrics=meta["metrics"])
        timing.write_text(json.dumps(r, indent=1))
        return r


def mb(kb):
    return round(kb / 1024)


def method_row(method, scene, start, runs):
    ms = [r["metrics"] for r in runs]
    phis = [m["phi"] for m in ms]
    phi = f"{phis[0]:.6f}" if len(phis) == 1 else f"{statistics.mean(phis):.6f} ± {statistics.stdev(phis):.1e}"
    jammed = [m for m in ms if m["n_dof"] > 0 and m["rattlers"] < m["n"]]
    if not jammed:
        z, iso = "—", "— (all rattlers)"
    else:
        zs = [m["z_nonrattler"] for m in ms]
        z = f"{zs[0]:.3f}" if len(zs) == 1 else f"{statistics.mean(zs):.3f} ± {statistics.stdev(zs):.3f}"
        iso = ", ".join(f"{m['iso_gap']} / {m['n_dof']}" for m in ms)
    cpu = ", ".join(f"{r['cpu_s']:.2f}" for r in runs)
    ns = sorted({m["n"] for m in ms})
    n = str(ns[0]) if len(ns) == 1 else "/".join(str(m["n"]) for m in ms)
    return (f"| {scene} | {'φ = 0.05' if start == 'init' else start + ' packing'} | {n} | {len(runs)} | {phi} | {z} "
            f"| {iso} | {max(m['max_overlap'] for m in ms):.1e} | {cpu} "
            f"| {', '.join(str(r['steps']) for r in runs)} | {mb(max(r['rss_kb'] for r in runs))} "
            f"| {', '.join(sorted({r['termination'] for r in runs}))} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("table", choices=ORDER + ["memory", "bounded"])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--n-small", type=int, default=1000)
    ap.add_argument("--n-large", type=int, default=10000)
    ap.add_argument("--mls-bound", type=int, default=50_000_000)
    a = ap.parse_args()
    run = Runner(a.packbench, a.out)
    small, large = a.n_small, a.n_large

    if a.table in ORDER:
        print("| scene | start | N | seeds | φ | z' | iso_gap / n_dof | max overlap | CPU s per run "
              "| steps per run | peak RSS MB | ended by |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for scene, start, n, seeds in rows_of(a.table, small, large):
            runs = [run.pack(a.table, scene, start, n, s) for s in seeds]
            print(method_row(a.table, scene, start, runs), flush=True)
        return

    bounded = {
        "mls": ("init", ["--max-steps", str(a.mls_bound)], f"_max{a.mls_bound}"),
        "calippso": ("adam", ["--max-steps", "1"], "_max1"),
        "closest-jammed": ("adam", ["--max-steps", "1000"], "_max1000"),
    }
    if a.table == "bounded":
        print("| method | bounded run (3D mono, seed 1) | CPU s | progress | peak RSS MB |")
        print("|---|---|---|---|---|")
        for method, (start, extra, label) in bounded.items():
            r = run.pack(method, "3D mono", start, large, 1, extra, label)
            print(f"| {method} | `{r['cmd']}` | {r['cpu_s']:.1f} | {r['steps']} steps, φ {r['metrics']['phi']:.6f} "
                  f"| {mb(r['rss_kb'])} |", flush=True)
        return

    # memory: the largest peak RSS over the seeds of each method's rows; the hours-long methods
    # at N = 10^4 by their bounded runs (3D only).
    print(f"| method | N = {small}, 3D | N = {small}, 2D | N = {large}, 3D | N = {large}, 2D |")
    print("|---|---|---|---|---|")
    for method in ORDER:
        cells = []
        for n in (small, large):
            for scene in SCENES:
                if method in bounded and n == large:
                    if scene == "3D mono":
                        start, extra, label = bounded[method]
                        cells.append(f"{mb(run.pack(method, scene, start, n, 1, extra, label)['rss_kb'])} MB (bounded run)")
                    else:
                        cells.append("—")
                    continue
                rows = [r for r in rows_of(method, small, large) if r[0] == scene and r[2] == n]
                if not rows:
                    cells.append("—")
                    continue
                per_start = [max(run.pack(method, scene, start, n, s)["rss_kb"] for s in seeds)
                             for _, start, _, seeds in rows]
                cells.append(" / ".join(f"{mb(k)} MB" for k in per_start))
        label = method + (" (from adam / mls)" if method in ("closest-jammed", "calippso") else "")
        print(f"| {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
