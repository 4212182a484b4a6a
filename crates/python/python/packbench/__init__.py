"""packbench: jammed and random close packings of spheres in any dimension.

Seven published methods (adam, fire, ls, mls, closest-jammed, calippso, seq-fill) on one
shared core, with NumPy arrays in and out::

    import packbench
    start = packbench.initial_packing(1000, 3, seed=1)
    result = packbench.pack("adam", start, seed=1)
    result.packing.positions          # N×d float64
    result.metrics["phi"], result.metrics["z_nonrattler"]
    rows = packbench.compare(["adam", "mls"], n=200, dim=3, seeds=2)

Every function calls the library the ``packbench`` command-line tool runs, so the same
start and seed give the same bits from Python and from the binary.
"""

from ._packbench import (
    Packing,
    Result,
    __version__,
    analyze,
    compare,
    initial_packing,
    methods,
    pack,
    pores,
    voronoi,
)

__all__ = [
    "Packing",
    "Result",
    "__version__",
    "analyze",
    "compare",
    "initial_packing",
    "methods",
    "pack",
    "pores",
    "voronoi",
]
