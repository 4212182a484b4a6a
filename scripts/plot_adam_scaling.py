#!/usr/bin/env python3
"""Time to jam against N on log–log axes, packbench `adam` and RCPGenerator 1.0, from the
results.json files that scripts/bench_vs_rcpgenerator.py writes (3D monodisperse rows).

Usage: VENV/bin/python scripts/plot_adam_scaling.py OUT.png RESULTS.json [RESULTS.json ...]
(needs matplotlib; the anchor's virtual environment has it).
"""

import json
import statistics
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

N_OF_ROW = {"mono1k": 1000, "mono10k": 10000, "mono30k": 30000, "mono100k": 100000, "mono1m": 1000000}


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    cpu = defaultdict(lambda: defaultdict(list))
    for path in sys.argv[2:]:
        for r in json.load(open(path)):
            if r["row"] in N_OF_ROW:
                for code in ("rcpgenerator", "packbench"):
                    if code in r:  # rows run with --packbench-only have no anchor
                        cpu[code][N_OF_ROW[r["row"]]].append(r[code]["cpu_s"])
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for code, label, marker in (("rcpgenerator", "RCPGenerator 1.0", "s"), ("packbench", "packbench adam", "o")):
        ns = sorted(cpu[code])
        means = [statistics.mean(cpu[code][n]) for n in ns]
        ax.loglog(ns, means, marker=marker, label=label)
        for n in ns:
            ax.scatter([n] * len(cpu[code][n]), cpu[code][n], s=8, color=ax.lines[-1].get_color(), alpha=0.5)
    ns = sorted(cpu["packbench"])
    if ns:
        t0 = statistics.mean(cpu["packbench"][ns[0]])
        ax.loglog(ns, [t0 * n / ns[0] for n in ns], "k:", lw=0.8, label="∝ N")
    ax.set_xlabel("N (3D monodisperse, from φ = 0.05)")
    ax.set_ylabel("CPU s to jam, one thread")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(sys.argv[1], dpi=120)
    print(f"wrote {sys.argv[1]}")


if __name__ == "__main__":
    main()
