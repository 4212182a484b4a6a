#!/usr/bin/env bash
# Whether two packbench binaries (before and after a restructure) write the same bytes:
# `pack --method M` for every method but closest-jammed-qp on a fixed 3D and 2D start (N = 64,
# seed 7; seq-fill fills its own 3D brick of 300), and the default `compare` (its packings, and
# runs.csv without the runtime column). One rayon thread each. Prints `same` or `DIFF` per file
# and exits 1 on any difference.
#
# Usage: scripts/same_bytes.sh OLD_BINARY NEW_BINARY [WORK_DIR]
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,8p "$0"; exit 2; }
old=$(realpath "$1") new=$(realpath "$2")
work=${3:-$(mktemp -d)}
mkdir -p "$work" && cd "$work"
export RAYON_NUM_THREADS=1
for d in 3 2; do
    "$new" init --N 64 --Ndim $d --seed 7 --output start$d.txt 2>/dev/null
done
for side in old new; do
    bin=${!side}
    mkdir -p $side
    for d in 3 2; do
        for m in adam fire ls mls closest-jammed calippso; do
            "$bin" pack --method $m --file start$d.txt --seed 7 --quiet --output $side/${m}_$d.txt >/dev/null 2>&1
        done
    done
    "$bin" pack --method seq-fill --N 300 --Ndim 3 --seed 7 --quiet --output $side/seq-fill.txt >/dev/null 2>&1
    "$bin" compare --quiet --out $side/compare >/dev/null 2>&1
    python3 - $side/compare/runs.csv > $side/runs-without-runtime.csv <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
w = csv.DictWriter(sys.stdout, [k for k in rows[0] if k != "runtime_s"])
w.writeheader()
for r in rows:
    w.writerow({k: v for k, v in r.items() if k != "runtime_s"})
PY
done
status=0
for f in old/*.txt old/compare/packings/*.txt old/runs-without-runtime.csv; do
    if cmp -s "$f" "new/${f#old/}"; then echo "same  ${f#old/}"; else echo "DIFF  ${f#old/}"; status=1; fi
done
exit $status
