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
        """Writes extended XYZ (OVITO): box, pbc flags, radii; two position columns in 2D."""
    def to_lammps(self, path: str) -> None:
        """Writes a LAMMPS data file (atom_style sphere) whose comments give the input lines
        (dimension, boundary) that read it."""
    def to_lammps_dump(self, path: str) -> None:
        """Writes a LAMMPS dump with pp/ff box bounds and radii (OVITO); no z column in 2D."""
    def to_vtp(self, path: str) -> None:
        """Writes VTK XML PolyData (ParaView, OVITO): Radius, Diameter, the box as FieldData."""
    def to_vtp_box(self, path: str) -> None:
        """Writes the box's edges as VTK XML PolyData lines (ParaView)."""
    def to_vtk(self, path: str) -> None:
        """Writes legacy VTK, vertices with to_vtp's arrays (older VTK readers, meshio; not OVITO)."""
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
    def to_dict(self) -> dict[str, Any]:
        """positions (N×d array), diameters (N array), container (dict); pickling uses it."""
    @classmethod
    def from_dict(cls, state: Mapping[str, Any]) -> Packing:
        """The packing of a to_dict() dict, bit for bit."""
    def with_phi(self, phi: float) -> Packing:
        """Diameters scaled to packing fraction phi; positions and container kept."""
    def with_box(self, box: Sequence[float]) -> Packing:
        """Positions scaled with a new box (axis by axis); diameters kept."""
    def relax(self, method: str = "fire", **keywords: Any) -> Result:
        """packbench.pack(method, self, **keywords): target_phi=, max_steps=, seed=, …"""
    def plot(self, ax: Any = None, **keywords: Any) -> Any:
        """matplotlib axes with the packing to scale (2D) or a slice of it (d ≥ 3)."""
    def _repr_html_(self) -> str:
        """The packbench view page, inline in Jupyter."""

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
    @property
    def frames(self) -> Optional[dict[str, npt.NDArray[Any]]]:
        """With pack(frames=K): step (K), phi (K), positions (K×N×d), diameters (K×N), box (K×d)."""
    def to_dict(self) -> dict[str, Any]:
        """The result as NumPy arrays and plain values; pickling uses it."""
    @classmethod
    def from_dict(cls, state: Mapping[str, Any]) -> Result:
        """The result of a to_dict() dict."""
    def _repr_html_(self) -> str:
        """The packbench view page of the run, inline in Jupyter."""

def initial_packing(
    n: int,
    dim: int,
    phi: float = 0.05,
    dist: Optional[str] = None,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    seed: Optional[int] = None,
    *,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    placement: Optional[Literal["rsa", "random", "poisson"]] = None,
    **dist_params: Union[float, Sequence[float]],
) -> Packing:
    """A random initial packing at a low φ, as `packbench init` makes it: no overlaps
    (random sequential addition) unless placement is "random" or "poisson"."""

def pack(
    method: str,
    packing: Union[Packing, tuple[ArrayLike, ArrayLike], None] = None,
    *,
    seed: Optional[int] = None,
    max_steps: Optional[int] = None,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    contact_tol: Optional[float] = None,
    force_balance: bool = True,
    progress: bool = False,
    callback: Optional[ProgressCallback] = None,
    on_interrupt: OnInterrupt = "raise",
    frames: Optional[int] = None,
    trace_every: Optional[int] = None,
    fixed: Optional[ArrayLike] = None,
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
    seeds: Optional[int] = None,
    seed: Optional[int] = None,
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
    placement: Optional[Literal["rsa", "random", "poisson"]] = None,
    progress: bool = False,
    on_interrupt: OnInterrupt = "raise",
    **dist_params: Union[float, Sequence[float]],
) -> list[dict[str, Any]]:
    """One dict per run with the fields of runs.csv (the packbench.compare wrapper adds
    executor=, any concurrent.futures.Executor)."""

def design(
    family: Literal[
        "lognormal", "powerlaw", "bidisperse", "weibull", "gamma", "mixture", "discrete"
    ],
    *,
    bounds: Optional[Mapping[str, Union[float, tuple[float, float], Sequence[float]]]] = None,
    objective: Literal["max-phi", "target", "min-ratio", "min-polydispersity"] = "max-phi",
    target: Optional[float] = None,
    max_ratio: Optional[float] = None,
    components: Optional[int] = None,
    fractions: Literal["volume", "number"] = "volume",
    draw: Literal["quantile", "random"] = "quantile",
    max_rattlers: Optional[float] = None,
    search_n: Optional[int] = None,
    n: Optional[int] = None,
    dim: Optional[int] = None,
    phi: Optional[float] = None,
    box: Optional[Sequence[float]] = None,
    walls: Optional[Sequence[int]] = None,
    fix_height: bool = False,
    shell: Optional[Sequence[float]] = None,
    hemispheres: Optional[Sequence[float]] = None,
    placement: Optional[Literal["rsa", "random", "poisson"]] = None,
    method: str = "adam",
    refine: Optional[str] = None,
    params: Optional[Mapping[str, Mapping[str, Any]]] = None,
    seeds_per_candidate: Optional[int] = None,
    seed: Optional[int] = None,
    budget: Optional[int] = None,
    population: Optional[int] = None,
    optimizer: Literal["auto", "cmaes", "bracket", "ego"] = "auto",
    screen: Literal["auto", "dw", "fg", "none"] = "auto",
    screen_margin: Optional[float] = None,
    confirm: Optional[int] = None,
    jobs: Optional[int] = None,
    progress: bool = False,
    on_interrupt: OnInterrupt = "raise",
) -> dict[str, Any]:
    """The search of `packbench design`: {"rows": one dict per evaluation with the columns of
    evaluations.csv, "best": the best distribution (params, diameters, confirm_mean,
    confirm_std, ...) or None, "generations", "packings", "stop"}."""

def methods() -> list[dict[str, Any]]:
    """The method registry: name, summary, accuracy_knob, params (defaults)."""

def set_num_threads(n: Optional[int]) -> None:
    """Threads of the methods' parallel loops in later runs (None: one per core)."""

def get_num_threads() -> int:
    """Threads later runs use."""
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
