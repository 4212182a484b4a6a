#!/usr/bin/env bash
# The table "pack from Python against packbench pack" of docs/BENCHMARKS.md (Python): the same
# adam run (3D monodisperse, N = 1000, periodic unit box, φ = 0.05, seed 1) by the binary and by
# the Python module, RUNS times each, CPU time (user + sys) and peak memory by GNU time.
#
#   PY=target/pyenv/bin/python scripts/tables/python_vs_binary.sh [--packbench BIN] [--runs 3] [--N 1000]
#
# PY is a python that imports packbench (made by crates/python/tests/run.sh); BIN defaults to
# $PACKBENCH, else target/release/packbench. Prints the Markdown table, then φ and steps of both
# runs (they must be the same bits) and the peak memory of each.
set -euo pipefail
pb=${PACKBENCH:-target/release/packbench}
runs=3
n=1000
while [ $# -gt 0 ]; do
  case $1 in
    --packbench) pb=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --N) n=$2; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
: "${PY:?set PY to a python that imports packbench}"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export RAYON_NUM_THREADS=1
"$PY" -c "import packbench; packbench.initial_packing($n, 3, seed=1).write('$dir/start.txt')"
cat > "$dir/pack.py" <<PYEOF
import packbench
r = packbench.pack("adam", packbench.Packing.read("$dir/start.txt"), seed=1)
print(repr(r.metrics["phi"]), r.steps)
PYEOF
bin_row="| binary (user + sys CPU s) |"
py_row="| Python (user + sys CPU s) |"
bin_sum=0; py_sum=0; bin_rss=0; py_rss=0
for i in $(seq "$runs"); do
  /usr/bin/time -o "$dir/t" -f '%U %S %M' "$pb" pack --method adam --file "$dir/start.txt" --seed 1 \
    --output "$dir/out" --quiet 2> "$dir/err"
  read -r u s m < "$dir/t"; c=$(printf '%.2f' "$(echo "$u + $s" | bc)"); bin_row="$bin_row $c |"; bin_sum=$(echo "$bin_sum + $c" | bc)
  [ "$m" -gt "$bin_rss" ] && bin_rss=$m
  py_out=$(/usr/bin/time -o "$dir/t" -f '%U %S %M' "$PY" "$dir/pack.py")
  read -r u s m < "$dir/t"; c=$(printf '%.2f' "$(echo "$u + $s" | bc)"); py_row="$py_row $c |"; py_sum=$(echo "$py_sum + $c" | bc)
  [ "$m" -gt "$py_rss" ] && py_rss=$m
done
header="| run |"; rule="|---|"
for i in $(seq "$runs"); do header="$header $i |"; rule="$rule---|"; done
echo "$header mean |"
echo "$rule---|"
echo "$bin_row $(printf '%.2f' "$(echo "scale=4; $bin_sum / $runs" | bc)") |"
echo "$py_row $(printf '%.2f' "$(echo "scale=4; $py_sum / $runs" | bc)") |"
echo
bin_out=$(python3 -c "import json; d = json.load(open('$dir/out.json')); print(repr(d['metrics']['phi']), d['steps'])")
echo "binary: φ = ${bin_out% *} after ${bin_out#* } steps; Python: φ = ${py_out% *} after ${py_out#* } steps"
echo "peak memory: binary $((bin_rss / 1024)) MB, Python $((py_rss / 1024)) MB"
