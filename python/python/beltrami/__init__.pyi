"""Type stubs of the beltrami package."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from typing import Any, Literal, Optional, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, bytes, os.PathLike[str], os.PathLike[bytes]]

class MeshError(ValueError):
    """A mesh that is not a valid oriented 2-manifold, or arrays that do not describe one."""

class FormatError(ValueError):
    """A mesh file that cannot be decoded."""

class SmoothError(ValueError):
    """Smoothing could not run on this mesh or had to stop."""

class MetricsError(ValueError):
    """A measurement could not be computed."""

class Mesh:
    """Vertex positions, faces and their half-edge connectivity, validated when built."""

    def __init__(
        self,
        vertices: npt.ArrayLike,
        faces: npt.ArrayLike,
        *,
        repair: bool = False,
        triangulate: bool = False,
    ) -> None:
        """`repair=True` repairs the faces (as `read(path, repair=True)`) instead of
        raising MeshError for a non-manifold or inconsistently oriented face list;
        `triangulate=True` (with `repair=True`) also splits polygons into triangles."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """The (N, 3) coordinates (a read-only copy)."""
    @property
    def faces(self) -> Union[npt.NDArray[np.int64], list[npt.NDArray[np.int64]]]:
        """(M, 3) for triangles, (M, k) for k-gons, a list of arrays for mixed polygons."""
    @property
    def n_vertices(self) -> int: ...
    @property
    def n_faces(self) -> int: ...
    @property
    def n_edges(self) -> int: ...
    @property
    def is_triangle_mesh(self) -> bool: ...
    @property
    def is_closed(self) -> bool: ...
    @property
    def path(self) -> Optional[os.PathLike[str]]:
        """The file the mesh was read from, or None."""
    def __len__(self) -> int: ...

def read(
    path: _Path,
    *,
    weld_tolerance: float = 1e-6,
    lenient: bool = False,
    repair: bool = False,
    triangulate: bool = False,
) -> Mesh:
    """Reads a .ply, .stl, .obj or .off mesh, or a .x3p or .sdf height map (in metres,
    as a triangulated grid), and builds its connectivity. `triangulate=True` (with
    `repair=True`) splits polygons into triangles."""

def write(
    path: _Path,
    mesh: Mesh,
    scalars: Optional[Mapping[str, npt.ArrayLike]] = None,
    *,
    ascii: bool = False,
    force: bool = False,
    sync: bool = True,
) -> None:
    """Writes a mesh file; the format follows the extension. A write-protected file
    is replaced only with `force=True` (PermissionError otherwise). `sync=False` leaves
    out the flushes to disk (the file is still replaced atomically; a power loss soon
    after may leave the old or a partial file). `scalars` (any mapping) go to .ply files
    only; FormatError otherwise, and for an STL file of a mesh whose repair on reading
    split vertices (STL would join them again). An STL file stores triangles only: a
    UserWarning says when vertices in no face are left out."""

def info(mesh: Mesh) -> dict[str, Any]:
    """Counts, topology and geometry, with the keys of `beltrami info --json`."""

def smooth(
    mesh: Mesh,
    weights: str = "cotangent",
    lam: Optional[float] = None,
    iterations: Optional[int] = None,
    boundary: Literal["fixed", "free", "curve"] = "fixed",
    method: Literal["explicit", "taubin", "hc", "implicit"] = "explicit",
    update: Literal["every", "once"] = "every",
    normalize: Optional[Literal["sum", "area"]] = None,
    *,
    vertex_area: Optional[Literal["mixed", "barycentric"]] = None,
    cotangent_negative: Literal["keep", "clamp", "abs"] = "keep",
    summation: Literal["rows", "scatter"] = "rows",
    time: Optional[float] = None,
    cutoff: Optional[float] = None,
    until_change: Optional[float] = None,
    mu: Optional[float] = None,
    hc_alpha: Optional[float] = None,
    hc_beta: Optional[float] = None,
    solver: Optional[Literal["cg", "cholesky"]] = None,
    pin: Optional[Union[Sequence[int], npt.ArrayLike]] = None,
    preserve_volume: bool = False,
    on_iteration: Optional[Callable[[int, dict[str, Any]], Any]] = None,
    progress: bool = False,
    max_iterations: int = 1_000_000,
    step_stats: bool = True,
) -> tuple[Mesh, dict[str, Any]]:
    """Laplacian diffusion smoothing with the options of `beltrami smooth`."""

def generate(
    surface: Literal["flens", "sphere", "block", "golfball"],
    *,
    noise: Optional[float] = None,
    absolute_noise: bool = False,
    seed: int = 1,
    level: Optional[int] = None,
    shuffle: Optional[int] = None,
    size: Literal["paper", "small"] = "paper",
    holes: Optional[int] = None,
    hole_radius: Optional[float] = None,
) -> Mesh:
    """One of the paper's test surfaces, as `beltrami generate` writes it."""

