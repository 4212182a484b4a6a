#!/usr/bin/env python3
"""The force-biased (FB) columns of Baranau & Tallarek 2014, Table 3, by the publication's protocol:
a fast FB compression with PackingGeneration (Baranau's own code, the anchor), then packbench's
MLS closest-jamming search.

Usage:
  scripts/anchors/baranau2014_fb.py [--sigmas 0.00,...,0.30] [--N 1000] [--seeds 3] [--first-seed 1]
                                    [--rate 1e-3] [--phi-exp PHI] [--out DIR] [--packbench BIN]
  scripts/anchors/baranau2014_fb.py --table RESULTS_JSON [RESULTS_JSON ...]

packbench has no FB algorithm, so the compression is PackingGeneration's `-fba`
($PACKBENCH_ANCHORS/pg/_Release/PackingGeneration.exe; PACKBENCH_ANCHORS defaults to anchors/ at
the repository root, where scripts/anchors/build.sh builds it). packbench is $PACKBENCH, else
--packbench, else target/release/packbench. For every σ and seed:

1. start: `packbench init --dist lognormal-mean1 --sigma σ --placement poisson` (N spheres,
   periodic unit box, φ = 0.05, the seed): Poisson centres, as the publication's compressions
   start from;
2. the start in PackingGeneration's input: packing.xyzd (x, y, z, d little-endian doubles) with
   the diameters scaled to mean 1 and the box side L chosen so that the nominal density of the
   diameters is φ_exp (below), and generation.conf (bulk, "Generation start: 0", the rate);
3. `PackingGeneration.exe -fba` in a folder of its own; its packing.xyzd keeps the input diameters,
   which are multiplied by ((1 − final porosity) / (1 − theoretical porosity))^(1/3) from its
   packing.nfo (its README, "Note on final diameters"), and everything divided by L back to the
   unit box, centres wrapped into it, written as packbench's plain text (x y z D per line);
4. `packbench pack --method mls --file FB.txt` with MLS's defaults (γ 10 → 1e-4, halved at reduced
   pressure 1e12, the publication's §III.B), same seed; its φ is the closest-jamming density φ_J.
   mls takes a start with overlaps and shrinks it uniformly by the smallest factor that clears
   them (`initial_shrink` in its record, printed here); PackingGeneration's FB ends with the
   closest pair just touching, so the factor is 1 to rounding.

The FB parameters. PackingGeneration's FB (Bezrukov, Bargiel & Stoyan 2002) has one rate, the
contraction rate γ, and its final density also follows the nominal density of the diameters
given, φ_exp (README §1.4). Its README states how the publication set φ_exp for its Fig. 2c: on the
line through (ln γ_fast, 0.6) and (ln γ_slow, 0.7), γ_fast = 1e-3, γ_slow = 1e-7. (The formula it
prints has the opposite sign, which would put γ_slow at 0.5, against its own words; the line
through the two points is used.) Table 3 concerns the fast compressions, so the default is the
fastest rate of that range, γ = 1e-3 with φ_exp = 0.6 (at N = 10³ FB ends at φ = 0.596–0.616
after 103–122 iterations). Not verified here: which FB rates the publication counted as fast
for its Fig. 4 and Table 3 (its text was not at hand; slower rates end FB denser, 0.635 at 1e-4
for σ = 0, which may move φ_J), and its start configurations beyond "Poisson" (its generation
mode 1 draws Poisson points itself; here they are packbench's, read in).

Prints one row per run (φ after FB, its largest overlap, MLS's shrink factor and termination, φ_J,
CPU seconds of each stage: user + sys of the child), then per σ the lowest and highest φ_J
beside phi_fast_min_fb and phi_fast_max_fb of crates/bench/data/published/baranau2014_table3.csv
with the band at the N run (value ± unc ± fs_half·√(fs_n/N)) and inside or OUTSIDE. Every number
goes to DIR/results.json after each run; --table prints the tables from one or more of them.
Results and verdicts: docs/notes/baranau-fb-columns.md.
"""

import argparse
import json
import math
import os
import resource
import shutil
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
TABLE3 = ROOT / "crates/bench/data/published/baranau2014_table3.csv"
GAMMA_FAST, PHI_MIN, GAMMA_SLOW, PHI_MAX = 1e-3, 0.6, 1e-7, 0.7


def phi_exp_of(rate):
    """The nominal density the publication paired with FB rate γ (PackingGeneration's README)."""
    t = (math.log(rate) - math.log(GAMMA_FAST)) / (math.log(GAMMA_SLOW) - math.log(GAMMA_FAST))
    return PHI_MIN + (PHI_MAX - PHI_MIN) * t


def anchors_dir():
    env = os.environ.get("PACKBENCH_ANCHORS")
    return Path(env) if env else ROOT / "anchors"


