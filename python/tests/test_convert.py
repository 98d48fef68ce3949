"""Round trips through numpy, trimesh, Open3D and PyVista (each skipped when absent)."""

from __future__ import annotations

import numpy as np
import pytest

import beltrami as bt


def assert_same(a: bt.Mesh, b: bt.Mesh) -> None:
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.faces, b.faces)


def test_numpy_round_trip_copies_once_and_keeps_the_bits(sphere):
    vertices = sphere.vertices.copy()  # writeable, C-contiguous float64
    mesh = bt.Mesh(vertices, sphere.faces)
    assert_same(mesh, sphere)
    # The mesh owns its copy: changing the array afterwards does not change it.
    vertices[0] = 99.0
    np.testing.assert_array_equal(mesh.vertices[0], sphere.vertices[0])
    # Other layouts and dtypes are converted first and give the same mesh.
    fortran = np.asfortranarray(sphere.vertices)
    assert_same(bt.Mesh(fortran, sphere.faces.astype(np.int32)), sphere)
    strided = np.hstack([sphere.vertices, sphere.vertices])[:, :3]
    assert_same(bt.Mesh(strided, sphere.faces), sphere)
    out = mesh.vertices
    assert out.dtype == np.float64 and out.flags.c_contiguous and not out.flags.writeable


def test_trimesh_round_trip(sphere):
    trimesh = pytest.importorskip("trimesh")
    t = bt.to_trimesh(sphere)
    assert isinstance(t, trimesh.Trimesh)
    assert_same(bt.from_trimesh(t), sphere)
    assert t.is_watertight and t.volume == pytest.approx(bt.info(sphere)["volume"], rel=1e-12)


def _open3d():
    try:
        import open3d
    except ImportError as e:  # also a missing system library (libusb, libGL)
        pytest.skip(f"open3d is not importable: {e}")
    return open3d


def test_open3d_round_trip(sphere, patch):
    open3d = _open3d()
    for mesh in (sphere, patch):
        o = bt.to_open3d(mesh)
        assert isinstance(o, open3d.geometry.TriangleMesh)
        assert len(o.vertices) == mesh.n_vertices and len(o.triangles) == mesh.n_faces
        assert_same(bt.from_open3d(o), mesh)
    # Open3D's own processing keeps what the mesh is: a closed, oriented surface.
    o = bt.to_open3d(sphere)
    assert o.is_watertight() and o.is_orientable()
    assert o.get_volume() == pytest.approx(bt.info(sphere)["volume"], rel=1e-12)
    # A mesh built in Open3D comes in as beltrami reads it.
    box = open3d.geometry.TriangleMesh.create_box(1.0, 2.0, 3.0)
    mesh = bt.from_open3d(box)
    assert mesh.is_closed and bt.info(mesh)["volume"] == pytest.approx(6.0, rel=1e-12)


def test_pyvista_round_trip(sphere, patch):
    pyvista = pytest.importorskip("pyvista")
    for mesh in (sphere, patch):
        p = bt.to_pyvista(mesh)
        assert isinstance(p, pyvista.PolyData)
        assert p.n_points == mesh.n_vertices and p.n_cells == mesh.n_faces
        assert_same(bt.from_pyvista(p), mesh)
    p = bt.to_pyvista(sphere)
    assert p.volume == pytest.approx(bt.info(sphere)["volume"], rel=1e-9)
    # Quads stay quads.
    quads = bt.Mesh(
        np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], float),
        np.array([[0, 1, 2, 3], [1, 4, 5, 2]]),
    )
    q = bt.to_pyvista(quads)
    assert q.n_cells == 2
    assert_same(bt.from_pyvista(q), quads)
    # A cube from PyVista (quads) comes in, and its triangulation too.
    cube = pyvista.Cube()
    assert bt.info(bt.from_pyvista(cube.triangulate().clean()))["closed"]


def test_duck_typed_inputs_need_no_package(sphere):
    class Open3dLike:
        vertices = sphere.vertices
        triangles = sphere.faces.astype(np.int32)

    class PyvistaLike:
        points = sphere.vertices
        faces = np.hstack([np.full((sphere.n_faces, 1), 3), sphere.faces]).ravel()

    assert_same(bt.from_open3d(Open3dLike()), sphere)
    assert_same(bt.from_pyvista(PyvistaLike()), sphere)

    class Broken:
        points = sphere.vertices
        faces = np.array([3, 0, 1])

    with pytest.raises(bt.MeshError, match="cell array"):
        bt.from_pyvista(Broken())

    # Faces of different sizes (a triangle beside a quad, sharing the edge 0-2) are
    # kept as they are, or split into triangles with the repair.
    class Mixed:
        points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 1, 0], [-1, 0, 0]], dtype=float)
        faces = np.array([3, 0, 1, 2, 4, 0, 2, 3, 4])

    mixed = bt.from_pyvista(Mixed())
    assert mixed.n_faces == 2 and [len(f) for f in mixed.faces] == [3, 4]
    split = bt.from_pyvista(Mixed(), repair=True, triangulate=True)
    assert split.n_faces == 3 and split.faces.shape == (3, 3)
    assert bt.info(split)["repairs"]["triangulated_faces"] == [1]
