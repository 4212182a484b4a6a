#!/usr/bin/env bash
# Builds the codes packbench is compared against, so that every comparison in
# docs/BENCHMARKS.md can be rerun from a clone:
#   rcpgenerator        RCPGenerator 1.0 (Desmond & Weeks; github.com/KD-physics/RCPGenerator):
#                       its Python package (C++ with pybind11, and rcptools) in a virtual
#                       environment, $ANCHORS/venv-rcpg/bin/python
#   packing-generation  PackingGeneration (Baranau; github.com/VasiliBaranov/packing-generation):
#                       LS, force-biased and closest-jammed generation,
#                       $ANCHORS/pg/_Release/PackingGeneration.exe
#
# Usage: scripts/anchors/build.sh [rcpgenerator] [packing-generation]   (default: both)
# Environment:
#   PACKBENCH_ANCHORS   where to build (default: anchors/ at the repository root, git-ignored);
#                       the comparison scripts read the same variable.
#   RCPGENERATOR_SRC, PACKING_GENERATION_SRC
#                       a local clone or bare git directory to build from instead of cloning
#                       the public repository (then no network is needed).
#   RCPGENERATOR_REF, PACKING_GENERATION_REF   a commit or tag to build (default: the newest).
#   JOBS                build parallelism (default 2). FORCE=1 rebuilds what already works.
# Needs git, g++ with OpenMP, make, python3 with venv and pip (cmake comes from pip).
# Both are built for this CPU (-march=native): rebuild on another machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
dest=${PACKBENCH_ANCHORS:-$root/anchors}
mkdir -p "$dest"
dest=$(cd "$dest" && pwd)
jobs=${JOBS:-2}
wanted=("$@")
[ ${#wanted[@]} -gt 0 ] || wanted=(rcpgenerator packing-generation)

# checkout NAME URL SRC REF: a work tree of the code at $dest/NAME-src, from SRC (a clone or a
# bare git directory) when given, else cloned from URL; REF picks the commit. Prints the commit.
checkout() {
  local name=$1 url=$2 src=$3 ref=$4 tree="$dest/$1-src"
  rm -rf "$tree"
  git clone -q --no-checkout "${src:-$url}" "$tree"
  local g=(git -C "$tree")
  [ -z "$ref" ] || "${g[@]}" update-ref --no-deref HEAD "$("${g[@]}" rev-parse "$ref^{commit}")"
  # Check out every file whose content the clone has: a local snapshot may lack its largest
  # files (notebooks, data), which the builds do not need.
  "${g[@]}" ls-tree -r --format='%(objectname) %(path)' HEAD |
    while read -r oid path; do
      "${g[@]}" cat-file -e "$oid" 2>/dev/null && printf '%s\0' "$path"
    done | "${g[@]}" checkout HEAD --pathspec-from-file=- --pathspec-file-nul -- 2>/dev/null ||
    "${g[@]}" checkout -q HEAD -- .
  "${g[@]}" rev-parse HEAD >"$tree/.anchor-commit"
  echo "$name: $(cat "$tree/.anchor-commit")" >&2
}

build_rcpgenerator() {
  local venv="$dest/venv-rcpg"
  if [ -z "${FORCE:-}" ] && "$venv/bin/python" -c 'import rcpgenerator' 2>/dev/null; then
    echo "rcpgenerator: already built in $venv"
    return
  fi
  checkout rcpg https://github.com/KD-physics/RCPGenerator.git \
    "${RCPGENERATOR_SRC:-}" "${RCPGENERATOR_REF:-}"
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --upgrade pip
  # The package's own CMake build (scikit-build-core), Release, with its native-CPU option.
  CMAKE_BUILD_PARALLEL_LEVEL=$jobs "$venv/bin/pip" install -q \
    -C cmake.define.RCP_NATIVE_OPTIMIZATION=ON -C cmake.build-type=Release \
    "$dest/rcpg-src/python_code/python"
  "$venv/bin/python" -c 'import rcpgenerator; print("rcpgenerator:", rcpgenerator.__file__)'
}

build_packing_generation() {
  local exe="$dest/pg/_Release/PackingGeneration.exe"
  if [ -z "${FORCE:-}" ] && [ -x "$exe" ]; then
    echo "packing-generation: already built at $exe"
    return
  fi
  checkout pg-git https://github.com/VasiliBaranov/packing-generation.git \
    "${PACKING_GENERATION_SRC:-}" "${PACKING_GENERATION_REF:-}"
  rm -rf "$dest/pg"
  cp -r "$dest/pg-git-src" "$dest/pg"
  # Its own Eclipse-generated makefiles (-O3, bundled Boost and Eigen headers), for this CPU.
  find "$dest/pg/_Release" -name subdir.mk -exec sed -i 's/-O3 /-O3 -march=native /' {} +
  if ! make -C "$dest/pg/_Release" -j"$jobs" all >"$dest/pg/build.log" 2>&1; then
    tail -30 "$dest/pg/build.log" >&2
    exit 1
  fi
  echo "packing-generation: $exe"
}

for w in "${wanted[@]}"; do
  case $w in
    rcpgenerator) build_rcpgenerator ;;
    packing-generation) build_packing_generation ;;
    *) echo "unknown anchor '$w' (rcpgenerator, packing-generation)" >&2; exit 2 ;;
  esac
done
