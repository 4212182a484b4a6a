#!/usr/bin/env python3
"""packbench `adam` against RCPGenerator 1.0, side by side on the same start files.

Usage:
  scripts/bench_vs_rcpgenerator.py [VENV] [--packbench BIN] [--rows ROW,ROW] [--seeds K]
                                   [--first-seed S] [--out DIR] [--method M] [--set KEY=VALUE]...
                                   [--packbench-only | --anchor-only] [--anchor-from RESULTS_JSON]

VENV is a virtual environment whose python imports `rcpgenerator` (RCPGenerator 1.0); by default
$PACKBENCH_ANCHORS/venv-rcpg (PACKBENCH_ANCHORS defaults to anchors/ at the repository root),
where scripts/anchors/build.sh builds it. For every row and seed the script writes one start file with
`packbench init` (φ = 0.05), then runs both codes on it one after the other, alternating which
goes first, each on one thread (OMP_NUM_THREADS=1 and rcpgenerator.set_num_threads(1) for the
anchor, RAYON_NUM_THREADS=1 for packbench), measures each run's CPU time (user + sys of the
child process, so time lost to other work on a shared machine is not counted), and measures both
outputs with the same ruler, `packbench analyze`. It prints one Markdown table per row and the
CPU-time ratio anchor/packbench, and writes every number to DIR/results.json. With
--packbench-only the anchor is not run (for N = 10^6, where it would take hours); such rows
have no ratio. With --anchor-only packbench is not run (its `init` still writes the start files):
the anchor's runs of a long table, made once, for later runs to reuse with --anchor-from.

Rows (name: scene):
  mono1k, mono10k, mono30k, mono100k, mono1m
                              3D monodisperse, N = 10^3, 10^4, 3·10^4, 10^5, 10^6, periodic unit box
  bi2d1k, bi2d10k             2D bidisperse 1:1.4 (50:50), N = 10^3, 10^4, periodic unit box
  lognormal1k, lognormal10k   3D lognormal, diameter std 0.2 at mean 1, N = 10^3, 10^4
  powerlaw1k, powerlaw10k, powerlaw15k
                              RCPGenerator 1.0's power law 1–15, exponent −3, N = 10^3, 10^4, 15 000,
                              box 1 × 0.5 × 1, walls on y

--preset parity runs the fidelity table: the four scenes at N = 10^3 and 10^4 (seeds 61–70) and
3D mono at N = 10^5 (seeds 61–63),
and prints each row's φ_J as mean ± standard error for both codes, their difference in
combined standard errors, the mean steps and CPU time of each code, and the CPU ratio.
--anchor-from RESULTS_JSON reuses the anchor runs of an earlier run of this script (its
results.json) on the same start files, checked byte for byte: to put another packbench protocol
beside the same anchor runs (e.g. `--preset parity --set protocol=pressure`).
--preset pressure runs the table of `--protocol pressure` against the anchor (mono1k, mono10k,
mono100k with 5 seeds, bi2d10k and powerlaw15k with 3; --set protocol=pressure is added) in the
same columns.
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

# Each row: packbench init flags, the box and walls both codes use, the anchor's size
# distribution (only used to construct its Packing; the start file overrides the particles).
ROWS = {
    "mono1k": dict(N=1000, d=3, init=["--dist", "mono", "--d", "1"], box=[1, 1, 1], walls=[0, 0, 0]),
    "mono10k": dict(N=10000, d=3, init=["--dist", "mono", "--d", "1"], box=[1, 1, 1], walls=[0, 0, 0]),
    "mono30k": dict(N=30000, d=3, init=["--dist", "mono", "--d", "1"], box=[1, 1, 1], walls=[0, 0, 0]),
    "mono100k": dict(N=100000, d=3, init=["--dist", "mono", "--d", "1"], box=[1, 1, 1], walls=[0, 0, 0]),
    "mono1m": dict(N=1000000, d=3, init=["--dist", "mono", "--d", "1"], box=[1, 1, 1], walls=[0, 0, 0]),
    "bi2d10k": dict(
        N=10000, d=2, init=["--dist", "bidisperse", "--d1", "1", "--d2", "1.4", "--p", "0.5"],
        box=[1, 1], walls=[0, 0],
    ),
    # The fidelity rows (N = 10^3 and 10^4 with 10 seeds each, `--preset parity`).
    "bi2d1k": dict(
        N=1000, d=2, init=["--dist", "bidisperse", "--d1", "1", "--d2", "1.4", "--p", "0.5"],
        box=[1, 1], walls=[0, 0],
    ),
    "lognormal1k": dict(
        N=1000, d=3, init=["--dist", "lognormal-mean1", "--sigma", "0.2"], box=[1, 1, 1], walls=[0, 0, 0],
    ),
    "lognormal10k": dict(
        N=10000, d=3, init=["--dist", "lognormal-mean1", "--sigma", "0.2"], box=[1, 1, 1], walls=[0, 0, 0],
    ),
    "powerlaw1k": dict(
        N=1000, d=3,
        init=["--dist", "powerlaw", "--d_min", "1", "--d_max", "15", "--exponent", "-3"],
        box=[1, 0.5, 1], walls=[0, 1, 0],
    ),
    "powerlaw10k": dict(
        N=10000, d=3,
        init=["--dist", "powerlaw", "--d_min", "1", "--d_max", "15", "--exponent", "-3"],
        box=[1, 0.5, 1], walls=[0, 1, 0],
    ),
    "powerlaw15k": dict(
        N=15000, d=3,
        init=["--dist", "powerlaw", "--d_min", "1", "--d_max", "15", "--exponent", "-3"],
        box=[1, 0.5, 1], walls=[0, 1, 0],
    ),
}

# Run by the anchor's python: pack one start file on one thread, write x1 .. xd D per line,
# print {"phi", "steps"}. Our own driver of its public Python API.
ANCHOR_RUNNER = r"""
import json, sys
import numpy as np
import rcpgenerator
rcpgenerator.set_num_threads(1)
start, out, box, walls = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), json.loads(sys.argv[4])
a = np.loadtxt(start, comments="#", ndmin=2)
d = a.shape[1] - 1
p = rcpgenerator.Packing(phi=0.05, N=a.shape[0], Ndim=d, box=box, walls=walls, fix_height=False,
                         dist={"type": "mono", "d": 1.0}, neighbor_max=0, seed=1, verbose=False)