def compare(mesh: Mesh, reference: Mesh, *, samples: Optional[int] = None) -> dict[str, Any]:
    """A mesh against a reference surface, with the keys of `beltrami compare --json`."""

def distances(
    points: Union[Mesh, npt.ArrayLike], reference: Mesh, *, signed: bool = False
) -> npt.NDArray[np.float64]:
    """Per-point distance to the reference surface (signed: positive outside)."""

def fit_sphere(points: Union[Mesh, npt.ArrayLike], *, weighted: bool = False) -> dict[str, Any]:
    """The least-squares sphere, with the keys of `beltrami fit sphere --json`."""

def fit_circle(points: Union[Mesh, npt.ArrayLike], *, weighted: bool = False) -> dict[str, Any]:
    """The least-squares circle, with the keys of `beltrami fit circle --json`."""

def fit_cylinder(points: Union[Mesh, npt.ArrayLike], *, weighted: bool = False) -> dict[str, Any]:
    """The least-squares cylinder, with the keys of `beltrami fit cylinder --json`."""

def residual(
    measured: Mesh,
    smoothed: Optional[Mesh] = None,
    *,
    form: Optional[str] = None,
    quadrature: Literal["lumped", "exact"] = "lumped",
    remove_mean: bool = False,
    smr: Sequence[float] = (),
    smc: Sequence[float] = (),
) -> dict[str, Any]:
    """ISO 25178-2 parameters of the residual, with the keys of `beltrami residual --json`
    and `heights` (the residual per vertex)."""

def quality(mesh: Mesh, reference: Optional[Mesh] = None) -> dict[str, Any]:
    """Triangle quality, with the keys of `beltrami info --quality --json`'s `quality`."""

def subdivide(mesh: Mesh, scheme: Literal["loop", "sqrt3"] = "loop", steps: int = 1) -> Mesh:
    """Loop or sqrt(3) subdivision, as `beltrami subdivide`; old vertices keep their indices."""

def delaunay(
    mesh: Mesh, max_dihedral: Optional[float] = None, max_flips: Optional[int] = None
) -> tuple[Mesh, dict[str, Any]]:
    """Edge flips until no cotangent weight is negative, as `beltrami delaunay --json`."""

def remove_flat_triangles(
    mesh: Mesh, max_height_ratio: float = 1e-12, max_move: float = 0.0
) -> tuple[Mesh, dict[str, Any]]:
    """Flat triangles (caps, needles) removed by flips, deletions and zero-length
    collapses (with `max_move`, collapses that move a vertex up to that far), as
    `beltrami repair --flat-faces --json` (its `flat_triangles`), with `vertex_origin`."""

def remesh(
    mesh: Mesh,
    edge_length: Optional[float] = None,
    *,
    edge_length_relative: Optional[float] = None,
    adaptive: Union[bool, tuple[Optional[float], Optional[float], Optional[float]], None] = None,
    iterations: int = 10,
    features: Optional[float] = None,
    feature_edges: Optional[npt.ArrayLike] = None,
    projection: bool = True,
    smooth_projection: bool = True,
    progress: bool = False,
) -> tuple[Mesh, dict[str, Any]]:
    """Isotropic remeshing, as `beltrami remesh --json` (`smooth_projection=False` is
    `--faceted`)."""

