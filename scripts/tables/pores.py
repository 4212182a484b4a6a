#!/usr/bin/env python3
"""The void-space tables of docs/BENCHMARKS.md: the cost of `analyze --pores`, and the void
space of packings made by different jamming protocols from the same starts.

Usage:
  scripts/tables/pores.py cost [--packbench BIN] [--out DIR] [--sizes 1000,10000,100000]
  scripts/tables/pores.py protocols [--packbench BIN] [--out DIR] [--N 1000] [--methods adam,mls,calippso]
                                    [--set METHOD.KEY=VALUE]... [--chain] [--dists mono,lognormal]

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

protocols --chain (for N = 10^4, where calippso from the φ = 0.05 start takes days): adam and
mls each by `RAYON_NUM_THREADS=1 packbench pack --method M --N N --Ndim 3 --dist D --seed 1
--no-force-balance --output DIR/chain_D_N/M` from the same start as compare's seed 1 (mls with
--save-interval 5e8, so a stopped run goes on with `--resume` when the script is run again),
then calippso from the mls packing (`pack --method calippso --file mls.txt`); the wall s of the
calippso row is its own leg, the mls leg's is on the mls row.

Prints one Markdown table. Runs are kept in DIR (default packbench-tables/) and reused.
"""

import argparse
import csv
import json
import os
import statistics
from pathlib import Path

from common import run, run_timed, timed_pack


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


def method_settings(settings, method):
    """The `--set KEY=VALUE` arguments of `method` among METHOD.KEY=VALUE settings."""
    return [arg for kv in settings if kv.startswith(f"{method}.") for arg in ("--set", kv.split(".", 1)[1])]


def chain_rows(pb, folder, n, dist, settings):
    """{method: (row with phi, z_nonrattler, iso_gap, runtime_s; packing path)}: adam and mls
    packed from the start of seed 1, calippso from the mls packing (see --chain)."""
    folder.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    scene = ["--N", str(n), "--Ndim", "3", "--seed", "1"] + dist
    legs = [("adam", scene, []), ("mls", scene, ["--save-interval", "500000000"]),
            ("calippso", ["--file", str(folder / "mls.txt"), "--seed", "1"], [])]
    rows = {}
    for method, start, extra in legs:
        name = folder / method
        record = Path(f"{name}.json")
        r = json.loads(record.read_text()) if record.exists() else None
        if r is None or r["termination"] == "interrupted":
            checkpoint = Path(f"{name}.checkpoint.json")
            args = (["--resume", str(checkpoint)] if checkpoint.exists()
                    else ["--method", method] + start + extra + method_settings(settings, method))
            r, _, _ = timed_pack([pb, "pack"] + args + ["--quiet", "--no-force-balance", "--output", str(name)],
                                 folder, method, env)
        rows[method] = (dict(r["metrics"], runtime_s=r["runtime_s"]), Path(f"{name}.txt"))
    return rows


def compare_rows(pb, folder, n, methods, dist, settings):
    """{method: (runs.csv row, packing path)} of one `compare` of every method from one start."""
    if not (folder / "runs.csv").exists():
        run([pb, "compare", "--methods", ",".join(methods), "--N", str(n), "--Ndim", "3", "--seeds", "1",
             "--seed", "1", "--jobs", "1", "--quiet", "--out", str(folder), "--pores"] + dist
            + [arg for kv in settings for arg in ("--set", kv)])
    return {r["method"]: (r, folder / "packings" / f"{r['method']}_seed1.txt")
            for r in csv.DictReader(open(folder / "runs.csv"))}


# (label, tag, flags) of the size distributions of the protocols table.
DISTRIBUTIONS = [("mono", "mono", ["--dist", "mono", "--d", "1"]),
                 ("lognormal σ = 0.2", "lognormal", ["--dist", "lognormal-mean1", "--sigma", "0.2"])]


def protocols(pb, out, n, methods, settings, chain, dists):
    print("| dist | method | φ | z' | iso_gap | wall s | local φ mean ± std | σ_v/⟨v⟩ | S_v | faces | D_i | D_f "
          "| ⟨pore⟩ | ⟨throat⟩ | ℓ_void | 4(1 − φ)/s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, tag, dist in DISTRIBUTIONS:
        if tag not in dists:
            continue
        if chain:
            rows = chain_rows(pb, out / f"chain_{tag}_{n}", n, dist, settings)
        else:
            rows = compare_rows(pb, out / f"cmp_{tag}_{n}", n, methods, dist, settings)
        for method in (["adam", "mls", "calippso"] if chain else methods):
            r, packing = rows[method]
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
    ap.add_argument("--dists", default="mono,lognormal", help="of mono, lognormal")
    ap.add_argument("--chain", action="store_true", help="adam and mls by pack, calippso from the mls packing")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    if a.table == "cost":
        cost(a.packbench, a.out, [int(s) for s in a.sizes.split(",")])
    else:
        protocols(a.packbench, a.out, a.N, a.methods.split(","),
                  a.set if a.set is not None else ["adam.protocol=pressure"], a.chain, a.dists.split(","))


if __name__ == "__main__":
    main()
