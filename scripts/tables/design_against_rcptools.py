#!/usr/bin/env python3
"""The "Against rcptools" table of docs/BENCHMARKS.md: packbench design and rcptools on three 3D
questions, five searches per tool with the same packings per search:

  mixture     the densest two-component mixture with D_max/D_min <= 10 (N = 1000);
  lognormal   the log-normal σ that jams at φ_J = 0.66;
  bidisperse  the smallest bidisperse size ratio (equal numbers) reaching φ_J = 0.65.

Usage:
  scripts/tables/design_against_rcptools.py OUT [--runs]

OUT is the folder examples/design/against_rcptools.sh filled: OUT/QUESTION/packbench-S/ (a
design folder) and packbench-S.time, rcptools-S.log (its RESULT line) and rcptools-S.time, for
each question and search seed S (and OUT/QUESTION-spc1/ for packbench with 1 seed per
candidate, SPC=1, and OUT/QUESTION-cmaes/ for packbench with CMA-ES, OPTIMIZER=cmaes). Prints one summary row per question and tool (the best search's answer, the
confirmed φ_J and the answer over the searches, mean ± std, the seed spread inside a search,
packings and CPU time per search); --runs prints the row of every search as well, and where each
packer's own packings cross the target. Confirmed φ_J is the mean over the 3 fresh confirmation
seeds; CPU is user + sys of the whole command (GNU time).
"""

import csv
import json
import re
import statistics
import sys
from pathlib import Path

QUESTIONS = {
    # name: (words, target φ_J or None for the largest φ_J)
    "mixture": ("densest mixture, D_max/D_min ≤ 10", None),
    "lognormal": ("log-normal σ, φ_J = 0.66", 0.66),
    "bidisperse": ("smallest ratio, φ_J ≥ 0.65", 0.65),
}


def cpu(path):
    m = re.search(r"([0-9.]+) user ([0-9.]+) sys ([0-9.]+) wall", path.read_text())
    if not m:
        sys.exit(f"{path}: no GNU time line")
    return float(m[1]) + float(m[2])


def packbench(out, seed, question):
    best = json.loads((out / f"packbench-{seed}" / "best.json").read_text())
    report = (out / f"packbench-{seed}" / "report.md").read_text()
    m = re.search(r"Search: .*?, (\d+) packings; (\d+) confirmation", report, re.S)
    values = dict(zip(best["names"], best["values"]))
    if question == "lognormal":
        answer, x = f"σ = {values['sigma']:.4f}", values["sigma"]
    elif question == "bidisperse":
        answer, x = f"ratio = {values['d2']:.4f}", values["d2"]
    else:
        answer, x = ", ".join(f"{n} = {v:.3g}" for n, v in values.items()), None
    return {
        "answer": answer,
        "x": x,
        "search_phi": best["search_phi"],
        "confirm_phi": best["confirm_phi"],
        "packings": int(m[1]) + int(m[2]),
        "cpu": cpu(out / f"packbench-{seed}.time"),
    }


def rcptools(out, seed, question):
    log = (out / f"rcptools-{seed}.log").read_text()
    m = re.search(r"^RESULT (.*)$", log, re.M)
    if not m:
        raise FileNotFoundError(f"rcptools-{seed}.log: no RESULT line (the search did not finish)")
    r = json.loads(m[1])
    if "theta" in r:
        answer, x = "θ = " + " ".join(f"{v:.3g}" for v in r["theta"]), None
    else:
        name = "σ" if r["param"] == "sigma" else r["param"]
        answer, x = f"{name} = {r['answer']:.4f}", r["answer"]
    return {
        "answer": answer,
        "x": x,
        "search_phi": r["search_phi"],
        "confirm_phi": r["confirm_phi"],
        "packings": r["packings"],
        "cpu": cpu(out / f"rcptools-{seed}.time"),
    }


def packed_points(out, seed, tool, question):
    """(parameter, φ_J) of every packing of a search (not the confirmations)."""
    if tool == "rcptools":
        log = (out / f"rcptools-{seed}.log").read_text()
        r = json.loads(re.search(r"^RESULT (.*)$", log, re.M)[1])
        return [(x, f) for x, _, phis in r["points"] for f in phis]
    name = "sigma" if question == "lognormal" else "d2"
    with open(out / f"packbench-{seed}" / "evaluations.csv") as f:
        return [(float(r[name]), float(r["phi"])) for r in csv.DictReader(f)
                if r["kind"] == "search" and r["phi"]]


def crossing(points, target, band=0.005):
    """Where a least-squares line through the packings with φ_J within `band` of the target
    crosses it: the packer's own answer, from every search's packings pooled."""
    near = [(x, f) for x, f in points if abs(f - target) <= band]
    n = len(near)
    if n < 3:
        return None, n
    mx, mf = sum(x for x, _ in near) / n, sum(f for _, f in near) / n
    sxx = sum((x - mx) ** 2 for x, _ in near)
    slope = sum((x - mx) * (f - mf) for x, f in near) / sxx if sxx > 0 else 0.0
    return (mx + (target - mf) / slope if slope > 0 else None), n


