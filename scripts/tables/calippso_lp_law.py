#!/usr/bin/env python3
"""How calippso's LP count grows with N, for each kind of start (docs/BENCHMARKS.md, calippso).

Usage:
  scripts/tables/calippso_lp_law.py [--packbench BIN] [--out DIR] [--sizes 500,1000,2000,4000]
                                    [--seeds 1,2,3] [--starts adam,ls,ls7,mls,mls7] [--figure PNG]
                                    [--made-only]

BIN defaults to $PACKBENCH, else target/release/packbench.

Starts (3D monodisperse, periodic unit box, the scene `packbench pack` builds from the flags,
one thread, `--no-force-balance`):
  adam  `pack --method adam --N N --Ndim 3 --seed S` (RCPGenerator 1.0's schedule, φ ≈ 0.64)
  ls    `pack --method ls --N N --Ndim 3 --seed S --rate 0.1 --pressure-cap 1e6` (fast LS)
  ls7   `pack --method ls --N N --Ndim 3 --seed S --rate 0.003 --pressure-cap 1e7` (LS compressed
        slowly until a window's pressure, still the growth's, reaches 1e7: φ ≈ 0.645 at N = 1000,
        where CALiPPSO.jl's example start at N = 1024 has 0.6440)
  mls   `pack --method mls --N N --Ndim 3 --seed S` (MLS, reduced pressure 1e12)
  mls7  `pack --method mls --N N --Ndim 3 --seed S --rate-initial 0.003 --pressure-cap 1e7
        --rate-final 1e-5` (ls7's compression, then MLS's stages held at reduced pressure 1e7:
        the pressure of a packing that has relaxed at zero growth, not of one still growing)
Each start is refined by

  RAYON_NUM_THREADS=1 packbench pack --method calippso --file START --seed S --no-force-balance

timed by GNU time (CPU = user + sys). Recorded per run: the LPs to convergence (`lp_count`),
the contacts changed per LP after the first (`contacts_changed` of the trace: the first LP
forms the network), the CPU time, φ before and after, and the termination. Runs that did not
converge are listed and left out of the fit.

The law: for each start kind, a least-squares line through (log N, log LPs) of every
converged run, LPs ≈ a·N^b, printed with b's standard error; and the same line through the
whole chain's CPU (the start's run time from its sidecar, one thread, plus calippso's CPU),
CPU ≈ c·N^e, with the N where the adam and mls chains cost the same: the crossover that
`compare --refine exact` uses (crates/bench/src/refinement.rs). --figure draws LPs and chain
CPU against N on log axes (needs matplotlib).

Every run is kept in DIR (default packbench-tables/lp-law) and reused when present; with
--made-only the runs not yet in DIR are skipped instead of made (to fit a grid made in parts).
Prints two Markdown tables: the runs, and the fit.
"""

import argparse
import json
import math
import os
import statistics
from pathlib import Path

from common import read_times, run, timed_pack

# Each start kind: its `pack` flags and its marker in the figure.
START_KINDS = {
    "adam": (["--method", "adam"], "o"),
    "ls": (["--method", "ls", "--rate", "0.1", "--pressure-cap", "1e6"], "s"),
    "ls7": (["--method", "ls", "--rate", "0.003", "--pressure-cap", "1e7"], "D"),
    "mls": (["--method", "mls"], "^"),
    "mls7": (["--method", "mls", "--rate-initial", "0.003", "--pressure-cap", "1e7", "--rate-final", "1e-5"], "v"),
}


def start(pb, out, kind, n, seed, env):
    """The start file of `kind` at N = n and `seed`, made once."""
    path = out / f"{kind}{n}_s{seed}.txt"
    if not path.exists():
        run([pb, "pack"] + START_KINDS[kind][0] + ["--N", str(n), "--Ndim", "3", "--seed", str(seed),
            "--quiet", "--no-force-balance", "--output", str(path.with_suffix(""))], env)
    return path


def refine(pb, out, kind, n, seed, env):
    """calippso from that start: a dict of what the tables show."""
    first = start(pb, out, kind, n, seed, env)
    name = f"calippso_{kind}{n}_s{seed}"
    record_path = out / f"{name}.json"
    if record_path.exists():
        record = json.loads(record_path.read_text())
        _, cpu, _ = read_times(out / f"{name}.time.txt")
    else:
        cmd = [pb, "pack", "--method", "calippso", "--file", str(first), "--seed", str(seed),
               "--no-force-balance", "--output", str(out / name)]
        record, cpu, _ = timed_pack(cmd, out, name, env)
    start_record = json.loads(first.with_suffix(".json").read_text())
    changed = [dict(row["values"]).get("contacts_changed") for row in record["trace"][1:]]
    changed = [c for c in changed if c is not None]
    return dict(kind=kind, n=n, seed=seed, lps=int(record["extra"]["lp_count"]), cpu=cpu,
                start_s=start_record["runtime_s"],
                changed=statistics.median(changed) if changed else float("nan"),
                phi_start=start_record["metrics"]["phi"], phi=record["metrics"]["phi"],
                termination=record["termination"])