def timed(cmd, cwd=None):
    """Runs `cmd`; returns (stdout, CPU seconds of the child: user + sys). Exits on failure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if r.returncode != 0:
        sys.exit(f"{cmd[0]} failed ({r.returncode}): {(r.stderr or r.stdout).strip()[-800:]}")
    return r.stdout, cpu


def read_text(path):
    return [[float(v) for v in line.split()] for line in path.read_text().splitlines()
            if line.strip() and not line.lstrip().startswith("#")]


def to_pg(rows, folder, rate, phi_exp, seed):
    """Writes PackingGeneration's input for the unit-box packing `rows`; returns L."""
    n = len(rows)
    scale = n / sum(r[3] for r in rows)  # mean diameter 1
    volume = sum(math.pi / 6 * (r[3] * scale) ** 3 for r in rows)
    side = (volume / phi_exp) ** (1 / 3)
    with open(folder / "packing.xyzd", "wb") as f:
        for r in rows:
            f.write(struct.pack("<4d", r[0] * side, r[1] * side, r[2] * side, r[3] * scale))
    (folder / "generation.conf").write_text(
        f"Particles count: {n}\nPacking size: {side!r} {side!r} {side!r}\nGeneration start: 0\n"
        f"Seed: {seed}\nSteps to write: 1000000\nBoundaries mode: 1\nContraction rate: {rate!r}\n")
    return side


