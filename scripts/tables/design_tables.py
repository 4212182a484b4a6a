#!/usr/bin/env python3
"""The Design tables of docs/BENCHMARKS.md: the two searches of the worked example and the
screen's error, condensed from each search's report.md.

Usage:
  scripts/tables/design_tables.py OUT [--run] [--packbench BIN]

--run first runs `PACKBENCH=BIN bash examples/design/worked_example.sh OUT` (about 4 CPU minutes
on 2 cores), keeping its GNU time lines in OUT/times.log; without it OUT must hold an earlier
run. BIN defaults to $PACKBENCH, else target/release/packbench. Prints, per search (OUT/lognormal,
OUT/mixture), the table of its answer, then one table of the Desmond–Weeks and Farr–Groot RMS
errors against the packed φ_J over each search's packed candidates (the "predictor" table of
its report.md).
"""

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "design" / "worked_example.sh"
SEARCHES = ["lognormal", "mixture"]


def grab(pattern, text, what):
    m = re.search(pattern, text, re.S)
    if not m:
        sys.exit(f"report.md: no {what} (pattern {pattern!r})")
    return m.groups()


def cpu_times(out):
    """{search: (wall s, user CPU s)} from OUT/times.log, empty without it."""
    log = out / "times.log"
    if not log.exists():
        return {}
    times = {}
    for name, wall, user in re.findall(r"(\w+): ([0-9.]+) s wall, ([0-9.]+) s user CPU", log.read_text()):
        times[name] = (float(wall), float(user))
    return times


def answer_table(out, name, times):
    report = (out / name / "report.md").read_text()
    (objective,) = grab(r"Objective: (.*?)\.\n", report, "objective")
    (scored,) = grab(r"Scored by (.*?)\n", report, "scoring")
    cand, skipped, packings, confirms = grab(
        r"Search: (\d+) candidates, (\d+) skipped.*?, (\d+) packings; (\d+) confirmation", report, "search line")
    (stopped,) = grab(r"Stopped: (.*?)\.?\n", report, "stop")
    (best,) = grab(r"## Best distribution\n\n(.*?)\.?\n", report, "best")
    (search_phi,) = grab(r"φ_J over the search seeds: ([0-9]+\.[0-9]+)", report, "search φ_J")
    (confirmed,) = grab(r"Confirmation with \d+ fresh seeds: φ_J = ([0-9.]+ ± [0-9.]+)", report, "confirmation")
    print(f"**{name}**: {objective}; scored by {scored}\n")
    print("| | |")
    print("|---|---|")
    print(f"| candidates | {cand}, {skipped} skipped by the screen or the ratio bound |")
    print(f"| packings | {packings} in the search + {confirms} confirmations |")
    print(f"| best | {best} |")
    print(f"| φ_J over the search seeds | {search_phi} |")
    print(f"| φ_J over {confirms} fresh seeds | **{confirmed}** (mean ± sample std) |")
    if name in times:
        wall, user = times[name]
        print(f"| CPU time | {user:.0f} s user for the whole command ({wall:.0f} s wall) |")
    print(f"| stopped | {stopped} |\n")


def screen_table(out):
    print("| search | candidates | Desmond–Weeks RMS | Farr–Groot RMS |")
    print("|---|---|---|---|")
    for name in SEARCHES:
        report = (out / name / "report.md").read_text()
        dw = grab(r"\| Desmond–Weeks \| (\d+) \| ([0-9.]+) \|", report, "Desmond–Weeks row")
        fg = grab(r"\| Farr–Groot \| (\d+) \| ([0-9.]+) \|", report, "Farr–Groot row")
        print(f"| {name} | {dw[0]} | {dw[1]} | {fg[1]} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--run", action="store_true")
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    a = ap.parse_args()
    if a.run:
        a.out.mkdir(parents=True, exist_ok=True)
        env = dict(os.environ, PACKBENCH=str(Path(a.packbench).resolve()))
        with open(a.out / "times.log", "w") as log:
            subprocess.run(["bash", str(EXAMPLE), str(a.out)], env=env, stderr=log, check=True)
    times = cpu_times(a.out)
    for name in SEARCHES:
        answer_table(a.out, name, times)
    screen_table(a.out)


if __name__ == "__main__":
    main()
