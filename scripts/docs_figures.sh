#!/usr/bin/env bash
# Regenerates the figures README and docs show of packbench's everyday outputs, into
# docs/figures/: the default `compare` (φ by method, a packing), a `--structure` analysis
# (P(f) with θ), a trace (φ and pressure against steps), the pore sizes and a reproduce report's
# figure.
# Each is made by the command a user runs, at README's defaults where they are quick.
# Usage: scripts/docs_figures.sh   (needs a release build: cargo build --release -p packbench)
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
bin="${PACKBENCH_BIN:-${CARGO_TARGET_DIR:-$repo/target}/release/packbench}"
out="$repo/docs/figures"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

# The main job, as README gives it.
"$bin" compare --out cmp
cp cmp/figures/phi_by_method.png "$out/compare_phi_by_method.png"

# A 3D packing and its exact refinement: the structure and trace figures.
"$bin" pack --method adam --N 1000 --Ndim 3 --seed 1 --output adam
"$bin" pack --method calippso --file adam.txt --output exact
"$bin" pack --method mls --N 1000 --Ndim 3 --seed 1 --output mls
"$bin" plot adam.txt exact.txt --kind forces --output "$out/structure_forces.png"
"$bin" plot adam.txt --output "$out/packing_slice_3d.png"
"$bin" plot adam.json mls.json --kind trace --output "$out/trace_adam_mls.png"

"$bin" plot adam.txt --kind pores --output "$out/pores_adam.png"

# A reproduce report's figure, at a small N: O'Hern's 2D disks and 3D spheres.
"$bin" reproduce ohern-2003 --N 250 --seeds 2 --out ohern
cp ohern/figures/reproduce.png "$out/reproduce_ohern.png"
echo "wrote $out/{compare_phi_by_method,structure_forces,packing_slice_3d,trace_adam_mls,pores_adam,reproduce_ohern}.png"
