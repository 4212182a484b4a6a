#!/bin/bash
# The worked example of `packbench design` (README, docs/BENCHMARKS.md):
#  1. the log-normal σ (log-std of the diameters) whose 3D packings of N = 2000 spheres jam at
#     φ_J = 0.66 with adam, 2 packings per candidate, 32 packings in all, 5 confirmation reruns;
#  2. the densest two-component mixture with a size ratio D_max/D_min ≤ 10 (N = 1000, one
#     packing per candidate, 54 packings, 3 confirmation reruns).
# Each writes its folder (evaluations.csv, best.json, best_diameters.txt, report.md, figures/).
# Stopped (Ctrl-C, a time limit)? Run the same line again with --resume.
set -euo pipefail
PACKBENCH=${PACKBENCH:-packbench}
OUT=${1:-design-example}
mkdir -p "$OUT"
/usr/bin/time -f "lognormal: %e s wall, %U s user CPU" \
  "$PACKBENCH" design --family lognormal --param sigma=0:0.4 --objective target --target 0.66 \
    --N 2000 --Ndim 3 --seeds-per-candidate 2 --budget 32 --confirm 5 --out "$OUT/lognormal"
/usr/bin/time -f "mixture: %e s wall, %U s user CPU" \
  "$PACKBENCH" design --family mixture --components 2 --max-ratio 10 --objective max-phi \
    --N 1000 --Ndim 3 --seeds-per-candidate 1 --budget 54 --confirm 3 --out "$OUT/mixture"
