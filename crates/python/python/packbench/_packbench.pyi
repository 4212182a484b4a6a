"""Type hints of the native module of packbench (see the docstrings at run time)."""

from collections.abc import Callable, Mapping, Sequence
from typing import Any, Literal, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
OnInterrupt = Literal["raise", "return"]
ProgressCallback = Callable[[int, float, dict[str, float]], Optional[bool]]

class Packing:
    """Particles in a container: positions (N×d), diameters (N), container keywords as the
    command line's --box, --walls, --fix-height, --shell, --hemispheres."""

    def __init__(
        self,
        positions: ArrayLike,
        diameters: ArrayLike,
        *,
        box: Optional[Sequence[float]] = None,
        walls: Optional[Sequence[int]] = None,
        fix_height: bool = False,
        shell: Optional[Sequence[float]] = None,
        hemispheres: Optional[Sequence[float]] = None,
    ) -> None: ...
    @staticmethod
    def read(
        path: str,
        *,
        box: Optional[Sequence[float]] = None,
        walls: Optional[Sequence[int]] = None,
        fix_height: bool = False,
        shell: Optional[Sequence[float]] = None,
        hemispheres: Optional[Sequence[float]] = None,
    ) -> Packing:
        """Reads the RCPGenerator plain text format (container from the keywords, else the
        JSON sidecar beside the file, else a periodic unit box)."""
    def write(self, path: str) -> None:
        """Writes the RCPGenerator plain text format with round-trip precision."""
    def to_xyz(self, path: str) -> None:
        """Writes extended XYZ (OVITO)."""
    def to_lammps(self, path: str) -> None:
        """Writes a LAMMPS data file (atom_style sphere)."""
    def to_vtk(self, path: str) -> None:
        """Writes legacy VTK polydata (ParaView)."""
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """N×d particle centres (a new array on each access)."""
    @property
    def diameters(self) -> npt.NDArray[np.float64]:
        """N diameters (a new array on each access)."""
    @property
    def box(self) -> list[float]:
        """Side lengths of the container's box."""
    @property
    def walls(self) -> Optional[list[int]]:
        """0 periodic / 1 walled per axis, −t first for a ball over t axes; None for a shell
        or a hemisphere-cut brick."""
    @property
    def container(self) -> dict[str, Any]:
        """The full container as in the JSON sidecar."""
    @property
    def phi(self) -> float:
        """Packing fraction."""
    @property
    def dim(self) -> int:
        """Dimension d."""
    @property
    def n(self) -> int:
        """Number of particles N."""
    def __len__(self) -> int: ...

class Result:
    """What `pack` returns."""

    @property
    def packing(self) -> Packing:
        """The final packing."""
    @property
    def metrics(self) -> dict[str, Any]:
        """The keys of `packbench analyze`: phi, z_nonrattler, rattlers, iso_gap, …"""
    @property
    def trace(self) -> dict[str, npt.NDArray[Any]]:
        """step, time_s, phi and the method's quantities over the run."""
    @property
    def termination(self) -> str:
        """Why the run stopped (converged, jammed, max_steps, interrupted, …)."""
    @property
    def runtime_s(self) -> float:
        """Wall seconds of the method (analysis excluded)."""
    @property
    def steps(self) -> int:
        """Steps in the method's own unit."""
    @property
    def method(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def params(self) -> dict[str, Any]:
        """The complete parameters the method ran with."""
    @property
    def extra(self) -> dict[str, Any]:
        """Method-specific results."""

def initial_packing(
    n: int,
    dim: int,
    phi: float = 0.05,
    dist: str = "mono",
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    seed: int = 0,
    *,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    placement: Optional[Literal["random", "poisson"]] = None,
    **dist_params: Union[float, Sequence[float]],
) -> Packing:
    """A random initial packing at a low φ, as `packbench init` makes it."""

def pack(
    method: str,
    packing: Union[Packing, tuple[ArrayLike, ArrayLike], None] = None,
    *,
    seed: int = 0,
    max_steps: Optional[int] = None,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    contact_tol: float = 1e-6,
    force_balance: bool = True,
    progress: bool = False,
    callback: Optional[ProgressCallback] = None,
    on_interrupt: OnInterrupt = "raise",
    **params: Any,
) -> Result:
    """Runs a packing method (parameters by the names `packbench methods` lists)."""

def analyze(
    positions: Union[ArrayLike, Packing],
    diameters: Optional[ArrayLike] = None,
    *,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    contact_tol: float = 1e-6,
    force_balance: bool = True,
) -> dict[str, Any]:
    """The metrics of `packbench analyze` as a dict."""

def compare(
    methods: Union[str, Sequence[str], None] = None,
    *,
    n: Optional[int] = None,
    dim: Optional[int] = None,
    seeds: int = 3,
    seed: int = 1,
    refine: Optional[str] = None,
    jobs: Optional[int] = None,
    params: Optional[Mapping[str, Mapping[str, Any]]] = None,
    phi: Optional[float] = None,
    dist: Optional[str] = None,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    placement: Optional[Literal["random", "poisson"]] = None,
    progress: bool = False,
    on_interrupt: OnInterrupt = "raise",
    **dist_params: Union[float, Sequence[float]],
) -> list[dict[str, Any]]:
    """One dict per run with the fields of runs.csv."""

def methods() -> list[dict[str, Any]]:
    """The method registry: name, summary, accuracy_knob, params (defaults)."""

def voronoi(
    positions: Union[ArrayLike, Packing],
    diameters: Optional[ArrayLike] = None,
    *,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
) -> dict[str, Any]:
    """Radical Voronoi cells: the summaries of `packbench analyze --voronoi` plus the arrays
    `volumes`, `local_phi` and `faces` (one entry per particle)."""
    ...

def pores(
    positions: Union[ArrayLike, Packing],
    diameters: Optional[ArrayLike] = None,
    *,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    samples: int = 20000,
    lines: int = 1000,
    seed: int = 1,
    scaffold_cutoff: Optional[float] = None,
) -> dict[str, Any]:
    """The void space: `voronoi`, `pores` (D_i, D_f, distributions, the network as arrays),
    `chords` in a periodic box and `scaffold_fill` with a cut-off."""
    ...
