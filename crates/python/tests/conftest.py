"""Shared fixtures: the `packbench` binary of the same build, and running it."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


def _binary():
    given = os.environ.get("PACKBENCH_BIN")
    if given:
        return pathlib.Path(given)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    return target / os.environ.get("PACKBENCH_TEST_PROFILE", "release-tests") / "packbench"


@pytest.fixture
def packbench_bin():
    """Path of the `packbench` binary of the test build (PACKBENCH_BIN, else the target dir's)."""
    path = _binary()
    if not path.is_file():
        pytest.fail(
            f"the packbench binary is not at {path}: build it with "
            "`cargo build --profile release-tests -p packbench` or set PACKBENCH_BIN"
        )
    return path


@pytest.fixture
def cli(packbench_bin, tmp_path):
    """Runs the binary in tmp_path; returns the CompletedProcess."""

    def run(*args):
        return subprocess.run(
            [str(packbench_bin), *map(str, args)],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            check=False,
        )

    return run


def cli_sentence(stderr):
    """The binary's error sentence without `packbench: ` and a `FILE:LINE:COLUMN: ` place."""
    text = stderr.strip().splitlines()[-1]
    assert text.startswith("packbench: "), text
    text = text[len("packbench: "):]
    parts = text.split(": ", 1)
    head = parts[0].split(":")
    if len(parts) == 2 and len(head) == 3 and head[1].isdigit() and head[2].isdigit():
        return parts[1]
    return text
