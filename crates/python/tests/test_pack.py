"""`pack("adam", …)` jams a 3D monodisperse packing near random close packing, reproducibly,
and bit for bit as the `packbench` binary does from the same start and seed."""

import re

import numpy as np
import pytest

import packbench

SEED = 1


@pytest.fixture(scope="module")
def start():
    return packbench.initial_packing(1000, 3, seed=SEED)


@pytest.fixture(scope="module")
def adam(start):
    return packbench.pack("adam", start, seed=SEED)


def test_adam_jams_near_rcp(adam):
    m = adam.metrics
    assert 0.630 <= m["phi"] <= 0.650, m
    assert abs(m["z_nonrattler"] - 6.0) <= 0.15, m
    assert adam.packing.n == 1000 and adam.packing.dim == 3
    assert adam.termination and adam.steps > 0
    assert adam.method == "adam" and adam.seed == SEED
    assert adam.params["delta_phi_tol"] > 0


def test_trace_is_numpy_columns_over_the_run(adam):
    t = adam.trace
    assert {"step", "time_s", "phi"} <= set(t)
    n = len(t["step"])
    assert n > 1 and all(isinstance(v, np.ndarray) and len(v) == n for v in t.values())
    assert t["step"].dtype == np.uint64 and np.all(np.diff(t["step"].astype(np.int64)) >= 0)
    assert abs(t["phi"][-1] - adam.metrics["phi"]) < 0.01
    assert len(t) > 3  # the method's own quantities (energy, …) are columns too


def test_same_seed_gives_identical_arrays(start, adam):
    again = packbench.pack("adam", start, seed=SEED)
    assert again.packing.positions.tobytes() == adam.packing.positions.tobytes()
    assert again.packing.diameters.tobytes() == adam.packing.diameters.tobytes()
    assert again.steps == adam.steps


def test_result_equals_the_binarys_bit_for_bit(cli, tmp_path, start, adam):
    start.write(str(tmp_path / "start.txt"))
    out = cli("pack", "--method", "adam", "--file", "start.txt", "--seed", SEED,
              "--output", "out", "--quiet")
    assert out.returncode == 0, out.stderr
    binary = packbench.Packing.read(str(tmp_path / "out.txt"))
    assert binary.positions.tobytes() == adam.packing.positions.tobytes()
    assert binary.diameters.tobytes() == adam.packing.diameters.tobytes()


def test_pairs_and_container_keywords_are_a_start():
    p = packbench.initial_packing(40, 2, box=[2.0, 1.0], walls=[1, 0], seed=4)
    r = packbench.pack("adam", (p.positions, p.diameters), box=[2.0, 1.0], walls=[1, 0], seed=4)
    same = packbench.pack("adam", p, seed=4)
    assert r.packing == same.packing
    assert r.packing.walls == [1, 0] and r.packing.box == [2.0, 1.0]


def test_max_steps_and_parameters_reach_the_method():
    p = packbench.initial_packing(100, 3, seed=5)
    r = packbench.pack("ls", p, seed=5, max_steps=20, rate=0.5)
    assert r.params["rate"] == 0.5
    assert r.termination == "max_steps"


def test_callback_receives_progress_and_can_stop_the_run():
    seen = []

    def callback(step, phi, values):
        seen.append((step, phi, dict(values)))
        return len(seen) >= 2

    p = packbench.initial_packing(1000, 3, seed=6)
    r = packbench.pack("mls", p, seed=6, rate_final=1e-9, callback=callback)
    assert len(seen) >= 2 and all(0 < phi < 1 for _, phi, _ in seen)
    assert all(isinstance(v, dict) and v for _, _, v in seen)
    assert r.termination == "interrupted"
    assert r.packing.phi > p.phi


def test_progress_line_without_tqdm(capsys, monkeypatch):
    import packbench._progress as progress

    monkeypatch.setattr(progress, "_tqdm", None)
    p = packbench.initial_packing(50, 2, seed=8)
    r = packbench.pack("ls", p, seed=8, progress=True)
    assert r.packing.n == 50
    # Without tqdm the bar is drawn as tqdm draws it, on stderr (stdout untouched): a line per
    # progress report at most every two seconds, and one when the run ends. This run is too
    # short for a report to be due, so that last line may be the only one.
    out, err = capsys.readouterr()
    assert out == ""
    lines = [line for line in err.splitlines() if line.startswith("ls: ")]
    assert lines, err
    bar = re.compile(r"ls: +(\d+)%\|([#0-9 ]{20})\| \d\d:\d\d(?: step (\d+)  phi (0\.\d{6}).*)?$")
    parsed = [bar.match(line) for line in lines]
    assert all(parsed), lines
    # ls stops at its pressure cap, its own rule: the last line is the full bar.
    assert r.termination == "pressure_cap", r.termination
    assert parsed[-1].group(1) == "100" and parsed[-1].group(2) == "#" * 20, lines[-1]
