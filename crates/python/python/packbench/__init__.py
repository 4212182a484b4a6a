"""packbench: jammed and random close packings of spheres in any dimension.

The eight methods of ``packbench.methods()`` (adam, fire, ls, mls, closest-jammed,
closest-jammed-qp, calippso, seq-fill) on one shared core, with NumPy arrays in and out::

    import packbench
    start = packbench.initial_packing(200, 3, seed=1)   # no overlaps (random sequential addition)
    exact = packbench.pack("calippso", packbench.pack("adam", start, seed=1).packing)
    exact.metrics["isostatic"], exact.metrics["phi"]
    exact.packing.positions          # N×d float64
    rows = packbench.compare(["adam", "fire"], n=100, dim=2, seeds=2)

Every function calls the library the ``packbench`` command-line tool runs, so the same
start and seed give the same bits from Python and from the binary. ``Packing`` and
``Result`` pickle (their state is NumPy arrays and plain values), so process pools, joblib
and Dask carry them; ``compare(executor=...)`` spreads a comparison over any
``concurrent.futures.Executor``.
"""

from ._packbench import (
    Packing,
    Result,
    __version__,
    analyze,
    design,
    get_num_threads,
    initial_packing,
    methods,
    pack,
    set_num_threads,
    pores,
    voronoi,
)
from ._packbench import compare as _compare_here


def compare(methods=None, *, executor=None, **keywords):
    if executor is None:
        return _compare_here(methods, **keywords)
    # One task per (seed, method), in the order of the rows (seed-major, then method); each
    # task is the same comparison reduced to one seed and one method, so its row is the row
    # this process would have made.
    if keywords.get("progress"):
        raise ValueError("progress=True shows runs of this process; with executor=, watch the "
                         "executor's own dashboard")
    if isinstance(methods, str):
        names = [methods]
    elif methods is None:
        names = [m["name"] for m in globals()["methods"]()]
    else:
        names = list(methods)
    seeds = keywords.pop("seeds", None)
    seeds = 3 if seeds is None else seeds
    first = keywords.pop("seed", None)
    first = 1 if first is None else first
    keywords.pop("jobs", None)
    # Checks every keyword here, before any task is sent, with one cheap run list.
    if not isinstance(seeds, int) or isinstance(seeds, bool) or seeds < 1:
        raise ValueError(f"seeds={seeds!r}: seeds must be a whole number of at least 1")
    if not isinstance(first, int) or isinstance(first, bool) or first < 0:
        raise ValueError(f"seed={first!r}: seed must be a whole number of at least 0")
    futures = [
        executor.submit(_compare_here, [name], seed=first + k, seeds=1, jobs=1, **keywords)
        for k in range(seeds)
        for name in names
    ]
    try:
        return [row for f in futures for row in f.result()]
    except BaseException:
        for f in futures:
            f.cancel()
        raise


compare.__doc__ = _compare_here.__doc__
compare.__wrapped__ = _compare_here

__all__ = [
    "Packing",
    "Result",
    "__version__",
    "analyze",
    "compare",
    "design",
    "get_num_threads",
    "initial_packing",
    "methods",
    "pack",
    "set_num_threads",
    "pores",
    "voronoi",
]
