#!/usr/bin/env bash
# packbench design against rcptools on three 3D questions, five searches per tool (search
# seeds 1-5), the same packings per search for both tools, 2 packings at a time, one search at
# a time:
#
#   mixture     the densest two-component mixture with D_max/D_min <= 10, N = 1000, 63 packings
#               (packbench: budget 60 + 3 confirmations; rcptools' CMA-ES search: 54 cheap + 6
#               elite + 3 confirmations; rcptools_mixture.py);
#   lognormal   the log-normal σ that jams at φ_J = 0.66, N = 1000, 35 packings (packbench:
#               2 seeds per candidate, budget 32 + 3 confirmations; rcptools: bisection and a
#               local line fit over σ with its own model and packer, rcptools_target.py);
#   bidisperse  the smallest bidisperse size ratio, equal numbers, reaching φ_J = 0.65, N = 1000,
#               35 packings (packbench: `discrete` with number fractions, x1 = 0.5 fixed,
#               objective min-ratio; rcptools: as for lognormal, rcptools_target.py).
#
#   PACKBENCH_ANCHORS=anchors bash examples/design/against_rcptools.sh OUT
#
# Both tools' packings start from random sequential addition at φ = 0.11 (rcptools places its
# spheres there, initializer_phi; packbench's design gets --phi 0.11, PHI to change it): the
# packers' φ_J rises with the start's φ (0.6495 from 0.05, 0.6501 from 0.11 for adam's 1 : 1.54
# bidisperse N = 1000, as for rcptools' engine), so equal starts make the question the same.
# QUESTIONS (default "mixture lognormal bidisperse") and SEEDS (default "1 2 3 4 5") choose a
# part; NT (default 1000) is N of the lognormal and bidisperse questions. SPC=1 runs packbench
# alone on those two with 1 seed per candidate (32 candidates instead of 16, the same packings)
# into OUT/QUESTION-spc1. OPTIMIZER (default auto, packbench's default: the bracket on those two
# questions, CMA-ES on the mixture) set to cmaes runs packbench alone on those two with
# `--optimizer cmaes` into OUT/QUESTION-cmaes. Finished searches are kept. Needs rcptools in $PACKBENCH_ANCHORS/venv-rcpg (scripts/anchors/build.sh) and GNU time.
# scripts/tables/design_against_rcptools.py OUT prints the table. Writes OUT/QUESTION/packbench-S
# (a design folder), packbench-S.time, rcptools-S.log (its RESULT line) and rcptools-S.time.
set -euo pipefail
out=${1:?usage: against_rcptools.sh OUT}
here=$(cd "$(dirname "$0")" && pwd)
packbench=${PACKBENCH:-target/release/packbench}
python=${PACKBENCH_ANCHORS:-anchors}/venv-rcpg/bin/python
seeds=${SEEDS:-1 2 3 4 5}
questions=${QUESTIONS:-mixture lognormal bidisperse}
nt=${NT:-1000}
spc=${SPC:-2}
phi=${PHI:-0.11}
optimizer=${OPTIMIZER:-auto}
timed() { /usr/bin/time -f "%U user %S sys %e wall" -o "$1" "${@:2}"; }

for s in $seeds; do
  for q in $questions; do
    dir=$out/$q
    [ "$q" != mixture ] && [ "$spc" != 2 ] && dir=$out/$q-spc$spc
    [ "$q" != mixture ] && [ "$optimizer" != auto ] && dir=$dir-$optimizer
    mkdir -p "$dir"
    case $q in
      mixture)
        question=(--family discrete --components 2 --max-ratio 10 --objective max-phi
          --N 1000 --seeds-per-candidate 1 --budget 60)
        rcptools=("$here/rcptools_mixture.py" "$dir/rcptools-$s" "$s") ;;
      lognormal)
        question=(--family lognormal --param sigma=0:0.4 --objective target --target 0.66
          --N "$nt" --seeds-per-candidate "$spc" --budget 32 --optimizer "$optimizer")
        rcptools=("$here/rcptools_target.py" lognormal "$s" "$nt") ;;
      bidisperse)
        question=(--family discrete --components 2 --fractions number --max-ratio 2
          --param x1=0.5 --objective min-ratio --target 0.65
          --N "$nt" --seeds-per-candidate "$spc" --budget 32 --optimizer "$optimizer")
        rcptools=("$here/rcptools_target.py" bidisperse "$s" "$nt") ;;
      *) echo "unknown question $q (mixture, lognormal or bidisperse)" >&2; exit 2 ;;
    esac
    if [ ! -f "$dir/packbench-$s/best.json" ]; then
      rm -rf "$dir/packbench-$s"
      timed "$dir/packbench-$s.time" "$packbench" design "${question[@]}" --Ndim 3 \
        --phi "$phi" --confirm 3 --seed "$s" --jobs 2 --quiet --out "$dir/packbench-$s"
    fi
    [ "$dir" != "$out/$q" ] && continue
    if [ ! -f "$dir/rcptools-$s.log" ] || ! grep -q '^RESULT ' "$dir/rcptools-$s.log"; then
      rm -rf "$dir/rcptools-$s"
      timed "$dir/rcptools-$s.time" "$python" "${rcptools[@]}" > "$dir/rcptools-$s.log" 2>&1
    fi
  done
done
