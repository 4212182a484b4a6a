"""Bad input raises ValueError with the sentence the command line prints."""

import numpy as np
import pytest

import packbench
from conftest import cli_sentence


@pytest.fixture
def start_file(tmp_path):
    packbench.initial_packing(20, 3, seed=1).write(str(tmp_path / "start.txt"))
    return "start.txt"


def bad_file(tmp_path, row, value):
    p = packbench.initial_packing(5, 3, seed=1)
    positions, diameters = p.positions, p.diameters
    lines = [" ".join(repr(float(v)) for v in [*x, dia]) for x, dia in zip(positions, diameters)]
    fields = lines[row].split()
    fields[value[0]] = value[1]
    lines[row] = " ".join(fields)
    (tmp_path / "bad.txt").write_text("\n".join(lines) + "\n")
    return positions, diameters


def test_nan_position(cli, tmp_path):
    positions, diameters = bad_file(tmp_path, 1, (0, "NaN"))
    out = cli("analyze", "bad.txt")
    assert out.returncode == 2
    positions[1, 0] = np.nan
    with pytest.raises(ValueError) as e:
        packbench.Packing(positions, diameters)
    assert str(e.value) == "positions[1, 0]: " + cli_sentence(out.stderr)
    with pytest.raises(ValueError, match="not a finite number"):
        packbench.analyze(positions, diameters)


def test_negative_diameter(cli, tmp_path):
    positions, diameters = bad_file(tmp_path, 3, (3, "-1"))
    out = cli("analyze", "bad.txt")
    assert out.returncode == 2
    diameters[3] = -1
    with pytest.raises(ValueError) as e:
        packbench.pack("adam", (positions, diameters))
    assert str(e.value) == "diameters[3]: " + cli_sentence(out.stderr)


def test_wrong_shape(cli, start_file):
    p = packbench.initial_packing(20, 3, seed=1)
    out = cli("analyze", start_file, "--box", "1,1")
    assert out.returncode == 2
    with pytest.raises(ValueError) as e:
        packbench.Packing(p.positions, p.diameters, box=[1, 1])
    # The binary's sentence, with the keyword the user typed in place of the flag.
    assert "--box has 2 lengths" in cli_sentence(out.stderr)
    assert str(e.value) == cli_sentence(out.stderr).replace("--box", "box=")
    with pytest.raises(ValueError, match="N×d array"):
        packbench.Packing(p.positions.ravel(), p.diameters)
    with pytest.raises(ValueError, match="one per row of positions"):
        packbench.Packing(p.positions, p.diameters[:-1])


def test_unknown_method(cli, start_file, tmp_path):
    out = cli("pack", "--method", "simulated-annealing", "--file", start_file, "--seed", 1)
    assert out.returncode == 2
    start = packbench.Packing.read(str(tmp_path / start_file))
    with pytest.raises(ValueError) as e:
        packbench.pack("simulated-annealing", start)
    assert str(e.value) == cli_sentence(out.stderr)


def test_unknown_parameter(cli, start_file, tmp_path):
    out = cli("pack", "--method", "adam", "--file", start_file, "--seed", 1, "--set", "learning_rate=0.1")
    assert out.returncode == 2
    start = packbench.Packing.read(str(tmp_path / start_file))
    with pytest.raises(ValueError) as e:
        packbench.pack("adam", start, learning_rate=0.1)
    assert str(e.value) == cli_sentence(out.stderr)
    assert "learning_rate" in str(e.value) and "delta_phi_tol" in str(e.value)


def test_bad_scene_and_keywords():
    with pytest.raises(ValueError, match='dist="bidisperse" needs d1='):
        packbench.initial_packing(10, 2, dist="bidisperse")
    with pytest.raises(ValueError, match="size-distribution parameters are"):
        packbench.initial_packing(10, 2, diameter=2.0)
    with pytest.raises(ValueError, match="a Packing has its container"):
        packbench.pack("adam", packbench.initial_packing(10, 2), box=[2, 2])
    with pytest.raises(ValueError, match="on_interrupt"):
        packbench.pack("adam", packbench.initial_packing(10, 2), on_interrupt="ignore")


def test_refused_export_is_a_value_error(tmp_path):
    # xyz, LAMMPS and VTK hold three coordinates: the core refuses a 4D packing.
    p = packbench.initial_packing(10, 4, seed=1)
    with pytest.raises(ValueError, match="cannot be exported"):
        p.to_xyz(str(tmp_path / "never-written.xyz"))
    assert not (tmp_path / "never-written.xyz").exists()
