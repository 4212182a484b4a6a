#!/usr/bin/env python3
"""The kernel table of docs/BENCHMARKS.md ("Kernels"): criterion benches and the event engine's
collision rate, measured now on this machine, one row per kernel.

Usage:
  scripts/tables/kernels.py [--skip-bench] [--skip-events] [--N-events 10000]

Runs, from the repository root:
  cargo bench -p packbench-core --bench cell_list
  cargo bench -p packbench-adam --bench jam -- forces
  RAYON_NUM_THREADS=1 cargo bench -p packbench-adam --bench jam -- neighbor_upkeep
  cargo build --release -p packbench-mls --examples
  RAYON_NUM_THREADS=1 target/release/examples/collision_rate N dense
then reads criterion's estimates (target/criterion/GROUP/BENCH/new/estimates.json: the mean
and its 95 % confidence interval, wall time) and the example's printed rates (per CPU second),
and prints one Markdown table with the commit it measured. --skip-bench reuses the estimates
criterion left from an earlier run; --skip-events leaves out the event-engine rows.

Criterion measures wall time: run it on an otherwise quiet machine.
"""

import argparse
import json
import os
import re
import subprocess
import sys
from pathlib import Path

from common import run

CRITERION = Path("target/criterion")

# (criterion group, bench, kernel, case): the rows, in the order of the table.
BENCHES = [
    ("cell_list", "near_pairs_mono_3d_1e5_phi0.6", "cell list, pair build (`cell_list`)",
     "N = 10⁵ mono spheres, φ = 0.6, periodic, skin 0.1 D"),
    ("cell_list", "near_pairs_powerlaw_1_15_3d_15000_phi0.6", "cell list, pair build (`cell_list`)",
     "power law 1–15, exponent −3, N = 15 000, box 1 × 0.5 × 1, walls on y"),
    ("forces_3d_mono_phi064", "n10000_one_thread", "soft-sphere force loop (`jam -- forces`)",
     "3D mono, φ = 0.64, N = 10⁴, one thread"),
    ("forces_3d_mono_phi064", "n10000_all_threads", "soft-sphere force loop (`jam -- forces`)",
     "3D mono, φ = 0.64, N = 10⁴, every core"),
    ("forces_3d_mono_phi064", "n100000_one_thread", "soft-sphere force loop (`jam -- forces`)",
     "3D mono, φ = 0.64, N = 10⁵, one thread"),
    ("forces_3d_mono_phi064", "n100000_all_threads", "soft-sphere force loop (`jam -- forces`)",
     "3D mono, φ = 0.64, N = 10⁵, every core"),
] + [
    ("neighbor_upkeep_n10000_1pc_moved", f"{scene}_{mode}",
     f"adam's neighbour upkeep, {how} (`jam -- neighbor_upkeep`)",
     f"{case}, N = 10⁴, 1 % moved 0.6 skin, one thread")
    for scene, case in [("powerlaw_1_15_walls", "power law 1–15, walls on y, φ = 0.6"),
                        ("mono_3d", "3D mono, φ = 0.64")]
    for mode, how in [("whole_build", "whole build"), ("refresh_rows", "movers' rows")]
]

# (label printed by collision_rate, case).
EVENT_ROWS = [
    ("ls rate 1", "LS γ = 1 from a Poisson start to p = 1e12"),
    ("equilibrium", "equilibrium fluid at φ = 0.55 (100 N collisions)"),
    ("ls rate 0.03", "LS γ = 0.03 from the same start to p = 1e12 (whole run)"),
]


def time_text(ns):
    """A duration in ns as µs or ms with three significant figures."""
    return f"{ns / 1e6:.3g} ms" if ns >= 1e6 else f"{ns / 1e3:.3g} µs"


def criterion_row(group, bench):
    """(mean ns, lower, upper) of criterion's last run of GROUP/BENCH, or None."""
    path = CRITERION / group / bench / "new" / "estimates.json"
    if not path.exists():
        return None
    mean = json.loads(path.read_text())["mean"]
    ci = mean["confidence_interval"]
    return mean["point_estimate"], ci["lower_bound"], ci["upper_bound"]


def event_rows(n):
    """{label: collisions per CPU second} from the collision_rate example at N = n."""
    subprocess.run(["cargo", "build", "--release", "-p", "packbench-mls", "--examples"], check=True,
                   stdout=sys.stderr)
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    out = run(["target/release/examples/collision_rate", str(n), "dense"], env)
    rates = {}
    for line in out.splitlines():
        label = line.split(":")[0].split(" phi")[0].strip()
        m = re.search(r"collisions_per_cpu_s ([0-9.e+-]+)", line)
        if m:
            rates[label] = float(m.group(1))
    return rates


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skip-bench", action="store_true")
    ap.add_argument("--skip-events", action="store_true")
    ap.add_argument("--N-events", type=int, default=10000)
    a = ap.parse_args()
    if not a.skip_bench:
        # Criterion's own report goes to stderr, so that stdout is the table alone.
        subprocess.run(["cargo", "bench", "-p", "packbench-core", "--bench", "cell_list"], check=True,
                       stdout=sys.stderr)
        subprocess.run(["cargo", "bench", "-p", "packbench-adam", "--bench", "jam", "--", "forces"],
                       check=True, stdout=sys.stderr)
        subprocess.run(["cargo", "bench", "-p", "packbench-adam", "--bench", "jam", "--",
                        "neighbor_upkeep"], check=True, stdout=sys.stderr,
                       env=dict(os.environ, RAYON_NUM_THREADS="1"))
    commit = run(["git", "rev-parse", "--short", "HEAD"]).strip()
    print(f"Commit {commit}.\n")
    print("| kernel | case | time (mean, 95 % interval) or rate |")
    print("|---|---|---|")
    for group, bench, kernel, case in BENCHES:
        est = criterion_row(group, bench)
        if est is None:
            print(f"| {kernel} | {case} | not measured (no criterion estimate) |")
            continue
        mean, lo, hi = est
        print(f"| {kernel} | {case} | {time_text(mean)} ({time_text(lo)}–{time_text(hi)}) |")
    if not a.skip_events:
        rates = event_rows(a.N_events)
        for label, case in EVENT_ROWS:
            rate = rates.get(label)
            shown = f"{rate:.3g} collisions per CPU s" if rate else "not printed"
            print(f"| event engine (`collision_rate {a.N_events} dense`) | {case}, N = {a.N_events} | {shown} |")


if __name__ == "__main__":
    main()