p.positions, p.diameters = a[:, :d].tolist(), a[:, d].tolist()
p.pack()
np.savetxt(out, np.column_stack([np.asarray(p.positions), np.asarray(p.diameters)]), fmt="%.17g")
print(json.dumps({"phi": p.phi_final, "steps": int(p.steps)}))
"""


def anchors_dir():
    """Where scripts/anchors/build.sh put the anchors: $PACKBENCH_ANCHORS, else anchors/ at the
    repository root."""
    env = os.environ.get("PACKBENCH_ANCHORS")
    return Path(env) if env else Path(__file__).resolve().parent.parent / "anchors"


def timed(cmd, env, may_fail=False):
    """Runs `cmd`; returns (stdout, CPU seconds of the child: user + sys). Exits on failure,
    unless `may_fail` (then a failed run returns stdout None)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if r.returncode != 0:
        if may_fail:
            print(f"{cmd[0]} failed ({r.returncode}): {r.stderr.strip()[-400:]}", file=sys.stderr)
            return None, cpu
        sys.exit(f"{cmd[0]} failed ({r.returncode}): {r.stderr.strip()[-800:]}")
    return r.stdout, cpu


def analyze(pb, path, row):
    box = ",".join(str(v) for v in row["box"])
    walls = ",".join(str(v) for v in row["walls"])
    r = subprocess.run(
        [pb, "analyze", str(path), "--box", box, "--walls", walls, "--no-force-balance"],
        capture_output=True, text=True,
    )
    if r.returncode != 0:
        sys.exit(f"packbench analyze {path} failed: {r.stderr.strip()}")
    return json.loads(r.stdout)


