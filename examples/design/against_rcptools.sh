#!/usr/bin/env bash
# packbench design against rcptools on the mixture question (the densest 3D two-component
# mixture with D_max/D_min <= 10, N = 1000), five searches per tool with search seeds 1-5, each
# with 63 packings (packbench: budget 60 + 3 confirmations; rcptools: 54 cheap + 6 elite + 3
# confirmations), 2 packings at a time, one search at a time.
#
#   PACKBENCH_ANCHORS=anchors bash examples/design/against_rcptools.sh OUT
#
# Needs rcptools in $PACKBENCH_ANCHORS/venv-rcpg (scripts/anchors/build.sh) and GNU time.
# scripts/tables/design_against_rcptools.py OUT prints the table.
set -euo pipefail
out=${1:?usage: against_rcptools.sh OUT}
here=$(cd "$(dirname "$0")" && pwd)
packbench=${PACKBENCH:-target/release/packbench}
python=${PACKBENCH_ANCHORS:-anchors}/venv-rcpg/bin/python
seeds=${SEEDS:-1 2 3 4 5}
mkdir -p "$out"
for s in $seeds; do
  if [ ! -f "$out/packbench-$s/best.json" ]; then
    rm -rf "$out/packbench-$s"
    /usr/bin/time -f "%U user %S sys %e wall" -o "$out/packbench-$s.time" \
      "$packbench" design --family discrete --components 2 --max-ratio 10 --objective max-phi \
      --N 1000 --Ndim 3 --seeds-per-candidate 1 --budget 60 --confirm 3 --seed "$s" \
      --jobs 2 --quiet --out "$out/packbench-$s"
  fi
  if [ ! -f "$out/rcptools-$s.log" ] || ! grep -q '^RESULT ' "$out/rcptools-$s.log"; then
    rm -rf "$out/rcptools-$s"
    /usr/bin/time -f "%U user %S sys %e wall" -o "$out/rcptools-$s.time" \
      "$python" "$here/rcptools_mixture.py" "$out/rcptools-$s" "$s" > "$out/rcptools-$s.log" 2>&1
  fi
done
