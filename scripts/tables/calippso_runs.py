#!/usr/bin/env python3
"""The calippso option tables of docs/BENCHMARKS.md: the displacement bound's schedule, and the
warm-started interior point against cold starts.

Usage:
  scripts/tables/calippso_runs.py TABLE [--packbench BIN] [--out DIR] [--n-small N] [--n-large N]

TABLE is bound-schedule or warm-start. BIN defaults to $PACKBENCH, else
target/release/packbench.

Starts (3D monodisperse, periodic unit box, from the scene flags as `packbench pack` builds
them): `pack --method adam --N N --Ndim 3 --seed S`, `pack --method ls --N N --Ndim 3 --seed 3`
("fast LS") and `pack --method mls --N N --Ndim 3 --seed 1`. Each calippso run is

  RAYON_NUM_THREADS=1 packbench pack --method calippso --file START --seed S --no-force-balance [OPTIONS]

timed by GNU time (CPU = user + sys, peak resident memory), and its output is checked by
`packbench analyze --contact-tol 1e-9` (with the force-balance residual).

bound-schedule: the adam (S = 1), fast-LS (S = 3) and MLS (S = 1) starts at N = --n-small
(1000), each with `--bound-schedule seed` and `trust-region`.
warm-start: adam starts at N = --n-large (4000), seeds 81–83; seeds 1–7 at --n-small summed;
the fast-LS start; each with `--set warm_start=false` (cold) and the default (warm).

Every run is kept in DIR (default packbench-tables/) and reused when present. Prints one
Markdown table.
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

from common import timed_pack


class Runner:
    def __init__(self, pb, out):
        self.pb, self.out = pb, out
        self.env = dict(os.environ, RAYON_NUM_THREADS="1")
        out.mkdir(parents=True, exist_ok=True)

    def timed(self, name, args):
        """`packbench pack ARGS --output DIR/name`, once; returns its record with cpu_s and rss_kb."""
        cached = self.out / f"{name}.time.json"
        if cached.exists():
            return json.loads(cached.read_text())
        cmd = [self.pb, "pack"] + args + ["--quiet", "--output", str(self.out / name)]
        meta, cpu, rss = timed_pack(cmd, self.out, name, self.env)
        r = dict(cpu_s=cpu, rss_kb=rss, steps=meta["steps"], extra=meta["extra"],
                 termination=meta["termination"], phi=meta["metrics"]["phi"], file=str(self.out / f"{name}.txt"))
        a = subprocess.run([self.pb, "analyze", r["file"], "--contact-tol", "1e-9"], capture_output=True, text=True)
        if a.returncode != 0:
            sys.exit(f"packbench analyze {r['file']} failed: {a.stderr.strip()}")
        r["exact"] = json.loads(a.stdout)
        cached.write_text(json.dumps(r, indent=1))
        return r

    def start(self, method, n, seed):
        return self.timed(f"{method}_{n}_s{seed}", ["--method", method, "--N", str(n), "--Ndim", "3",
                                                    "--seed", str(seed), "--no-force-balance"])

    def calippso(self, start_method, n, seed, options, label):
        start = self.start(start_method, n, seed)
        return self.timed(f"{start_method}_{n}_s{seed}_calippso_{label}",
                          ["--method", "calippso", "--file", start["file"], "--seed", str(seed),
                           "--no-force-balance"] + options)


def ipm_per_solve(r):
    e = r["extra"]
    return e["lp_iterations"] / e["lp_solves"] if e.get("lp_solves") else float("nan")


def exact(r):
    m = r["exact"]
    fb = m.get("force_balance")
    return (f"iso_gap {m['iso_gap']} / {m['n_dof']}, overlap {m['max_overlap']:.1e}, "
            f"force balance {fb:.1e}" if fb is not None else f"iso_gap {m['iso_gap']} / {m['n_dof']}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("table", choices=["bound-schedule", "warm-start"])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--n-small", type=int, default=1000)
    ap.add_argument("--n-large", type=int, default=4000)
    a = ap.parse_args()
    run = Runner(a.packbench, a.out)
    small, large = a.n_small, a.n_large

    if a.table == "bound-schedule":
        print("| start | schedule | LPs | CPU s | φ_J | iso_gap / n_dof | max overlap | force balance "
              "| bound switches | peak RSS MB |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for label, method, seed in (("adam", "adam", 1), ("fast LS", "ls", 3), ("MLS", "mls", 1)):
            for schedule in ("seed", "trust-region"):
                r = run.calippso(method, small, seed, ["--bound-schedule", schedule], schedule)
                m = r["exact"]
                fb = m.get("force_balance")
                print(f"| {label}, N = {small} | {schedule} | {r['steps']} | {r['cpu_s']:.1f} | {r['phi']:.10f} "
                      f"| {m['iso_gap']} / {m['n_dof']} | {m['max_overlap']:.1e} "
                      f"| {'—' if fb is None else f'{fb:.1e}'} | {r['extra'].get('bound_switches', '—')} "
                      f"| {round(r['rss_kb'] / 1024)} |", flush=True)
        return

    cold, warm = (["--set", "warm_start=false"], "cold"), ([], "warm")
    print("| N, seed | cold: LPs, CPU s, IPM iterations/solve | warm: LPs, CPU s, IPM iterations/solve "
          "| φ_J cold / warm | warm output at contact tol 1e-9 |")
    print("|---|---|---|---|---|")
    for method, n, seed, label in [("adam", large, s, f"{large}, {s}") for s in (81, 82, 83)] + [
            ("ls", small, 3, f"{small}, fast LS (seed 3)")]:
        c, w = (run.calippso(method, n, seed, *opt) for opt in (cold, warm))
        print(f"| {label} | {c['steps']}, {c['cpu_s']:.1f}, {ipm_per_solve(c):.1f} "
              f"| {w['steps']}, {w['cpu_s']:.1f}, {ipm_per_solve(w):.1f} | {c['phi']:.10f} / {w['phi']:.10f} "
              f"| {exact(w)} |", flush=True)
    pairs = [tuple(run.calippso("adam", small, s, *opt) for opt in (cold, warm)) for s in range(1, 8)]
    same = sum(f"{c['phi']:.10f}" == f"{w['phi']:.10f}" for c, w in pairs)
    print(f"| {small}, seeds 1–7 (sum) | {sum(c['steps'] for c, _ in pairs)}, {sum(c['cpu_s'] for c, _ in pairs):.1f} "
          f"| {sum(w['steps'] for _, w in pairs)}, {sum(w['cpu_s'] for _, w in pairs):.1f} "
          f"| equal to 10 digits for {same} of 7 seeds | — |", flush=True)


if __name__ == "__main__":
    main()
