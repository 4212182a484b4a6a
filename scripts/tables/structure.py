#!/usr/bin/env python3
"""The structure tables of docs/BENCHMARKS.md ("Structure of packbench's jammed packings" and
"Structure at N ≈ 10⁴"): one row per packing from `packbench analyze FILE --structure`.

Usage:
  scripts/tables/structure.py [--packbench BIN] [--out DIR] [--N 1000] [--poisson 10000]
                              [--no-build] [--no-forces] [ROW]...

BIN defaults to $PACKBENCH, else target/release/packbench. Unless --no-build, the script makes
and analyses, seed 1, 3D monodisperse:

  adam       packbench pack --method adam --N N --Ndim 3 --seed 1 --no-force-balance
  calippso   packbench pack --method calippso --file ADAM.txt --seed 1 --no-force-balance
  Poisson    packbench init --N P --Ndim 3 --phi 0.64 --placement poisson --seed 1 (analysed
             without forces: points that overlap have none)

Each ROW is LABEL=FILE, or LABEL=FILE@ARGS with extra `analyze` arguments separated by spaces
(e.g. "seq-fill=seqfill.txt@--walls 1,1,1 --no-force-balance"), for packings made elsewhere
(an interrupted MLS run, a large N). The analysis runs with the force balance (θ needs the
forces) unless --no-forces; one thread (RAYON_NUM_THREADS=1). Prints one Markdown table with the
defaults' fits (S(k→0) and χ̃(k→0) from the linear fit over k·D̄ ≤ 4, θ over f/⟨f⟩ ∈ [0.01, 0.3],
γ over h ∈ [1e-5, 1e-2]; fit sample counts in brackets).
"""

import argparse
import json
import os
from functools import partial
from pathlib import Path

from common import run

ENV = dict(os.environ, RAYON_NUM_THREADS="1")
run = partial(run, env=ENV)  # every command on one thread


def fmt(x, spec):
    return "" if x is None else format(x, spec)


def row(pb, label, path, extra):
    m = json.loads(run([pb, "analyze", str(path), "--structure"] + extra))
    s = m["structure"]
    sk, f, g = s.get("structure_factor") or {}, s.get("forces") or {}, s.get("gaps") or {}
    theta = f"{f['theta']:.2f} ({f['fit_samples']})" if f.get("theta") is not None else ""
    gamma = f"{g['gamma']:.2f} ({g['fit_samples']})" if g.get("gamma") is not None else ""
    dw = (s.get("rcp_prediction") or {}).get("desmond_weeks")
    return (f"| {label} | {m['n']} | {m['phi']:.4f} | {m['iso_gap']} | {fmt(sk.get('s_k0'), '.4f')} "
            f"| {fmt(sk.get('chi_k0'), '.4f')} | {fmt(s.get('q4'), '.4f')} | {fmt(s.get('q6'), '.4f')} "
            f"| {fmt(s.get('psi6'), '.4f')} | {fmt(s.get('local_mean'), '.4f')} "
            f"| {fmt(s.get('crystal_fraction'), '.4f')} | {theta} | {gamma} | {fmt(dw, '.4f')} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("rows", nargs="*", metavar="ROW")
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables"))
    ap.add_argument("--N", type=int, default=1000)
    ap.add_argument("--poisson", type=int, default=10000)
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--no-forces", action="store_true")
    a = ap.parse_args()
    pb, out = a.packbench, a.out
    out.mkdir(parents=True, exist_ok=True)
    forces = ["--no-force-balance"] if a.no_forces else []
    rows = []
    if not a.no_build:
        adam, cal, poisson = out / f"structure_adam{a.N}", out / f"structure_calippso{a.N}", out / f"poisson{a.poisson}"
        if not Path(f"{adam}.txt").exists():
            run([pb, "pack", "--method", "adam", "--N", str(a.N), "--Ndim", "3", "--seed", "1", "--quiet",
                 "--no-force-balance", "--output", str(adam)])
        if not Path(f"{cal}.txt").exists():
            run([pb, "pack", "--method", "calippso", "--file", f"{adam}.txt", "--seed", "1", "--quiet",
                 "--no-force-balance", "--output", str(cal)])
        if not Path(f"{poisson}.txt").exists():
            run([pb, "init", "--N", str(a.poisson), "--Ndim", "3", "--phi", "0.64", "--placement", "poisson",
                 "--seed", "1", "--output", f"{poisson}.txt"])
        rows += [("calippso", f"{cal}.txt", forces), ("adam", f"{adam}.txt", forces),
                 ("Poisson points", f"{poisson}.txt", ["--no-force-balance"])]
    for spec in a.rows:
        label, rest = spec.split("=", 1)
        path, _, args = rest.partition("@")
        extra = args.split()
        rows.append((label, path, extra + [f for f in forces if f not in extra]))
    print("| packing | N | φ | iso_gap | s_k0 | χ̃_k0 | Q4 | Q6 | ψ6 | mean local q6 (ψ6) | crystal-like "
          "| θ (n) | γ (n) | DW φ_RCP |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, path, extra in rows:
        print(row(pb, label, path, extra), flush=True)


if __name__ == "__main__":
    main()