def fit(rows, key="lps"):
    """Least squares of log `key` on log N: (a, b, standard error of b), or None under 3 points."""
    xs = [math.log(r["n"]) for r in rows]
    ys = [math.log(r[key]) for r in rows]
    if len(xs) < 3 or len(set(xs)) < 2:
        return None
    mx, my = statistics.mean(xs), statistics.mean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    a = my - b * mx
    res = sum((y - a - b * x) ** 2 for x, y in zip(xs, ys))
    se = math.sqrt(res / (len(xs) - 2) / sxx)
    return math.exp(a), b, se


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for kind, (_, marker) in START_KINDS.items():
        mine = [r for r in rows if r["kind"] == kind and r["termination"] == "converged"]
        if not mine:
            continue
        ax1.scatter([r["n"] for r in mine], [r["lps"] for r in mine], marker=marker, label=f"{kind} start")
        ax2.scatter([r["n"] for r in mine], [r["chain"] for r in mine], marker=marker, label=f"{kind} chain")
        ns = sorted({r["n"] for r in mine})
        for ax, key in ((ax1, "lps"), (ax2, "chain")):
            law = fit(mine, key)
            if law:
                a, b, _ = law
                ax.plot(ns, [a * n ** b for n in ns], linestyle="--", label=f"{kind}: N^{b:.2f}")
    for ax, label in ((ax1, "LPs to convergence"), (ax2, "start + calippso CPU s (one core)")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("N (3D monodisperse)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    fig.suptitle("calippso: LPs and the whole chain's CPU against N, by start")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables/lp-law"))
    ap.add_argument("--sizes", default="500,1000,2000,4000")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--starts", default=",".join(START_KINDS))
    ap.add_argument("--figure", type=Path, default=None)
    ap.add_argument("--made-only", action="store_true", help="skip runs not yet in DIR")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    print("| start | N | seed | φ start | φ_J | LPs | median contacts changed per LP | CPU s | ended |")
    print("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for kind in a.starts.split(","):
        for n in (int(s) for s in a.sizes.split(",")):
            for seed in (int(s) for s in a.seeds.split(",")):
                if a.made_only and not (a.out / f"calippso_{kind}{n}_s{seed}.json").exists():
                    continue
                r = refine(a.packbench, a.out, kind, n, seed, env)
                rows.append(r)
                print(f"| {kind} | {n} | {seed} | {r['phi_start']:.6f} | {r['phi']:.6f} | {r['lps']} "
                      f"| {r['changed']:g} | {r['cpu']:.1f} | {r['termination']} |", flush=True)
    for r in rows:
        r["chain"] = r["start_s"] + r["cpu"]
    print("\n| start | converged runs | LPs ≈ a·N^b: a | b ± SE | mean LPs at the largest N |")
    print("|---|---|---|---|---|")
    for kind in a.starts.split(","):
        mine = [r for r in rows if r["kind"] == kind and r["termination"] == "converged"]
        law = fit(mine)
        top = max((r["n"] for r in mine), default=None)
        at_top = statistics.mean(r["lps"] for r in mine if r["n"] == top) if top else float("nan")
        if law:
            print(f"| {kind} | {len(mine)} | {law[0]:.3g} | {law[1]:.2f} ± {law[2]:.2f} | {at_top:.0f} (N = {top}) |")
        else:
            print(f"| {kind} | {len(mine)} | — | — | — |")
    print("\n| chain | converged runs | CPU s ≈ c·N^e: c | e ± SE |")
    print("|---|---|---|---|")
    laws = {}
    for kind in a.starts.split(","):
        mine = [r for r in rows if r["kind"] == kind and r["termination"] == "converged"]
        law = fit(mine, "chain")
        if law:
            laws[kind] = law
            print(f"| {kind} → calippso | {len(mine)} | {law[0]:.3g} | {law[1]:.2f} ± {law[2]:.2f} |")
    if "adam" in laws and "mls" in laws and laws["adam"][1] != laws["mls"][1]:
        (ca, ea, _), (cm, em, _) = laws["adam"], laws["mls"]
        cross = (cm / ca) ** (1.0 / (ea - em))
        print(f"\nThe adam and mls chains cost the same CPU at N ≈ {cross:.0f}.")
    if a.figure:
        figure(rows, a.figure)


if __name__ == "__main__":
    main()
