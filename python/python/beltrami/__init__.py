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
    remove_flat_triangles,
    residual,
    smooth,
    study,
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
    "from_pyvista",
    "from_trimesh",
    "generate",
    "info",
    "laplacian",
    "mass_matrix",
    "quality",
    "read",
    "register_weight",
    "remesh",
    "remove_flat_triangles",
    "residual",
    "smooth",
    "study",
    "subdivide",
    "to_open3d",
    "to_pyvista",
    "to_trimesh",
    "weight_schemes",
    "write",
]


def from_trimesh(mesh: Any, *, repair: bool = False, triangulate: bool = False) -> Mesh:
    """A ``Mesh`` from a ``trimesh.Trimesh`` (or anything with ``vertices`` and ``faces``).

    The vertices and faces are copied as they are: trimesh's own processing (merging,
    removing degenerate faces) is whatever the Trimesh object was built with.
    Raises ``MeshError`` when the faces are not an oriented 2-manifold, unless
    ``repair=True``, which repairs them as ``Mesh(..., repair=True)`` does.
    """
    return Mesh(mesh.vertices, mesh.faces, repair=repair, triangulate=triangulate)


def to_trimesh(mesh: Mesh) -> Any:
    """A ``trimesh.Trimesh`` with the mesh's vertices and faces, unprocessed.

    Needs trimesh (``pip install trimesh``) and a triangle mesh.
    """
    import trimesh

    return trimesh.Trimesh(
        vertices=mesh.vertices.copy(), faces=_triangles(mesh), process=False
    )


def from_open3d(mesh: Any, *, repair: bool = False, triangulate: bool = False) -> Mesh:
    """A ``Mesh`` from an ``open3d.geometry.TriangleMesh`` (its ``vertices`` and ``triangles``).

    Duck-typed: anything whose ``vertices`` and ``triangles`` numpy can read as (N, 3)
    and (M, 3) arrays works; Open3D itself is not imported. Open3D's vectors are copied
    once into the mesh (``numpy.asarray`` of them is a view). Raises ``MeshError`` when
    the triangles are not an oriented 2-manifold, unless ``repair=True``, which repairs
    them as ``Mesh(..., repair=True)`` does.
    """
    import numpy as np

    return Mesh(
        np.asarray(mesh.vertices), np.asarray(mesh.triangles), repair=repair, triangulate=triangulate
    )


def to_open3d(mesh: Mesh) -> Any:
    """An ``open3d.geometry.TriangleMesh`` with the mesh's vertices and triangles.

    Needs Open3D (``pip install open3d``, which is not a dependency) and a triangle
    mesh (``MeshError`` for a polygon mesh).
    """
    import numpy as np
    import open3d

    return open3d.geometry.TriangleMesh(
        # Open3D takes writeable arrays only; `mesh.vertices` is a read-only copy.
        open3d.utility.Vector3dVector(np.array(mesh.vertices)),
        open3d.utility.Vector3iVector(np.ascontiguousarray(_triangles(mesh), dtype=np.int32)),
    )


def to_pyvista(mesh: Mesh) -> Any:
    """A ``pyvista.PolyData`` with the mesh's vertices and faces (polygons too).

    Needs PyVista (``pip install pyvista``, which is not a dependency). The faces become
    PyVista's flat cell array ``[k, v0, …, v(k-1), k, …]``.
    """
    import numpy as np
    import pyvista

    faces = mesh.faces
    if isinstance(faces, list):
        cells = (
            np.concatenate([np.concatenate(([len(f)], f)) for f in faces])
            if faces
            else np.zeros(0, dtype=np.int64)
        )
    else:
        counts = np.full((faces.shape[0], 1), faces.shape[1], dtype=np.int64)
        cells = np.hstack([counts, faces]).ravel()
    return pyvista.PolyData(mesh.vertices, cells.astype(np.int64))


def from_pyvista(mesh: Any, *, repair: bool = False, triangulate: bool = False) -> Mesh:
    """A ``Mesh`` from a ``pyvista.PolyData`` (its ``points`` and flat ``faces`` cell array).

    Duck-typed: anything with ``points`` ((N, 3)) and ``faces`` (``[k, v0, …, k, …]``)
    works; PyVista itself is not imported. Lines, vertices and strips of the PolyData
    are ignored; faces of different sizes are kept as they are (``repair=True,
    triangulate=True`` splits them into triangles, as ``Mesh`` does). Raises
    ``MeshError`` for a cell array that does not parse or faces that are no oriented
    2-manifold (``repair=True`` repairs those, as ``Mesh(..., repair=True)`` does).
    """
    import numpy as np

    cells = np.asarray(mesh.faces, dtype=np.int64).ravel()
    rows = []
    i = 0
    while i < len(cells):
        k = int(cells[i])
        if k < 3 or i + 1 + k > len(cells):
            raise MeshError(f"pyvista face cell array: bad vertex count {k} at offset {i}")
        rows.append(cells[i + 1 : i + 1 + k])
        i += 1 + k
    if any(len(r) != len(rows[0]) for r in rows):
        faces: Any = [r.tolist() for r in rows]
    else:
        faces = np.stack(rows) if rows else np.zeros((0, 3), dtype=np.int64)
    return Mesh(np.asarray(mesh.points), faces, repair=repair, triangulate=triangulate)


def _triangles(mesh: Mesh) -> Any:
    """The faces as an (M, 3) array; ``MeshError`` for a polygon mesh."""
    faces = mesh.faces
    if isinstance(faces, list) or faces.shape[1] != 3:
        raise MeshError(
            "the mesh has polygon faces; "
            "Mesh(vertices, faces, repair=True, triangulate=True) splits them into triangles"
        )
    return faces
