"""Packings and results pickle, copy and round-trip through plain dicts of NumPy arrays, so
process pools carry them."""

import copy
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import packbench


@pytest.fixture(scope="module")
def result():
    return packbench.pack("adam", packbench.initial_packing(60, 2, dist="bidisperse", d1=1, d2=1.4,
                                                            p=0.5, seed=4), seed=4)


def same_result(a, b):
    assert a.packing == b.packing
    assert a.packing.positions.tobytes() == b.packing.positions.tobytes()
    assert a.metrics == b.metrics and a.params == b.params and a.extra == b.extra
    assert (a.termination, a.steps, a.method, a.seed, a.runtime_s) == (
        b.termination, b.steps, b.method, b.seed, b.runtime_s)
    assert set(a.trace) == set(b.trace)
    for k in a.trace:
        np.testing.assert_array_equal(a.trace[k], b.trace[k])


def test_packing_pickles_and_copies_bit_for_bit():
    p = packbench.initial_packing(50, 3, walls=[1, 0, 0], box=[1, 2, 1], seed=1)
    for q in (pickle.loads(pickle.dumps(p)), copy.deepcopy(p), copy.copy(p),
              packbench.Packing.from_dict(p.to_dict())):
        assert q == p and q.positions.tobytes() == p.positions.tobytes()
        assert q.container == p.container
    d = p.to_dict()
    assert isinstance(d["positions"], np.ndarray) and d["positions"].shape == (50, 3)
    assert isinstance(d["diameters"], np.ndarray) and isinstance(d["container"], dict)


def test_result_pickles_and_copies(result):
    for r in (pickle.loads(pickle.dumps(result)), copy.deepcopy(result),
              packbench.Result.from_dict(result.to_dict())):
        assert isinstance(r, packbench.Result)
        same_result(r, result)


def test_from_dict_refuses_bad_state(result):
    d = result.to_dict()
    d.pop("metrics")
    with pytest.raises(ValueError, match="needs `metrics`"):
        packbench.Result.from_dict(d)
    with pytest.raises(ValueError, match="needs `diameters`"):
        packbench.Packing.from_dict({"positions": np.zeros((2, 2)), "container": {}})


def jam(seed):
    start = packbench.initial_packing(60, 2, dist="bidisperse", d1=1, d2=1.4, p=0.5, seed=seed)
    return start, packbench.pack("adam", start, seed=seed)


def test_a_process_pool_runs_four_packings_and_returns_them():
    with ProcessPoolExecutor(max_workers=2) as pool:
        runs = list(pool.map(jam, range(4)))
    assert len(runs) == 4
    for seed, (start, r) in enumerate(runs):
        assert isinstance(r, packbench.Result) and r.packing.n == 60
        # jammed disks (adam at N = 60: 0.825-0.845 over seeds 0-15), nearly overlap-free, the
        # same bits as a run in this process
        assert 0.80 < r.metrics["phi"] < 0.87 and r.metrics["max_overlap"] < 1e-3, r.metrics
        here = packbench.pack("adam", start, seed=seed)
        assert here.packing.positions.tobytes() == r.packing.positions.tobytes()
