#!/usr/bin/env python3
"""The "Cost of `analyze --structure`" table of docs/BENCHMARKS.md.

Usage:
  scripts/tables/structure_cost.py [--packbench BIN] [--out DIR] [--sizes 1000,10000,100000]
                                   [--forces-up-to 100000]

BIN defaults to $PACKBENCH, else target/release/packbench. For each N, the packing is
`packbench pack --method adam --protocol pressure --N N --Ndim 3 --seed 1 --quiet
--no-force-balance --output DIR/adamN` (the packings of the void-space table, reused when
present), then `packbench analyze DIR/adamN.txt --structure --no-force-balance` and, up to
--forces-up-to, `packbench analyze DIR/adamN.txt --structure` (the force-balance QP solved once,
shared by the metrics and P(f); see
crates/core/src/analysis/force_balance/mod.rs for its three solvers), each timed by GNU time on one thread (RAYON_NUM_THREADS=1).
The S(k) columns: wave vectors summed and allowed, and the largest measured relative standard
error of a bin (the default target ε = 0.03).
"""

import argparse
import json
import os
from functools import partial
from pathlib import Path

from common import run, run_timed

ENV = dict(os.environ, RAYON_NUM_THREADS="1")
run = partial(run, env=ENV)  # every command on one thread


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--sizes", default="1000,10000,100000")
    ap.add_argument("--forces-up-to", type=int, default=100000)
    a = ap.parse_args()
    pb, out = a.packbench, a.out
    out.mkdir(parents=True, exist_ok=True)
    print("| N (adam, 3D mono) | forces | CPU s | peak RSS | S(k) vectors summed / allowed "
          "| largest S(k) relative error |")
    print("|---|---|---|---|---|---|")
    for n in (int(s) for s in a.sizes.split(",")):
        packing = out / f"adam{n}.txt"
        if not packing.exists():
            run([pb, "pack", "--method", "adam", "--protocol", "pressure", "--N", str(n), "--Ndim", "3",
                 "--seed", "1", "--quiet", "--no-force-balance", "--output", str(out / f"adam{n}")])
        cases = [("no", ["--no-force-balance"])] + ([("yes", [])] if n <= a.forces_up_to else [])
        for label, extra in cases:
            args = ["analyze", str(packing), "--structure"] + extra
            text, _, cpu, rss = run_timed([pb] + args, out / f"adam{n}.structure-time.txt", ENV)
            m = json.loads(text)
            sk = m["structure"]["structure_factor"]
            print(f"| {n} | {label} | {cpu:.2f} | {round(rss / 1024)} MB "
                  f"| {sum(sk['vectors'])} / {sum(sk['vectors_in_bin'])} "
                  f"| {sk['max_relative_error']:.3f} |", flush=True)


if __name__ == "__main__":
    main()
