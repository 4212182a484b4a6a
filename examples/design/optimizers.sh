#!/bin/bash
# CMA-ES against the surrogate optimiser (`--optimizer ego`) on one question, the same budget,
# several search seeds (docs/BENCHMARKS.md, Design): the log-normal σ whose 3D packings of
# N spheres jam at φ_J = 0.655 with adam, SPC packings per candidate, BUDGET packings, 4
# confirmation reruns; no screen, so both optimisers pack every candidate they propose.
# Defaults N=256 SPC=1 BUDGET=24; the second setting of the table is N=500 SPC=2 BUDGET=32.
# Needs a binary built with the feature: cargo build --release --features ego -p packbench.
# Then: python3 scripts/tables/design_optimizers.py OUT
set -euo pipefail
PACKBENCH=${PACKBENCH:-packbench}
OUT=${1:-design-optimizers}
SEEDS=${SEEDS:-"1 2 3 4 5"}
N=${N:-256}
SPC=${SPC:-1}
BUDGET=${BUDGET:-24}
mkdir -p "$OUT"
for opt in cmaes ego; do
  for seed in $SEEDS; do
    dir="$OUT/$opt-seed$seed"
    rm -rf "$dir"
    /usr/bin/time -o "$dir.time" -f "%e %U %S" \
      "$PACKBENCH" design --family lognormal --param sigma=0:0.4 --objective target \
        --target 0.655 --N "$N" --Ndim 3 --seeds-per-candidate "$SPC" --budget "$BUDGET" --confirm 4 \
        --screen none --jobs 2 --quiet --optimizer "$opt" --seed "$seed" --out "$dir"
  done
done
