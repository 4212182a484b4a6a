"""`compare(executor=...)` spreads the runs of a comparison over any concurrent.futures
executor — a process pool, or a Dask cluster — and returns the rows this process makes."""

from concurrent.futures import ProcessPoolExecutor

import pytest

import packbench

KEYWORDS = dict(n=24, dim=2, seeds=2, seed=3, dist="bidisperse", d1=1.0, d2=1.4, p=0.5)
STABLE = ["method", "seed", "d", "n", "phi", "z_nonrattler", "rattlers", "iso_gap", "isostatic",
          "max_overlap", "steps", "termination", "knob_value"]


def stable(rows):
    return [{k: r[k] for k in STABLE} for r in rows]


@pytest.fixture(scope="module")
def here():
    return packbench.compare(["adam", "ls"], jobs=1, **KEYWORDS)


def test_a_process_pool_gives_the_rows_of_this_process(here):
    with ProcessPoolExecutor(max_workers=2) as pool:
        rows = packbench.compare(["adam", "ls"], executor=pool, **KEYWORDS)
    assert [(r["method"], r["seed"]) for r in rows] == [("adam", 3), ("ls", 3), ("adam", 4), ("ls", 4)]
    assert stable(rows) == stable(here)
    # Jammed bidisperse disks: adam 0.813-0.846 and ls 0.791-0.836 at N = 24 over seeds 1-20.
    assert all(0.77 < r["phi"] < 0.87 for r in rows), rows


def test_a_local_dask_cluster_gives_the_rows_of_this_process(here):
    import distributed  # installed by tests/run.sh: this test never skips
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        rows = packbench.compare(["adam", "ls"], executor=client.get_executor(), **KEYWORDS)
    assert stable(rows) == stable(here)


def test_bad_keywords_fail_before_any_task_is_sent():
    class Refusing:
        def submit(self, *a, **k):
            raise AssertionError("a task was sent")

    with pytest.raises(ValueError, match="seeds=0"):
        packbench.compare("adam", executor=Refusing(), n=10, dim=2, seeds=0)
