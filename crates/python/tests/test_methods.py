"""Every method of the registry runs from Python on a small 2D start."""

import pytest

import packbench

METHODS = packbench.methods()


def test_registry_lists_names_summaries_and_defaults():
    names = [m["name"] for m in METHODS]
    assert {"adam", "fire", "ls", "mls", "closest-jammed", "calippso", "seq-fill"} <= set(names)
    for m in METHODS:
        assert m["summary"] and m["accuracy_knob"] in m["params"]


@pytest.fixture(scope="module")
def start():
    return packbench.initial_packing(30, 2, dist="bidisperse", d1=1.0, d2=1.4, p=0.5, seed=3)


@pytest.mark.parametrize("name", [m["name"] for m in METHODS])
def test_method_runs_on_a_small_2d_start(start, name):
    r = packbench.pack(name, start, seed=3)
    assert r.method == name
    assert r.termination not in ("", "failed")
    m = r.metrics
    assert m["dim"] == 2 and m["n"] == r.packing.n > 0
    # Every method makes a dense packing from the dilute start (φ = 0.05).
    assert m["phi"] > 0.5, (name, m)
    assert m["max_overlap"] < 0.05, (name, m)
