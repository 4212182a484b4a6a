"""`voronoi` and `pores` give the known cells and holes of crystals, as arrays and dicts."""

import math

import numpy as np
import pytest

import packbench


def fcc(cells, a=1.0):
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    grid = np.array([[i, j, k] for i in range(cells) for j in range(cells) for k in range(cells)])
    positions = ((grid[:, None, :] + basis[None, :, :]).reshape(-1, 3) + 0.25) * a
    diameters = np.full(len(positions), a / math.sqrt(2))
    return positions, diameters, [cells * a] * 3


def test_fcc_cells_are_a_quarter_cube_with_twelve_faces():
    positions, diameters, box = fcc(2, a=1.5)
    v = packbench.voronoi(positions, diameters, box=box)
    assert v["volumes"].shape == (32,)
    assert np.allclose(v["volumes"], 1.5**3 / 4, rtol=1e-12)
    assert np.all(v["faces"] == 12)
    assert np.allclose(v["local_phi"], math.pi / math.sqrt(18), rtol=1e-12)
    assert abs(v["total_volume"] - 27.0) < 1e-10


def test_fcc_octahedral_hole_is_the_largest_included_sphere():
    positions, diameters, box = fcc(2)
    r = diameters[0] / 2
    out = packbench.pores(positions, diameters, box=box, samples=2000, lines=100)
    p = out["pores"]
    assert abs(p["included_sphere_diameter"] - 2 * (math.sqrt(2) - 1) * r) < 1e-9
    assert p["centres"].shape == (p["pores"], 3)
    assert p["throat_pores"].shape == (p["throats"], 2)
    assert len(p["throat_diameters"]) == p["throats"]
    assert len(p["pore_size_samples"]) == 2000
    c = out["chords"]
    assert c["void"]["count"] == len(c["void"]["lengths"])


def test_overlapping_centres_raise_value_error():
    with pytest.raises(ValueError, match="same centre"):
        packbench.voronoi(np.array([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]), np.ones(2), box=[3, 3, 3])
