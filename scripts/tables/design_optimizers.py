#!/usr/bin/env python3
"""The table of CMA-ES against EGO in docs/BENCHMARKS.md (Design) from the folders that
examples/design/optimizers.sh writes: per search, the best |φ_J − target| after 8, 16 and 24
packings, the packings used until the best candidate's φ_J lies within the seed-to-seed spread
(std of the confirmation reruns of all searches of that optimiser) of the target, the answer σ,
its confirmed φ_J, and the user CPU time of the command."""
import csv
import json
import statistics
import sys
from pathlib import Path

TARGET = 0.655


def search(dir):
    """Candidates in the order proposed as (packings used through it, mean φ_J over its
    seeds), the confirmation φ_J, best.json and the CPU seconds (user + sys)."""
    rows = list(csv.DictReader(open(dir / "evaluations.csv")))
    groups = {}
    for r in rows:
        if r["kind"] == "search" and r["phi"]:
            key = (int(r["generation"]), int(r["candidate"]))
            groups.setdefault(key, []).append(float(r["phi"]))
    packed, used = [], 0
    for key in sorted(groups):
        used += len(groups[key])
        packed.append((used, statistics.mean(groups[key])))
    confirm = [float(r["phi"]) for r in rows if r["kind"] == "confirm" and r["phi"]]
    best = json.load(open(dir / "best.json"))
    wall, user, sys_ = map(float, open(str(dir) + ".time").read().split()[-3:])
    return packed, confirm, best, user + sys_


def main(out):
    out = Path(out)
    dirs = sorted(d for d in out.iterdir() if d.is_dir())
    by_opt = {}
    for d in dirs:
        by_opt.setdefault(d.name.split("-seed")[0], []).append(d)
    stds = [statistics.stdev(search(d)[1]) for d in dirs if len(search(d)[1]) > 1]
    spread = statistics.mean(stds)
    print(f"seed-to-seed spread of φ_J at the answers (mean std of 4 fresh seeds): {spread:.4f}")
    print("| optimiser | seed | best abs(φ_J − 0.655) after 8 / 16 / 24 (/ 32) packings | packings to within the spread | σ found | φ_J confirmed (4 fresh seeds) | CPU s |")
    print("|---|---|---|---|---|---|---|")
    summary = []
    for opt, ds in by_opt.items():
        sig, miss, packs, cpus = [], [], [], []
        for d in ds:
            packed, confirm, best, cpu = search(d)
            dist = [abs(phi - TARGET) for _, phi in packed]
            running = [min(dist[: i + 1]) for i in range(len(dist))]

            def at(k):
                seen = [x for (u, _), x in zip(packed, running) if u <= k]
                return f"{seen[-1]:.4f}" if seen else "–"

            within = next((u for (u, _), x in zip(packed, running) if x <= spread), None)
            cm = statistics.mean(confirm)
            cs = statistics.stdev(confirm)
            sig.append(best["values"][0])
            miss.append(abs(cm - TARGET))
            packs.append(within if within else packed[-1][0] + 1)
            cpus.append(cpu)
            print(
                f"| {opt} | {d.name.split('seed')[1]} | {' / '.join(at(k) for k in (8, 16, 24, 32) if k <= packed[-1][0])} | "
                f"{within if within else '> ' + str(packed[-1][0])} | {best['values'][0]:.4f} | "
                f"{cm:.4f} ± {cs:.4f} | {cpu:.0f} |"
            )
        summary.append(
            f"| {opt} | {len(ds)} | {statistics.mean(packs):.1f} | {statistics.mean(sig):.4f} "
            f"± {statistics.stdev(sig):.4f} | {statistics.mean(miss):.4f} | "
            f"{statistics.mean(cpus):.1f} |"
        )
    print()
    print("| optimiser | searches | mean packings to within the spread | σ found (mean ± std over searches) | mean abs(confirmed φ_J − 0.655) | mean CPU s |")
    print("|---|---|---|---|---|---|")
    print("\n".join(summary))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "design-optimizers")

