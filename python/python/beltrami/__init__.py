"""beltrami: discrete Laplace-Beltrami operators on triangle meshes, for surface metrology.

Meshes come from numpy arrays (``Mesh(vertices, faces)``), from files (``read``) or
from trimesh and Open3D objects (``from_trimesh``, ``from_open3d``); ``smooth`` takes
the options of ``beltrami smooth`` with the same words and defaults and returns the
smoothed mesh and the command line's ``--report`` as a dict.

    >>> import beltrami as bt
    >>> noisy = bt.generate("sphere", level=3, noise=0.2)
    >>> smoothed, report = bt.smooth(noisy, method="taubin", iterations=20)
    >>> report["stop"]
    'completed'
"""

from __future__ import annotations

from typing import Any

from ._beltrami import (
    FormatError,
    Mesh,
    MeshError,
    MetricsError,
    SmoothError,
    compare,
    decimate,
    delaunay,
    distances,
    fill_holes,
    fit_circle,
    fit_cylinder,
    fit_sphere,
    generate,
    info,
    laplacian,
    mass_matrix,
    quality,
    read,
    register_weight,
    remesh,
    residual,
    smooth,
    subdivide,
    weight_schemes,
    write,
)

__all__ = [
    "FormatError",
    "Mesh",
    "MeshError",
    "MetricsError",
    "SmoothError",
    "compare",
    "decimate",
    "delaunay",
    "distances",
    "fill_holes",
    "fit_circle",
    "fit_cylinder",
    "fit_sphere",
    "from_open3d",
    "from_trimesh",
    "generate",
    "info",
    "laplacian",
    "mass_matrix",
    "quality",
    "read",
    "register_weight",
    "remesh",
    "residual",
    "smooth",
    "subdivide",
    "to_open3d",
    "to_pyvista",
    "to_trimesh",
    "weight_schemes",
    "write",
]


def from_trimesh(mesh: Any) -> Mesh:
    """A ``Mesh`` from a ``trimesh.Trimesh`` (or anything with ``vertices`` and ``faces``).

    The vertices and faces are copied as they are: trimesh's own processing (merging,
    removing degenerate faces) is whatever the Trimesh object was built with.
    Raises ``MeshError`` when the faces are not an oriented 2-manifold.
    """
    return Mesh(mesh.vertices, mesh.faces)


def to_trimesh(mesh: Mesh) -> Any:
    """A ``trimesh.Trimesh`` with the mesh's vertices and faces, unprocessed.

    Needs trimesh (``pip install trimesh``) and a triangle mesh.
    """
    import trimesh

    return trimesh.Trimesh(
        vertices=mesh.vertices.copy(), faces=_triangles(mesh), process=False
    )


def from_open3d(mesh: Any) -> Mesh:
    """A ``Mesh`` from an ``open3d.geometry.TriangleMesh`` (its ``vertices`` and ``triangles``)."""
    import numpy as np

    return Mesh(np.asarray(mesh.vertices), np.asarray(mesh.triangles))


def to_open3d(mesh: Mesh) -> Any:
    """An ``open3d.geometry.TriangleMesh`` with the mesh's vertices and triangles.

    Needs Open3D (``pip install open3d``) and a triangle mesh.
    """
    import open3d

    return open3d.geometry.TriangleMesh(
        open3d.utility.Vector3dVector(mesh.vertices.copy()),
        open3d.utility.Vector3iVector(_triangles(mesh).astype("int32")),
    )


def to_pyvista(mesh: Mesh) -> Any:
    """A ``pyvista.PolyData`` with the mesh's vertices and faces (polygons too).

    Needs PyVista (``pip install pyvista``).
    """
    import numpy as np
    import pyvista

    faces = mesh.faces
    rows = faces if isinstance(faces, list) else list(faces)
    cells = np.concatenate([np.concatenate(([len(f)], f)) for f in rows]) if rows else []
    return pyvista.PolyData(mesh.vertices.copy(), np.asarray(cells, dtype=np.int64))


def _triangles(mesh: Mesh) -> Any:
    """The faces as an (M, 3) array; ``MeshError`` for a polygon mesh."""
    faces = mesh.faces
    if isinstance(faces, list) or faces.shape[1] != 3:
        raise MeshError("the mesh has polygon faces; triangulate it first")
    return faces
