#!/usr/bin/env python3
"""The φ_RCP prediction tables of docs/BENCHMARKS.md (Structure): Desmond–Weeks and Farr–Groot
against packbench's measured φ_J, and against Baranau & Tallarek (2014) Table 4.

Usage:
  scripts/tables/rcp_prediction.py measured [--packbench BIN] [--out DIR] [--N 2000] [--mls SIGMA=FILE]...
  scripts/tables/rcp_prediction.py baranau CSV [--packbench BIN]

BIN defaults to $PACKBENCH, else target/release/packbench.

measured: for σ = 0, 0.1, 0.2, 0.3 (diameter std at mean 1), `packbench pack --method adam --N N
--Ndim 3 --dist lognormal-mean1 --sigma σ --seed 1 --no-force-balance` (σ = 0: `--dist mono --d 1`
at N = 1000), then `packbench analyze PACKING --structure --no-force-balance`, whose
`structure.rcp_prediction` gives δ, skewness and both predictions from the packing's own
diameters. Each --mls SIGMA=FILE adds a row for a packing made elsewhere (the MLS runs of record
at N = 10^4, hours each).

baranau: CSV is the table (`sigma,phi_lt,phi_rcp,…`, e.g.
crates/bench/data/published/baranau2014_table4.csv). Desmond–Weeks from the exact moments of the lognormal of diameter
std σ at mean 1 (δ = σ, S = (e^{s²} + 2)√(e^{s²} − 1) with s² = ln(1 + σ²)); Farr–Groot from
`packbench predict --dist lognormal-mean1 --sigma σ --N 100000` (10^5 drawn diameters).

Prints one Markdown table.
"""

import argparse
import csv
import json
import math
import os
import sys
from functools import partial
from pathlib import Path

from common import run

run = partial(run, env=dict(os.environ, RAYON_NUM_THREADS="1"))  # every command on one thread


def measured(pb, out, n, mls):
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for sigma in ("0", "0.1", "0.2", "0.3"):
        size = 1000 if sigma == "0" else n
        dist = ["--dist", "mono", "--d", "1"] if sigma == "0" else ["--dist", "lognormal-mean1", "--sigma", sigma]
        name = out / f"adam_rcp_{size}_sigma{sigma}"
        if not Path(f"{name}.txt").exists():
            run([pb, "pack", "--method", "adam", "--N", str(size), "--Ndim", "3", "--seed", "1", "--quiet",
                 "--no-force-balance", "--output", str(name)] + dist)
        rows.append((sigma, f"adam, N = {size}", Path(f"{name}.txt")))
    for item in mls:
        sigma, path = item.split("=", 1)
        rows.append((sigma, "MLS (file)", Path(path)))
    print("| σ | packing | δ (sample) | skewness | φ_J | Desmond–Weeks | DW − φ_J | Farr–Groot | FG − φ_J |")
    print("|---|---|---|---|---|---|---|---|---|")
    for sigma, label, path in rows:
        s = json.loads(run([pb, "analyze", str(path), "--structure", "--no-force-balance"]))["structure"]
        p, phi = s["rcp_prediction"], s["phi"]
        print(f"| {sigma} | {label} | {p['polydispersity']:.4f} | {p['skewness']:.3f} | {phi:.4f} "
              f"| {p['desmond_weeks']:.4f} | {p['desmond_weeks'] - phi:+.4f} "
              f"| {p['farr_groot']:.4f} | {p['farr_groot'] - phi:+.4f} |", flush=True)


def baranau(pb, table):
    lines = [line for line in open(table) if not line.startswith("#")]
    print("| σ | S | Desmond–Weeks | Farr–Groot | φ_LT | φ_RCP | DW − φ_RCP | FG − φ_RCP |")
    print("|---|---|---|---|---|---|---|---|")
    for r in csv.DictReader(lines):
        sigma = float(r["sigma"])
        s2 = math.log(1 + sigma * sigma)
        skew = (math.exp(s2) + 2) * math.sqrt(math.exp(s2) - 1)
        dw = 0.634 + 0.0658 * sigma + 0.0857 * skew * sigma * sigma
        dist = ["--dist", "mono", "--d", "1"] if sigma == 0 else ["--dist", "lognormal-mean1", "--sigma", r["sigma"]]
        fg = json.loads(run([pb, "predict", "--N", "100000", "--Ndim", "3"] + dist))["farr_groot"]
        rcp = float(r["phi_rcp"])
        print(f"| {r['sigma']} | {skew:.3f} | {dw:.4f} | {fg:.4f} | {float(r['phi_lt']):.4f} | {rcp:.4f} "
              f"| {dw - rcp:+.4f} | {fg - rcp:+.4f} |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("table", choices=["measured", "baranau"])
    ap.add_argument("csv", nargs="?", help="baranau: the published table")
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--N", type=int, default=2000)
    ap.add_argument("--mls", action="append", default=[], metavar="SIGMA=FILE")
    a = ap.parse_args()
    if a.table == "measured":
        measured(a.packbench, a.out, a.N, a.mls)
    elif not a.csv:
        sys.exit("baranau needs the published table: rcp_prediction.py baranau CSV")
    else:
        baranau(a.packbench, a.csv)


if __name__ == "__main__":
    main()