def mean_std(xs):
    return statistics.mean(xs), (statistics.stdev(xs) if len(xs) > 1 else 0.0)


def fmt(x, digits=4):
    return "–" if x is None else f"{x:.{digits}f}"


def score(rows, target, question):
    """The best search's answer: the largest confirmed φ_J; the confirmed φ_J closest to the
    target; or the smallest ratio whose confirmed φ_J reaches the target."""
    conf = [statistics.mean(r["confirm_phi"]) for r in rows]
    if target is None:
        return f"φ_J {max(conf):.4f}"
    if question == "bidisperse":
        ok = [(r["x"], c) for r, c in zip(rows, conf) if c >= target]
        if not ok:
            return "none reached"
        x, c = min(ok)
        return f"{x:.4f} (φ_J {c:.4f})"
    c = min(conf, key=lambda c: abs(c - target))
    return f"off by {abs(c - target):.4f}"


def pm(xs, digits=4):
    m, sd = mean_std(xs)
    return f"{m:.{digits}f} ± {sd:.{digits}f}"


# The searches of one question: (label, folder suffix, reader). The `-spc1` folders hold
# packbench alone with 1 seed per candidate (SPC=1 examples/design/against_rcptools.sh), the
# `-cmaes` folders packbench alone with CMA-ES in place of the bracket (OPTIMIZER=cmaes).
TOOLS = [("packbench", "", packbench), ("packbench, CMA-ES", "-cmaes", packbench),
         ("packbench, 1 seed per candidate", "-spc1", packbench), ("rcptools", "", rcptools)]


def main():
    args = [a for a in sys.argv[1:] if a != "--runs"]
    if len(args) != 1:
        sys.exit(__doc__)
    root, runs = Path(args[0]), "--runs" in sys.argv[1:]
    summary = []
    if runs:
        print("| question | tool | search seed | answer | φ_J (search) | confirmed φ_J "
              "(3 fresh seeds, mean ± std) | packings | CPU s |")
        print("|---|---|---|---|---|---|---|---|")
    for question, (words, target) in QUESTIONS.items():
        for name, suffix, read in TOOLS:
            out = root / (question + suffix)
            if not out.is_dir():
                continue
            seeds = sorted({int(re.match(r"\w+-(\d+)", p.name)[1])
                            for p in out.glob(f"{name.split(',')[0]}-*.time")})
            rows, done = [], []
            for s in seeds:
                try:
                    rows.append(read(out, s, question))
                    done.append(s)
                except (FileNotFoundError, SystemExit) as e:
                    if runs:
                        print(f"| {question} | {name} | {s} | not finished ({e}) | | | | |")
                    continue
                r = rows[-1]
                m, sd = mean_std(r["confirm_phi"])
                line = "" if name != "rcptools" or target is None else " (line)"
                if runs:
                    print(f"| {question} | {name} | {s} | {r['answer']} | "
                          f"{fmt(r['search_phi'])}{line} | {m:.4f} ± {sd:.4f} | "
                          f"{r['packings']} | {r['cpu']:.0f} |")
            if rows:
                summary.append((words, name, out, done, rows, target, question))
    if runs:
        print()
    print("| question | tool | searches | best search | confirmed φ_J over the searches "
          "| abs(φ_J − target) | answer | spread | packings | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for words, name, out, done, rows, target, question in summary:
        conf = [statistics.mean(r["confirm_phi"]) for r in rows]
        within = statistics.mean(mean_std(r["confirm_phi"])[1] for r in rows)
        packings = ", ".join(str(p) for p in sorted({r["packings"] for r in rows}))
        off = "–" if target is None else pm([abs(c - target) for c in conf])
        answer = "–" if target is None else pm([r["x"] for r in rows], 3)
        print(f"| {words} | {name} | {len(rows)} | {score(rows, target, question)} "
              f"| {pm(conf)} | {off} | {answer} | {within:.4f} | {packings} "
              f"| {statistics.mean(r['cpu'] for r in rows):.0f} |")
    if not runs:
        return
    print()
    print("| question | tool | packings pooled (φ_J within 0.005 of the target) "
          "| the packer's crossing of the target (line fit) |")
    print("|---|---|---|---|")
    for words, name, out, done, rows, target, question in summary:
        if target is None:
            continue
        tool = "rcptools" if name == "rcptools" else "packbench"
        points = [p for s in done for p in packed_points(out, s, tool, question)]
        x, n = crossing(points, target)
        print(f"| {words} | {name} | {n} of {len(points)} | {fmt(x)} |")


if __name__ == "__main__":
    main()
