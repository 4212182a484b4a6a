#!/usr/bin/env python3
"""The "Published values" tables of docs/BENCHMARKS.md, condensed from `packbench reproduce`'s
reports: Baranau & Tallarek 2014 Table 4 by σ, and one row per other publication, each value with
the band its published file fixes and whether the recomputation lies inside it.

Usage:
  scripts/tables/published.py OUT [--run NAME,...] [--N 1000] [--seeds 3] [--jobs 1] [--packbench BIN]

--run NAME,... first runs `packbench reproduce NAME --N N --seeds S --jobs J --quiet --out
OUT/NAME` under GNU time (CPU = user + system of the whole command, in OUT/NAME.time.txt) for
each name (baranau2014-table4 takes about 50 CPU minutes at N = 10³; the others 2 s–2 min).
Then, for every OUT/NAME holding a report.md: Table 4 as published φ_LT / φ_RCP beside the
lowest / highest φ_J of the seeds (± its bootstrap standard error) and every seed's φ_J (the
refined φ of runs.csv); the others as "published → recomputed (mean ± SE)" per case and
quantity. BIN defaults to $PACKBENCH, else target/release/packbench.
"""

import argparse
import csv
import os
import re
from collections import defaultdict
from pathlib import Path

from common import read_times, run_timed

TABLE4 = "baranau2014-table4"
OTHERS = ["desmond-weeks-2014", "dimensions", "dimensions-adam", "ohern-2003", "3drsp-2022"]


def report_rows(folder):
    """[(case, quantity, published, band, recomputed, verdict)] of report.md's results table."""
    rows = []
    for line in (folder / "report.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 7 and line.startswith("| ") and cells[0] != "case" and not cells[0].startswith("---"):
            rows.append((cells[0], cells[1], cells[2], cells[3], cells[4], cells[6]))
    return rows


def cpu_of(out, name):
    times = out / f"{name}.time.txt"
    return f"{read_times(times)[1]:.0f} s" if times.exists() else "not timed"


def table4(out):
    folder = out / TABLE4
    by_case = defaultdict(dict)
    for case, quantity, published, band, recomputed, verdict in report_rows(folder):
        by_case[case][quantity] = (f"{published} {band}", f"{recomputed.split(' (')[0]} {verdict}")
    phis = defaultdict(list)
    with open(folder / "runs.csv") as f:
        for r in csv.DictReader(f):
            phi = r["refined_phi"] or r["phi"]
            phis[r["case"]].append(f"{float(phi):.4f}")
    print(f"Baranau & Tallarek 2014, Table 4, {cpu_of(out, TABLE4)} CPU:\n")
    print("| σ | φ_LT published [band] | lowest of the seeds, verdict | φ_RCP published [band] | highest of the seeds, verdict | every φ_J |")
    print("|---|---|---|---|---|---|")
    for case, q in by_case.items():
        lt, rcp = q.get("φ_LT", ("—", "—")), q.get("φ_RCP", ("—", "—"))
        sigma = case.removeprefix("σ = ")
        print(f"| {sigma} | {lt[0]} | {lt[1]} | {rcp[0]} | {rcp[1]} | {' '.join(phis[case])} |")
    print()


def others(out, names):
    print("| publication | CPU | published [band] → recomputed (mean ± SE) verdict, per case |")
    print("|---|---|---|")
    for name in names:
        parts = []
        for case, quantity, published, band, recomputed, verdict in report_rows(out / name):
            if recomputed.startswith("not run") or band == "—":
                continue
            parts.append(f"{case} {quantity}: {published} {band} → {recomputed.split(' (')[0]} {verdict}")
        print(f"| `reproduce {name}` | {cpu_of(out, name)} | {'; '.join(parts)} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--run", default="")
    ap.add_argument("--N", type=int, default=1000)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    for name in filter(None, a.run.split(",")):
        cmd = [a.packbench, "reproduce", name, "--seeds", str(a.seeds), "--jobs", str(a.jobs), "--quiet",
               "--out", str(a.out / name)]
        if name != "3drsp-2022":  # its cubes set their own N
            cmd[3:3] = ["--N", str(a.N)]
        run_timed(cmd, a.out / f"{name}.time.txt")
    if (a.out / TABLE4 / "report.md").exists():
        table4(a.out)
    present = [n for n in OTHERS if (a.out / n / "report.md").exists()]
    if present:
        others(a.out, present)


if __name__ == "__main__":
    main()
