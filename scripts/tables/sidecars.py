#!/usr/bin/env python3
"""A table of runs of record from their JSON sidecars: the hour-long runs of docs/BENCHMARKS.md
(MLS, calippso and closest-jammed at N = 10^4 and above), whose commands the page gives, are
tabulated by this script from what `packbench pack --output NAME` wrote.

Usage:
  scripts/tables/sidecars.py NAME.json [NAME.json ...] [--contact-tol 1e-9] [--packbench BIN]

Per sidecar one row: method, N, φ, iso_gap / n_dof, rattlers, max overlap, force balance (as
the run's analysis reported them), steps (the method's unit: collisions for mls, LPs for
calippso), wall s and termination. With --contact-tol T the packing NAME.txt is analysed again
by `packbench analyze --contact-tol T --no-force-balance` and its iso_gap / n_dof and rattlers
replace the run's (exact methods are judged at 1e-9). BIN defaults to $PACKBENCH, else
target/release/packbench.
"""

import argparse
import json
import os
from pathlib import Path

from common import run


def fmt(x, spec):
    return "—" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sidecars", nargs="+", type=Path)
    ap.add_argument("--contact-tol", type=float)
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    a = ap.parse_args()
    tol = f" (contact tol {a.contact_tol:g})" if a.contact_tol else ""
    print(f"| run | method | N | φ | iso_gap / n_dof{tol} | rattlers | max overlap | force balance | steps "
          "| wall s | termination |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for path in a.sidecars:
        r = json.loads(path.read_text())
        m = r["metrics"]
        if a.contact_tol:
            again = json.loads(run([a.packbench, "analyze", str(path.with_suffix(".txt")), "--no-force-balance",
                                    "--contact-tol", str(a.contact_tol)]))
            m = dict(m, iso_gap=again["iso_gap"], n_dof=again["n_dof"], rattlers=again["rattlers"])
        print(f"| {path.stem} | {r['method']} | {m['n']} | {m['phi']:.6f} | {m['iso_gap']} / {m['n_dof']} "
              f"| {m['rattlers']} | {fmt(m.get('max_overlap'), '.1e')} | {fmt(m.get('force_balance'), '.1e')} "
              f"| {r['steps']:,} | {r['runtime_s']:.0f} | {r['termination']} |")


if __name__ == "__main__":
    main()
