"""`analyze` of crystals gives their known φ and contact numbers, with the keys of the CLI."""

import json
import math

import numpy as np

import packbench


def fcc(cells, a=1.0):
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    grid = np.array([[i, j, k] for i in range(cells) for j in range(cells) for k in range(cells)])
    positions = ((grid[:, None, :] + basis[None, :, :]).reshape(-1, 3) + 0.25) * a
    diameters = np.full(len(positions), a / math.sqrt(2))
    return positions, diameters, [cells * a] * 3


def triangular(nx, ny):
    # Rows of unit disks, alternate rows shifted by 1/2; the box is nx × ny·√3/2.
    h = math.sqrt(3) / 2
    positions = np.array([[i + 0.5 * (j % 2) + 0.25, (j + 0.5) * h] for j in range(ny) for i in range(nx)])
    return positions, np.ones(len(positions)), [float(nx), ny * h]


def test_fcc_has_phi_pi_over_sqrt18_and_twelve_contacts():
    positions, diameters, box = fcc(3)
    m = packbench.analyze(positions, diameters, box=box)
    assert abs(m["phi"] - math.pi / math.sqrt(18)) < 1e-12
    assert m["rattlers"] == 0
    assert abs(m["z_mean"] - 12) < 1e-12 and abs(m["z_nonrattler"] - 12) < 1e-12
    assert m["contacts"] == 6 * len(positions)
    assert m["max_overlap"] < 1e-12


def test_triangular_lattice_has_phi_pi_over_2sqrt3_and_six_contacts():
    positions, diameters, box = triangular(6, 6)
    m = packbench.analyze(positions, diameters, box=box)
    assert abs(m["phi"] - math.pi / (2 * math.sqrt(3))) < 1e-12
    assert m["rattlers"] == 0 and abs(m["z_nonrattler"] - 6) < 1e-12
    # Over-constrained: 3N contacts against 2(N − 1) + 1 degrees of freedom.
    n = len(positions)
    assert m["iso_gap"] == 3 * n - (2 * (n - 1) + 1)
    assert not m["isostatic"]


def test_analyze_has_the_keys_and_values_of_the_command_line(cli, tmp_path):
    positions, diameters, box = fcc(2)
    p = packbench.Packing(positions, diameters, box=box)
    p.write(str(tmp_path / "fcc.txt"))
    out = cli("analyze", "fcc.txt", "--box", ",".join(map(str, box)))
    assert out.returncode == 0, out.stderr
    assert packbench.analyze(p) == json.loads(out.stdout)