def decimate(
    mesh: Mesh,
    vertices: Optional[int] = None,
    *,
    ratio: Optional[float] = None,
    max_error: Optional[float] = None,
    max_normal_deviation: Optional[float] = None,
    keep_boundary: bool = False,
    placement: Optional[Literal["optimal", "endpoint"]] = None,
    quality_threshold: Optional[float] = None,
    openmesh: bool = False,
    max_aspect_ratio: Optional[float] = None,
    max_distance: Optional[float] = None,
    plane_weights: Optional[Literal["area", "uniform"]] = None,
    stabilizer: Optional[float] = None,
    flip_tolerance: Optional[float] = None,
    fit_rounds: Optional[int] = None,
    distance: bool = True,
    progress: bool = False,
) -> tuple[Mesh, dict[str, Any]]:
    """Quadric-error decimation, as `beltrami decimate --json`. `None` means the
    default ("optimal", 0.4, "area", 0.0, 0.2, 2); options that could not take effect
    (with `openmesh=True`, or a fit or flips with a bound that excludes them) raise
    ValueError."""

def fill_holes(
    mesh: Mesh,
    *,
    max_loop_edges: Optional[int] = None,
    fill_all: bool = False,
    refine: bool = True,
    fair: bool = True,
    progress: bool = False,
) -> tuple[Mesh, dict[str, Any]]:
    """Hole filling, as `beltrami fill-holes --json` (`progress=True`: a tqdm bar of the
    boundary loops)."""

def laplacian(
    mesh: Mesh,
    weights: str = "cotangent",
    normalize: Optional[Literal["sum", "area"]] = "sum",
    *,
    vertex_area: Literal["mixed", "barycentric"] = "mixed",
    cotangent_negative: Literal["keep", "clamp", "abs"] = "keep",
) -> Any:
    """The smoother's Laplacian as a scipy.sparse CSR matrix (L @ vertices = L x)."""

def mass_matrix(mesh: Mesh, *, vertex_area: Literal["mixed", "barycentric"] = "mixed") -> Any:
    """The diagonal matrix of vertex areas as a scipy.sparse CSR matrix."""

def register_weight(
    name: str,
    function: Callable[[dict[str, npt.NDArray[Any]]], npt.ArrayLike],
    *,
    description: str = "",
    depends_on_positions: bool = True,
    replace: bool = False,
) -> None:
    """Registers a weight scheme computed by a vectorised Python function over halfedges."""

def weight_schemes() -> list[str]:
    """The names of the registered weight schemes."""

def from_trimesh(mesh: Any, *, repair: bool = False, triangulate: bool = False) -> Mesh:
    """A Mesh from a trimesh.Trimesh (anything with vertices and faces)."""

def to_trimesh(mesh: Mesh) -> Any:
    """A trimesh.Trimesh with the mesh's vertices and faces, unprocessed."""

def from_open3d(mesh: Any, *, repair: bool = False, triangulate: bool = False) -> Mesh:
    """A Mesh from an open3d.geometry.TriangleMesh."""

def to_open3d(mesh: Mesh) -> Any:
    """An open3d.geometry.TriangleMesh with the mesh's vertices and triangles."""

def to_pyvista(mesh: Mesh) -> Any:
    """A pyvista.PolyData with the mesh's vertices and faces."""

def from_pyvista(mesh: Any, *, repair: bool = False, triangulate: bool = False) -> Mesh:
    """A Mesh from a pyvista.PolyData (its points and flat faces cell array)."""

def study(
    out: _Path = "study",
    *,
    surfaces: Sequence[Literal["flens", "sphere", "block", "golfball"]] = (
        "flens",
        "sphere",
        "block",
        "golfball",
    ),
    weights: Optional[Sequence[str]] = None,
    iterations: Sequence[int] = (10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 200),
    lam: float = 0.8,
    noise: float = 0.2,
    absolute_noise: bool = False,
    seed: int = 1,
    seeds: int = 3,
    boundary: Literal["fixed", "free", "curve"] = "free",
    update: Literal["every", "once"] = "every",
    small: bool = False,
    countermeasure_weights: str = "cotangent",
    no_countermeasures: bool = False,
    cotangent_negative: Literal["keep", "clamp", "abs"] = "keep",
    normalize: Literal["sum", "area"] = "sum",
    vertex_area: Literal["mixed", "barycentric"] = "mixed",
    remesh: Optional[float] = None,
    remesh_relative: Optional[float] = None,
    no_remesh: bool = False,
    no_scan_example: bool = False,
) -> dict[str, Any]:
    """The comparison study, as `beltrami study`: writes `out`, returns the paths and verdicts."""