def mean_se(values):
    """Mean and standard error of the mean (0 for one value)."""
    m = statistics.mean(values)
    return m, (statistics.stdev(values) / len(values) ** 0.5 if len(values) > 1 else 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("venv", type=Path, nargs="?", default=None,
                    help="virtual environment that imports rcpgenerator "
                         "(default: $PACKBENCH_ANCHORS/venv-rcpg)")
    ap.add_argument("--packbench", default="target/release/packbench")
    ap.add_argument("--rows", default="mono1k,mono10k,bi2d10k,powerlaw15k,mono100k")
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--first-seed", type=int, default=61)
    ap.add_argument("--method", default="adam")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--out", type=Path, default=None)
    only = ap.add_mutually_exclusive_group()
    only.add_argument("--packbench-only", action="store_true", help="do not run the anchor")
    only.add_argument("--anchor-only", action="store_true",
                      help="do not run packbench (anchor runs for a later --anchor-from)")
    ap.add_argument("--anchor-from", type=Path, default=None, metavar="RESULTS_JSON",
                    help="results.json of an earlier run: its anchor runs stand for this run's on "
                         "start files with the same bytes (checked), instead of running the anchor again")
    ap.add_argument("--preset", choices=["parity", "pressure"], help="a table of docs/BENCHMARKS.md (see above)")
    a = ap.parse_args()
    plan = [(name, a.seeds) for name in a.rows.split(",")]
    if a.preset == "parity":
        plan = [(n, 10) for n in ("mono1k", "bi2d1k", "lognormal1k", "powerlaw1k")] + [
            (n, 10) for n in ("mono10k", "bi2d10k", "lognormal10k", "powerlaw10k")] + [("mono100k", 3)]
    elif a.preset == "pressure":
        plan = [(n, 5) for n in ("mono1k", "mono10k", "mono100k")] + [(n, 3) for n in ("bi2d10k", "powerlaw15k")]
        if "protocol=pressure" not in a.set:
            a.set.append("protocol=pressure")
    venv = a.venv or anchors_dir() / "venv-rcpg"
    py = venv / "bin" / "python"
    if not py.exists():
        sys.exit(f"no python at {py}: build RCPGenerator 1.0 with scripts/anchors/build.sh, or set "
                 "PACKBENCH_ANCHORS to where it was built")
    for name, _ in plan:
        if name not in ROWS:
            sys.exit(f"unknown row {name}; rows: {', '.join(ROWS)}")
    out = a.out or Path(tempfile.mkdtemp(prefix="vs_rcpg_"))
    out.mkdir(parents=True, exist_ok=True)
    env1 = dict(os.environ, OMP_NUM_THREADS="1", RAYON_NUM_THREADS="1")
    results = []
    summary = []
    earlier = {}
    if a.anchor_from:
        earlier = {(r["row"], r["seed"]): r["rcpgenerator"]
                   for r in json.loads(a.anchor_from.read_text()) if "rcpgenerator" in r}
    for name, n_seeds in plan:
        row = ROWS[name]
        box = ",".join(str(v) for v in row["box"])
        walls = ",".join(str(v) for v in row["walls"])
        print(f"\n## {name}: d = {row['d']}, N = {row['N']}, box {box}, walls {walls}\n", flush=True)
        print("| seed | code | CPU s | steps | φ_J | max overlap | iso_gap / n_dof | rattlers |")
        print("|---|---|---|---|---|---|---|---|", flush=True)
        for seed in range(a.first_seed, a.first_seed + n_seeds):
            start = out / f"{name}_s{seed}_start.txt"
            subprocess.run(
                [a.packbench, "init", "--N", str(row["N"]), "--Ndim", str(row["d"]), "--phi", "0.05",
                 "--box", box, "--walls", walls, "--seed", str(seed), "--output", str(start)]
                + row["init"],
                check=True, capture_output=True,
            )
            runs = {}

            def anchor():
                if (name, seed) in earlier:
                    prev = earlier[(name, seed)]
                    prev_start = Path(prev["file"]).with_name(start.name)
                    if not prev_start.exists() or prev_start.read_bytes() != start.read_bytes():
                        sys.exit(f"--anchor-from: {prev_start} is not this run's start {start}")
                    runs["rcpgenerator"] = dict(cpu_s=prev["cpu_s"], steps=prev["steps"], file=Path(prev["file"]))
                    return
                o = out / f"{name}_s{seed}_rcpg.txt"
                so, cpu = timed([str(py), "-c", ANCHOR_RUNNER, str(start), str(o),
                                 json.dumps(row["box"]), json.dumps(row["walls"])], env1)
                runs["rcpgenerator"] = dict(cpu_s=cpu, steps=json.loads(so)["steps"], file=o)

            def ours():
                o = out / f"{name}_s{seed}_packbench.txt"
                # No force-balance solve in the timed run (the anchor does none); both outputs
                # are analysed afterwards by the same command.
                cmd = [a.packbench, "pack", "--method", a.method, "--file", str(start), "--box", box,
                       "--walls", walls, "--seed", str(seed), "--quiet", "--no-force-balance",
                       "--output", str(o)]
                for kv in a.set:
                    cmd += ["--set", kv]
                # A run that ends at its budget still overlapping exits 1 but keeps its packing
                # and record for inspection: recorded as failed, the anchor still runs.
                record = o.with_suffix(".json")
                record.unlink(missing_ok=True)
                so, cpu = timed(cmd, env1, may_fail=True)
                if not record.exists():
                    sys.exit(f"packbench failed on {start} and wrote no packing")
                meta = json.loads(record.read_text())
                runs["packbench"] = dict(cpu_s=cpu, steps=meta.get("steps"), file=o,
                                         termination=meta.get("termination"), failed=so is None)

            order = [anchor, ours] if seed % 2 == 0 else [ours, anchor]
            for f in order:
                if not (a.packbench_only and f is anchor or a.anchor_only and f is ours):
                    f()
            for code, r in runs.items():
                m = analyze(a.packbench, r["file"], row)
                r.update(phi=m["phi"], max_overlap=m["max_overlap"], iso_gap=m["iso_gap"],
                         n_dof=m["n_dof"], rattlers=m["rattlers"])
                label = f"{code}, **failed** ({r['termination']})" if r.get("failed") else code
                print(f"| {seed} | {label} | {r['cpu_s']:.2f} | {r['steps']} | {r['phi']:.4f} | "
                      f"{r['max_overlap']:.1e} | {r['iso_gap']} / {r['n_dof']} | {r['rattlers']} |",
                      flush=True)
            results.append(dict(row=name, seed=seed, **{
                k: {kk: (str(vv) if kk == "file" else vv) for kk, vv in v.items()}
                for k, v in runs.items()
            }))
        rows = [r for r in results if r["row"] == name]
        if a.anchor_only:
            ta = [r["rcpgenerator"]["cpu_s"] for r in rows]
            print(f"\n{name}: mean CPU anchor {statistics.mean(ta):.2f} s", flush=True)
            continue
        failed = sum(r["packbench"]["failed"] for r in rows)
        if failed:
            print(f"\n{name}: packbench failed on {failed} of {len(rows)} seeds (no ratio)", flush=True)
            continue
        tp = [r["packbench"]["cpu_s"] for r in rows]
        pp = [r["packbench"]["phi"] for r in rows]
        if a.packbench_only:
            print(f"\n{name}: mean CPU packbench {statistics.mean(tp):.2f} s; "
                  f"mean φ_J packbench {statistics.mean(pp):.4f}", flush=True)
            continue
        ta = [r["rcpgenerator"]["cpu_s"] for r in rows]
        pa = [r["rcpgenerator"]["phi"] for r in rows]
        print(f"\n{name}: mean CPU anchor {statistics.mean(ta):.2f} s, packbench {statistics.mean(tp):.2f} s, "
              f"ratio anchor/packbench = {statistics.mean(ta) / statistics.mean(tp):.2f}; "
              f"mean φ_J anchor {statistics.mean(pa):.4f}, packbench {statistics.mean(pp):.4f}", flush=True)
        (ma, sa), (mp, sp) = mean_se(pa), mean_se(pp)
        combined = (sa * sa + sp * sp) ** 0.5
        steps_a = statistics.mean(r["rcpgenerator"]["steps"] for r in rows)
        steps_p = statistics.mean(r["packbench"]["steps"] for r in rows)
        summary.append(f"| {name} | {row['N']} | {len(rows)} | {ma:.4f} ± {sa:.4f} | {mp:.4f} ± {sp:.4f} | "
                       f"{mp - ma:+.4f} | {(mp - ma) / combined if combined > 0 else float('nan'):+.1f} | "
                       f"{steps_a:.0f} / {steps_p:.0f} | {statistics.mean(ta):.2f} / {statistics.mean(tp):.2f} | "
                       f"{statistics.mean(ta) / statistics.mean(tp):.2f} |")
    if summary:
        print(f"\n## φ_J, {a.method} against RCPGenerator 1.0 (mean ± standard error over seeds)\n")
        print("| row | N | seeds | RCPGenerator 1.0 φ_J | packbench φ_J | Δφ_J | Δ / combined SE "
              "| mean steps anchor / packbench | mean CPU s anchor / packbench | CPU ratio anchor/packbench |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        print("\n".join(summary), flush=True)
    (out / "results.json").write_text(json.dumps(results, indent=1))
    print(f"\nall numbers: {out / 'results.json'}")


if __name__ == "__main__":
    main()
