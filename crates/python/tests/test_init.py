"""Initial packings: overlap-free random sequential addition by default (RCPGenerator's
`InitializeParticles`), an error above the φ it reaches, the overlapping Poisson placement by
name, and the same bytes as `packbench init`."""

import numpy as np
import pytest

import packbench


def smallest_gap(p):
    """min over pairs of r_ij − (D_i + D_j)/2, minimum image on periodic axes."""
    x, dia, box = p.positions, p.diameters, np.asarray(p.box)
    periodic = np.array([w == 0 for w in p.walls])
    delta = x[:, None, :] - x[None, :, :]
    delta[..., periodic] -= box[periodic] * np.round(delta[..., periodic] / box[periodic])
    r = np.sqrt((delta ** 2).sum(-1))
    gap = r - (dia[:, None] + dia[None, :]) / 2
    np.fill_diagonal(gap, np.inf)
    return gap.min()


@pytest.mark.parametrize("dim, phi", [(2, 0.45), (3, 0.3)])
def test_default_start_has_no_overlaps_at_the_phi_asked(dim, phi):
    p = packbench.initial_packing(400, dim, phi=phi, dist="bidisperse", d1=1, d2=1.4, p=0.5, seed=3)
    assert abs(p.phi - phi) < 1e-12
    assert smallest_gap(p) >= 0.0
    assert packbench.analyze(p, force_balance=False)["max_overlap"] == 0.0


def test_walls_keep_whole_spheres_inside():
    p = packbench.initial_packing(300, 3, phi=0.25, walls=[1, 1, 0], seed=2)
    x, r = p.positions, p.diameters / 2
    assert np.all(x[:, :2] >= r[:, None] - 1e-12) and np.all(x[:, :2] <= 1 - r[:, None] + 1e-12)
    assert smallest_gap(p) >= 0.0


def test_phi_above_what_sequential_addition_reaches_is_an_error():
    # Equal spheres saturate near 0.38 under random sequential addition; 0.9 cannot be placed.
    with pytest.raises(ValueError, match="could not place a non-overlapping particle") as e:
        packbench.initial_packing(200, 3, phi=0.9, seed=1)
    assert "poisson" in str(e.value)


def test_the_overlapping_placements_are_kept_by_name():
    for placement in ("poisson", "random"):
        p = packbench.initial_packing(400, 3, phi=0.3, seed=3, placement=placement)
        assert smallest_gap(p) < -0.3 * p.diameters[0], placement
    # and they take any φ below 1, as before
    assert abs(packbench.initial_packing(50, 3, phi=0.9, placement="poisson").phi - 0.9) < 1e-12


def test_the_command_line_places_the_same_spheres(cli, tmp_path):
    p = packbench.initial_packing(300, 3, phi=0.3, seed=5)
    out = cli("init", "--N", 300, "--Ndim", 3, "--phi", 0.3, "--seed", 5, "--output", "i.txt")
    assert out.returncode == 0, out.stderr
    assert packbench.Packing.read(str(tmp_path / "i.txt")).positions.tobytes() == p.positions.tobytes()
    bad = cli("init", "--N", 200, "--Ndim", 3, "--phi", 0.9, "--seed", 1)
    assert bad.returncode == 2 and "could not place a non-overlapping particle" in bad.stderr
