#!/usr/bin/env python3
"""The "Against rcptools" table of docs/BENCHMARKS.md: packbench design and rcptools on the
densest two-component 3D mixture with D_max/D_min <= 10 at N = 1000, five searches per tool.

Usage:
  scripts/tables/design_against_rcptools.py OUT

OUT is the folder examples/design/against_rcptools.sh filled: packbench-S/ (a design folder)
and packbench-S.time, rcptools-S.log (its RESULT line) and rcptools-S.time, for each search seed
S. Prints one row per search and one summary row per tool: the best candidate's φ_J in the
search, its φ_J on 3 fresh confirmation seeds (mean ± sample std), the packings, and the CPU
time (user + sys of the whole command, GNU time).
"""

import json
import re
import statistics
import sys
from pathlib import Path


def cpu(path):
    m = re.search(r"([0-9.]+) user ([0-9.]+) sys ([0-9.]+) wall", path.read_text())
    if not m:
        sys.exit(f"{path}: no GNU time line")
    return float(m[1]) + float(m[2])


def packbench(out, seed):
    best = json.loads((out / f"packbench-{seed}" / "best.json").read_text())
    report = (out / f"packbench-{seed}" / "report.md").read_text()
    m = re.search(r"Search: .*?, (\d+) packings; (\d+) confirmation", report, re.S)
    params = " ".join(f"{n}={v:.3g}" for n, v in zip(best["names"], best["values"]))
    return {
        "answer": params,
        "search_phi": best["search_phi"],
        "confirm_phi": best["confirm_phi"],
        "packings": int(m[1]) + int(m[2]),
        "cpu": cpu(out / f"packbench-{seed}.time"),
    }


def rcptools(out, seed):
    log = (out / f"rcptools-{seed}.log").read_text()
    m = re.search(r"^RESULT (.*)$", log, re.M)
    if not m:
        sys.exit(f"rcptools-{seed}.log: no RESULT line (the search did not finish)")
    r = json.loads(m[1])
    return {
        "answer": "θ = " + " ".join(f"{x:.3g}" for x in r["theta"]),
        "search_phi": r["search_phi"],
        "confirm_phi": r["confirm_phi"],
        "packings": r["packings"],
        "cpu": cpu(out / f"rcptools-{seed}.time"),
    }


def mean_std(xs):
    return statistics.mean(xs), (statistics.stdev(xs) if len(xs) > 1 else 0.0)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    seeds = sorted(int(p.name.split("-")[1]) for p in out.glob("packbench-*") if p.is_dir())
    print("| tool | search seed | best φ_J (search) | confirmed φ_J (3 fresh seeds) | packings | CPU s |")
    print("|---|---|---|---|---|---|")
    summary = {}
    for name, read in [("packbench", packbench), ("rcptools", rcptools)]:
        rows = []
        for s in seeds:
            try:
                rows.append(read(out, s))
            except (FileNotFoundError, SystemExit) as e:
                print(f"| {name} | {s} | not finished ({e}) | | | |")
                continue
            r = rows[-1]
            m, sd = mean_std(r["confirm_phi"])
            print(f"| {name} | {s} | {r['search_phi']:.4f} | {m:.4f} ± {sd:.4f} | {r['packings']} | {r['cpu']:.0f} |")
        if rows:
            summary[name] = rows
    print()
    print("| tool | searches | best confirmed φ_J | confirmed φ_J over the searches (mean ± std) | packings per search | CPU s per search (mean) |")
    print("|---|---|---|---|---|---|")
    for name, rows in summary.items():
        confirmed = [statistics.mean(r["confirm_phi"]) for r in rows]
        m, sd = mean_std(confirmed)
        print(f"| {name} | {len(rows)} | {max(confirmed):.4f} | {m:.4f} ± {sd:.4f} | "
              f"{', '.join(str(p) for p in sorted({r['packings'] for r in rows}))} | "
              f"{statistics.mean(r['cpu'] for r in rows):.0f} |")


if __name__ == "__main__":
    main()
