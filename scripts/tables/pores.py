#!/usr/bin/env python3
"""The void-space tables of docs/BENCHMARKS.md: the cost of `analyze --pores`, and the void
space of packings made by different jamming protocols from the same starts.

Usage:
  scripts/tables/pores.py cost [--packbench BIN] [--out DIR] [--sizes 1000,10000,100000]
  scripts/tables/pores.py protocols [--packbench BIN] [--out DIR] [--N 1000] [--methods adam,mls,calippso]
                                    [--set METHOD.KEY=VALUE]...

BIN defaults to $PACKBENCH, else target/release/packbench.

cost: for each N, `RAYON_NUM_THREADS=1 packbench pack --method adam --protocol pressure --N N
--Ndim 3 --seed 1 --quiet --no-force-balance` (the pressure protocol was adam's default when the
table was made), then `packbench analyze adamN.txt --no-force-balance --pores` timed by GNU time
(wall, user + sys, peak resident memory). Σ V_cell / V − 1 checks that the radical Voronoi
cells fill the unit box.

protocols: for 3D monodisperse and 3D lognormal (diameter std 0.2 at mean 1), `packbench
compare --methods METHODS --N N --Ndim 3 --dist D --seeds 1 --seed 1 --jobs 1 --quiet --out
DIR/cmp_D --pores` (every method from the same φ = 0.05 start; φ, z', iso_gap and the run's
wall time from its runs.csv), then `packbench analyze --no-force-balance --pores` on each of its
packings. Lengths in units of the packing's mean diameter. --set is passed to compare (default:
adam.protocol=pressure, the protocol of the recorded table).

Prints one Markdown table. Runs are kept in DIR (default packbench-tables/) and reused.
"""

import argparse
import csv
import json
import os
import statistics
from pathlib import Path

from common import run, run_timed


def analyze(pb, path, timed=False):
    """`packbench analyze PATH --no-force-balance --pores`: (metrics, (wall, cpu, rss_kb) or None)."""
    cmd = [pb, "analyze", str(path), "--no-force-balance", "--pores"]
    if not timed:
        return json.loads(run(cmd)), None
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    out, wall, cpu, rss = run_timed(cmd, Path(f"{path}.pores-time.txt"), env)
    return json.loads(out), (wall, cpu, rss)


def mean_diameter(path):
    ds = [float(line.replace(",", " ").split()[-1]) for line in open(path)
          if line.strip() and not line.lstrip().startswith("#")]
    return statistics.mean(ds)


def cost(pb, out, sizes):
    print("| N (adam, 3D mono) | φ | wall s | CPU s (user + sys) | peak RSS | pores / throats | Σ V_cell / V − 1 |")
    print("|---|---|---|---|---|---|---|")
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    for n in sizes:
        packing = out / f"adam{n}.txt"
        if not packing.exists():
            run([pb, "pack", "--method", "adam", "--protocol", "pressure", "--N", str(n), "--Ndim", "3",
                 "--seed", "1", "--quiet", "--no-force-balance", "--output", str(out / f"adam{n}")], env)
        m, (wall, cpu, rss) = analyze(pb, packing, timed=True)
        p = m["pores"]
        print(f"| {n} | {m['phi']:.6f} | {wall:.2f} | {cpu:.2f} | {round(rss / 1024)} MB "
              f"| {p['pores']} / {p['throats']} | {m['voronoi']['total_volume'] - 1:.1e} |", flush=True)


def protocols(pb, out, n, methods, settings):
    print("| dist | method | φ | z' | iso_gap | wall s | local φ mean ± std | σ_v/⟨v⟩ | S_v | faces | D_i | D_f "
          "| ⟨pore⟩ | ⟨throat⟩ | ℓ_void | 4(1 − φ)/s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, tag, dist in (("mono", "mono", ["--dist", "mono", "--d", "1"]),
                             ("lognormal σ = 0.2", "lognormal", ["--dist", "lognormal-mean1", "--sigma", "0.2"])):
        folder = out / f"cmp_{tag}_{n}"
        if not (folder / "runs.csv").exists():
            run([pb, "compare", "--methods", ",".join(methods), "--N", str(n), "--Ndim", "3", "--seeds", "1",
                 "--seed", "1", "--jobs", "1", "--quiet", "--out", str(folder), "--pores"] + dist
                + [arg for kv in settings for arg in ("--set", kv)])
        rows = {r["method"]: r for r in csv.DictReader(open(folder / "runs.csv"))}
        for method in methods:
            r = rows[method]
            packing = folder / "packings" / f"{method}_seed1.txt"
            m, _ = analyze(pb, packing)
            d = mean_diameter(packing)
            v, p, c = m["voronoi"], m["pores"], m["chords"]
            print(f"| {label} | {method} | {float(r['phi']):.6f} | {float(r['z_nonrattler']):.3f} | {r['iso_gap']} "
                  f"| {float(r['runtime_s']):.1f} | {v['local_phi_mean']:.4f} ± {v['local_phi_std']:.4f} "
                  f"| {v['volume_std_relative']:.4f} | {v['volume_entropy']:.3f} | {v['faces_mean']:.2f} "
                  f"| {p['included_sphere_diameter'] / d:.3f} | {p['free_sphere_diameter'] / d:.3f} "
                  f"| {p['pore_size_mean'] / d:.4f} | {p['throat_size_mean'] / d:.4f} "
                  f"| {c['void']['mean'] / d:.4f} ± {c['void']['mean_error'] / d:.4f} "
                  f"| {c['void_mean_predicted'] / d:.4f} |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("table", choices=["cost", "protocols"])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--sizes", default="1000,10000,100000")
    ap.add_argument("--N", type=int, default=1000)
    ap.add_argument("--methods", default="adam,mls,calippso")
    ap.add_argument("--set", action="append", default=None, metavar="METHOD.KEY=VALUE")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    if a.table == "cost":
        cost(a.packbench, a.out, [int(s) for s in a.sizes.split(",")])
    else:
        protocols(a.packbench, a.out, a.N, a.methods.split(","),
                  a.set if a.set is not None else ["adam.protocol=pressure"])


if __name__ == "__main__":
    main()