def from_pg(folder, side, out):
    """PackingGeneration's result in packbench's plain text (unit box); returns its iterations."""
    info = {}
    for line in (folder / "packing.nfo").read_text().splitlines():
        if ":" in line:
            key, value = line.split(":", 1)
            info[key.strip()] = value.split("(")[0].strip()
    k = ((1 - float(info["Final Porosity"])) / (1 - float(info["Theoretical Porosity"]))) ** (1 / 3)
    data = (folder / "packing.xyzd").read_bytes()
    with open(out, "w") as f:
        for i in range(len(data) // 32):
            x, y, z, d = struct.unpack_from("<4d", data, 32 * i)
            f.write(f"{(x / side) % 1.0!r} {(y / side) % 1.0!r} {(z / side) % 1.0!r} {d * k / side!r}\n")
    return int(info.get("Total Iterations", "0"))


def analyze(pb, path):
    so, _ = timed([pb, "analyze", str(path), "--box", "1,1,1", "--walls", "0,0,0", "--no-force-balance"])
    return json.loads(so)


def one_run(a, pb, exe, sigma, seed, out):
    tag = f"sigma{sigma * 100:03.0f}_seed{seed}"
    start = out / f"{tag}_start.txt"
    _, cpu_init = timed([pb, "init", "--N", str(a.N), "--Ndim", "3", "--dist", "lognormal-mean1",
                         "--sigma", str(sigma), "--placement", "poisson", "--box", "1,1,1",
                         "--walls", "0,0,0", "--seed", str(seed), "--output", str(start)])
    folder = out / f"{tag}_pg"
    shutil.rmtree(folder, ignore_errors=True)  # a packing.nfo left there would skip the run
    folder.mkdir()
    t0 = time.process_time()
    side = to_pg(read_text(start), folder, a.rate, a.phi_exp, seed)
    log, cpu_fb = timed([str(exe), "-fba"], cwd=folder)
    (folder / "log.txt").write_text(log)
    fb = out / f"{tag}_fb.txt"
    iterations = from_pg(folder, side, fb)
    cpu_convert = time.process_time() - t0
    m_fb = analyze(pb, fb)
    mls = out / f"{tag}_mls"
    _, cpu_mls = timed([pb, "pack", "--method", "mls", "--file", str(fb), "--box", "1,1,1", "--walls",
                        "0,0,0", "--seed", str(seed), "--quiet", "--no-force-balance", "--output", str(mls)])
    rec = json.loads(Path(f"{mls}.json").read_text())
    return dict(sigma=sigma, seed=seed, N=a.N, rate=a.rate, phi_exp=a.phi_exp, fb_iterations=iterations,
                phi_fb=m_fb["phi"], fb_max_overlap=m_fb["max_overlap"],
                initial_shrink=rec["extra"].get("initial_shrink"), termination=rec["termination"],
                phi_j=rec["metrics"]["phi"], iso_gap=rec["metrics"]["iso_gap"],
                rattlers=rec["metrics"]["rattlers"], mls_max_overlap=rec["metrics"]["max_overlap"],
                cpu_init=cpu_init, cpu_fb=cpu_fb, cpu_convert=cpu_convert, cpu_mls=cpu_mls)


def published():
    lines = [l for l in TABLE3.read_text().splitlines() if l.strip() and not l.startswith("#")]
    head = lines[0].split(",")
    return {f"{float(r.split(',')[0]):.2f}": dict(zip(head, map(float, r.split(",")))) for r in lines[1:]}


def band(row, col, n):
    half = row[f"{col}_unc"] + row["fs_half"] * math.sqrt(row["fs_n"] / n)
    return row[col] - half, row[col] + half


def print_tables(results):
    pub = published()
    print("\n## φ_J after fast FB + MLS against Baranau & Tallarek 2014, Table 3 (FB columns)\n")
    print("| σ | N | seeds | φ after FB | φ_fast_min FB [band] | lowest φ_J | | "
          "φ_fast_max FB [band] | highest φ_J | | the φ_J |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    groups = {}
    for r in results:
        groups.setdefault((f"{r['sigma']:.2f}", r["N"]), []).append(r)
    for (s, n), rs in sorted(groups.items()):
        row, phis = pub[s], [r["phi_j"] for r in sorted(rs, key=lambda r: r["seed"])]
        cells = []
        for col, v in (("phi_fast_min_fb", min(phis)), ("phi_fast_max_fb", max(phis))):
            lo, hi = band(row, col, n)
            cells.append(f"{row[col]:.4f} [{lo:.4f}, {hi:.4f}] | {v:.4f} | "
                         f"{'inside' if lo <= v <= hi else 'OUTSIDE'}")
        fb = [r["phi_fb"] for r in rs]
        print(f"| {s} | {n} | {len(rs)} | {min(fb):.4f}–{max(fb):.4f} | {cells[0]} | {cells[1]} | "
              f"{' '.join(f'{p:.4f}' for p in phis)} |")
    print("\n## CPU seconds per run (mean over the seeds; user + sys of each child)\n")
    print("| σ | N | init | PG input/output | FB (PackingGeneration) | MLS (packbench) |")
    print("|---|---|---|---|---|---|")
    for (s, n), rs in sorted(groups.items()):
        mean = lambda k: sum(r[k] for r in rs) / len(rs)  # noqa: E731
        print(f"| {s} | {n} | {mean('cpu_init'):.2f} | {mean('cpu_convert'):.2f} | {mean('cpu_fb'):.2f} | "
              f"{mean('cpu_mls'):.1f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sigmas", default="0.00,0.05,0.10,0.15,0.20,0.25,0.30")
    ap.add_argument("--N", type=int, default=1000)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--rate", type=float, default=GAMMA_FAST, help="FB contraction rate γ")
    ap.add_argument("--phi-exp", type=float, default=None,
                    help="nominal density of the FB input (default: the publication's line at γ)")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", str(ROOT / "target/release/packbench")))
    ap.add_argument("--table", type=Path, nargs="+", metavar="RESULTS_JSON",
                    help="print the tables of earlier runs and stop")
    a = ap.parse_args()
    if a.table:
        print_tables([r for p in a.table for r in json.loads(p.read_text())])
        return
    a.phi_exp = a.phi_exp if a.phi_exp is not None else phi_exp_of(a.rate)
    exe = anchors_dir() / "pg" / "_Release" / "PackingGeneration.exe"
    if not exe.exists():
        sys.exit(f"no PackingGeneration at {exe}: build it with scripts/anchors/build.sh "
                 "packing-generation, or set PACKBENCH_ANCHORS to where it was built")
    if shutil.which(a.packbench) is None:
        sys.exit(f"no packbench at {a.packbench}: set PACKBENCH or --packbench")
    out = a.out or Path(tempfile.mkdtemp(prefix="baranau_fb_"))
    out.mkdir(parents=True, exist_ok=True)
    print(f"FB: PackingGeneration -fba, γ = {a.rate:g}, φ_exp = {a.phi_exp:.4f}; then packbench mls "
          f"(defaults); N = {a.N}; out {out}\n")
    print("| σ | seed | FB iterations | φ after FB | FB max overlap | 1 − MLS shrink | MLS end | φ_J "
          "| iso_gap | CPU s init / PG io / FB / MLS |")
    print("|---|---|---|---|---|---|---|---|---|---|", flush=True)
    results = []
    for sigma in (float(s) for s in a.sigmas.split(",")):
        for seed in range(a.first_seed, a.first_seed + a.seeds):
            r = one_run(a, a.packbench, exe, sigma, seed, out)
            results.append(r)
            (out / "results.json").write_text(json.dumps(results, indent=1))
            print(f"| {sigma:.2f} | {seed} | {r['fb_iterations']} | {r['phi_fb']:.4f} | "
                  f"{r['fb_max_overlap']:.1e} | {1 - r['initial_shrink']:.1e} | {r['termination']} | "
                  f"{r['phi_j']:.4f} | {r['iso_gap']} | {r['cpu_init']:.2f} / {r['cpu_convert']:.2f} / "
                  f"{r['cpu_fb']:.2f} / {r['cpu_mls']:.1f} |", flush=True)
    print_tables(results)
    print(f"\nall numbers: {out / 'results.json'}")


if __name__ == "__main__":
    main()
