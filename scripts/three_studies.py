"""The three studies of docs/BENCHMARKS.md, written the way a notebook user writes them, with
packbench's Python module and with RCPGenerator 1.0's, one thread each, on the same machine.

    PYTHON_PACKBENCH=target/pyenv/bin/python PYTHON_RCPG=VENV/bin/python \\
        python3 scripts/three_studies.py [--n 2000] [--seeds 3]

Each study is one process per (code, seed) that builds its start with the code's own
initializer (φ = 0.05, its own random placement) and packs it with the code's default
protocol; the CPU and wall times cover both, not the interpreter's start or the import
(CPU time is the steadier on a shared machine). Every final
packing is measured by packbench's analysis (contact tolerance 1e-6), so the φ and iso_gap
columns are comparable. Prints a Markdown table.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

STUDIES = {
    "3D mono": dict(dim=3, dist={"type": "mono", "d": 1.0}),
    "2D bidisperse 1:1.4": dict(dim=2, dist={"type": "bidisperse", "d1": 1.0, "d2": 1.4, "p": 0.5}),
    "3D lognormal σ = 0.2": dict(dim=3, dist={"type": "lognormal", "mu": 0.0, "sigma": 0.2}),
}

PACKBENCH = r'''
import json, sys, time
import packbench
packbench.set_num_threads(1)
n, dim, seed, dist, out = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), json.loads(sys.argv[4]), sys.argv[5]
kind = dist.pop("type")
t, c = time.perf_counter(), time.process_time()
start = packbench.initial_packing(n, dim, phi=0.05, dist=kind, seed=seed, **dist)
r = packbench.pack("adam", start, seed=seed, force_balance=False)
wall, cpu = time.perf_counter() - t, time.process_time() - c
r.packing.write(out)
print(json.dumps({"wall_s": wall, "cpu_s": cpu, "steps": r.steps}))
'''

RCPG = r'''
import json, sys, time
import numpy as np
import rcpgenerator
rcpgenerator.set_num_threads(1)
n, dim, seed, dist, out = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), json.loads(sys.argv[4]), sys.argv[5]
t, c = time.perf_counter(), time.process_time()
p = rcpgenerator.Packing(phi=0.05, N=n, Ndim=dim, box=[1.0] * dim, walls=[0] * dim, fix_height=False,
                         dist=dist, neighbor_max=0, seed=seed, verbose=False)
p.pack()
wall, cpu = time.perf_counter() - t, time.process_time() - c
np.savetxt(out, np.column_stack([np.asarray(p.positions), np.asarray(p.diameters)]), fmt="%.17g")
print(json.dumps({"wall_s": wall, "cpu_s": cpu, "steps": p.steps}))
'''


def run(python, code, n, dim, seed, dist, out):
    env = dict(os.environ, OMP_NUM_THREADS="1", RAYON_NUM_THREADS="1")
    text = subprocess.run([python, "-c", code, str(n), str(dim), str(seed), json.dumps(dist), out],
                          check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(text.strip().splitlines()[-1])


def measure(python_packbench, path):
    code = ("import json, sys, packbench; m = packbench.analyze(packbench.Packing.read(sys.argv[1]),"
            " force_balance=False); print(json.dumps(m))")
    return json.loads(subprocess.run([python_packbench, "-c", code, path], check=True,
                                     capture_output=True, text=True).stdout)


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    a.add_argument("--n", type=int, default=2000)
    a.add_argument("--seeds", type=int, default=3)
    args = a.parse_args()
    pb, rg = os.environ["PYTHON_PACKBENCH"], os.environ["PYTHON_RCPG"]
    print("| study (N = %d, 1 thread) | code | CPU s (mean of %d) | wall s | φ (mean ± sd) | iso_gap | rattlers |"
          % (args.n, args.seeds))
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, study in STUDIES.items():
            for code_name, python, code in (("RCPGenerator 1.0", rg, RCPG), ("packbench adam", pb, PACKBENCH)):
                walls, cpus, phis, gaps, ratt = [], [], [], [], []
                for seed in range(1, args.seeds + 1):
                    out = os.path.join(tmp, f"{code_name[:4]}-{seed}.txt")
                    r = run(python, code, args.n, study["dim"], seed, dict(study["dist"]), out)
                    m = measure(pb, out)
                    walls.append(r["wall_s"])
                    cpus.append(r["cpu_s"])
                    phis.append(m["phi"])
                    gaps.append(m["iso_gap"])
                    ratt.append(m["rattlers"])
                    print(f"  {name} {code_name} seed {seed}: {r['wall_s']:.2f} s, φ {m['phi']:.5f}",
                          file=sys.stderr)
                sd = statistics.stdev(phis) if len(phis) > 1 else 0.0
                print(f"| {name} | {code_name} | {statistics.mean(cpus):.2f} | {statistics.mean(walls):.2f} | "
                      f"{statistics.mean(phis):.4f} ± {sd:.4f} | {statistics.mean(gaps):+.0f} | "
                      f"{statistics.mean(ratt):.0f} |")


if __name__ == "__main__":
    main()
