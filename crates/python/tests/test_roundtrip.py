"""Positions and diameters from NumPy come back bit-identical through Packing and a file."""

import numpy as np
import pytest

import packbench


def random_particles(n, d, seed):
    rng = np.random.default_rng(seed)
    # Values with all 53 bits of mantissa in use, strictly inside the unit box.
    positions = rng.random((n, d)) * (1 - 2e-3) + 1e-3
    diameters = rng.random(n) * 0.01 + 0.001
    return positions, diameters


@pytest.mark.parametrize("d", [2, 3, 5])
def test_arrays_round_trip_bit_identical(d):
    positions, diameters = random_particles(50, d, seed=d)
    p = packbench.Packing(positions, diameters)
    assert p.positions.dtype == np.float64 and p.positions.shape == (50, d)
    assert p.positions.tobytes() == positions.tobytes()
    assert p.diameters.tobytes() == diameters.tobytes()
    assert (p.n, p.dim, len(p)) == (50, d, 50)
    assert p.box == [1.0] * d and p.walls == [0] * d


@pytest.mark.parametrize("d", [2, 3])
def test_file_round_trip_bit_identical(tmp_path, d):
    positions, diameters = random_particles(64, d, seed=10 + d)
    p = packbench.Packing(positions, diameters, box=[1.0] * d, walls=[1] + [0] * (d - 1))
    path = tmp_path / "p.txt"
    p.write(str(path))
    back = packbench.Packing.read(str(path), box=[1.0] * d, walls=[1] + [0] * (d - 1))
    assert back.positions.tobytes() == positions.tobytes()
    assert back.diameters.tobytes() == diameters.tobytes()
    assert back == p
    assert back.phi == p.phi


def test_non_contiguous_and_integer_input_is_converted():
    positions, diameters = random_particles(20, 4, seed=3)
    view = positions[:, ::2]  # a strided view, 20×2
    p = packbench.Packing(view, diameters)
    assert p.positions.tobytes() == np.ascontiguousarray(view).tobytes()
    q = packbench.Packing([[0, 0], [0.5, 0.5]], [1, 1], box=[2, 2])
    assert q.diameters.dtype == np.float64 and q.diameters.tolist() == [1.0, 1.0]


def test_exports_write_their_formats(tmp_path):
    p = packbench.initial_packing(30, 3, seed=2)
    p.to_xyz(str(tmp_path / "p.xyz"))
    p.to_lammps(str(tmp_path / "p.data"))
    p.to_vtk(str(tmp_path / "p.vtk"))
    xyz = (tmp_path / "p.xyz").read_text().splitlines()
    assert xyz[0].strip() == "30" and "Lattice" in xyz[1]
    data = (tmp_path / "p.data").read_text()
    assert "atom_style sphere" in data and "\n30 atoms\n" in data and "Atoms # sphere" in data
    assert (tmp_path / "p.vtk").read_text().startswith("# vtk DataFile")


def test_initial_packing_matches_the_command_line(cli, tmp_path):
    p = packbench.initial_packing(200, 3, phi=0.1, dist="bidisperse", d1=1.0, d2=1.4, p=0.5, seed=7)
    assert abs(p.phi - 0.1) < 1e-12
    out = cli("init", "--N", 200, "--Ndim", 3, "--phi", 0.1, "--dist", "bidisperse",
              "--d1", 1.0, "--d2", 1.4, "--p", 0.5, "--seed", 7, "--output", "init.txt")
    assert out.returncode == 0, out.stderr
    cli_packing = packbench.Packing.read(str(tmp_path / "init.txt"))
    assert cli_packing.positions.tobytes() == p.positions.tobytes()
    assert cli_packing.diameters.tobytes() == p.diameters.tobytes()
