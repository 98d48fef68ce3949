"""Meshes from and to numpy arrays, and the errors of bad arrays."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import beltrami as bt

FIXTURES = pathlib.Path(__file__).resolve().parents[2] / "fixtures"

TETRA_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_numpy_round_trip_is_exact():
    rng = np.random.default_rng(1)
    v = TETRA_V + rng.normal(scale=1e-3, size=TETRA_V.shape)
    mesh = bt.Mesh(v, TETRA_F)
    assert mesh.vertices.dtype == np.float64
    assert mesh.faces.dtype == np.int64
    np.testing.assert_array_equal(mesh.vertices, v)
    np.testing.assert_array_equal(mesh.faces, TETRA_F)
    assert (mesh.n_vertices, mesh.n_faces, mesh.n_edges) == (4, 4, 6)
    assert mesh.is_closed and mesh.is_triangle_mesh
    assert len(mesh) == 4


def test_any_real_and_integer_dtype_and_layout():
    v32 = np.asfortranarray(TETRA_V.astype(np.float32))
    f32 = TETRA_F.astype(np.uint32)
    mesh = bt.Mesh(v32, f32)
    np.testing.assert_array_equal(mesh.vertices, TETRA_V)
    mesh = bt.Mesh(TETRA_V.tolist(), TETRA_F.tolist())
    np.testing.assert_array_equal(mesh.faces, TETRA_F)


def test_arrays_are_read_only_copies():
    mesh = bt.Mesh(TETRA_V, TETRA_F)
    with pytest.raises(ValueError):
        mesh.vertices[0, 0] = 5.0
    copy = mesh.vertices.copy()
    copy[0, 0] = 5.0
    assert mesh.vertices[0, 0] == 0.0


def test_quads_come_back_as_quads():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    mesh = bt.Mesh(v, [[0, 1, 2, 3]])
    assert mesh.faces.shape == (1, 4)
    assert not mesh.is_triangle_mesh


@pytest.mark.parametrize(
    ("vertices", "faces", "message"),
    [
        (TETRA_V[:, :2], TETRA_F, r"vertices must be an \(N, 3\) array, got shape \(4, 2\)"),
        (np.zeros(12), TETRA_F, r"vertices must be an \(N, 3\) array"),
        (
            np.where(np.arange(12).reshape(4, 3) == 7, np.nan, TETRA_V),
            TETRA_F,
            r"vertex 2 has a non-finite coordinate \(NaN\)",
        ),
        (TETRA_V, TETRA_F.astype(float), "faces must be an integer array"),
        (TETRA_V, TETRA_F[:, :2], r"faces must be an \(M, 3\) array"),
        (
            TETRA_V,
            np.array([[0, 2, 1], [0, 1, 7]]),
            "face 1 refers to vertex 7, but there are only 4 vertices",
        ),
        (
            TETRA_V,
            np.array([[0, 2, 1], [0, -1, 3]]),
            "face 1 refers to vertex -1, but there are only 4 vertices",
        ),
        (TETRA_V, np.array([[0, 1, 1]]), "face 0 lists vertex 1 more than once"),
    ],
)
def test_bad_arrays_raise_mesh_error_naming_the_element(vertices, faces, message):
    with pytest.raises(bt.MeshError, match=message):
        bt.Mesh(vertices, faces)


def test_mesh_error_is_a_value_error():
    assert issubclass(bt.MeshError, ValueError)
    assert issubclass(bt.FormatError, ValueError)
    assert issubclass(bt.SmoothError, ValueError)


@pytest.mark.parametrize("name", ["MeshError", "FormatError", "SmoothError", "MetricsError"])
def test_the_exceptions_pickle_as_the_packages_own(name):
    # As a process pool or Dask sends them back from a worker: the class that comes back
    # is the one `except bt.MeshError` catches.
    import pickle

    cls = getattr(bt, name)
    assert cls.__module__ == "beltrami"
    back = pickle.loads(pickle.dumps(cls("face 3 refers to vertex 9")))
    assert type(back) is cls and str(back) == "face 3 refers to vertex 9"


def test_non_manifold_edge_is_refused():
    v = np.vstack([TETRA_V, [[0.5, 0.5, -1.0]]])
    # Three faces on the edge 0-1.
    f = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(bt.MeshError, match="non-manifold|orientation"):
        bt.Mesh(v, f)


def test_repair_true_repairs_what_read_would():
    v = np.vstack([TETRA_V, [[0.5, 0.5, -1.0]]])
    f = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    # The error says how to get past it; an index out of range has no such hint.
    with pytest.raises(bt.MeshError, match=r"\(pass repair=True to repair it\)$"):
        bt.Mesh(v, f)
    with pytest.raises(bt.MeshError) as bad_index:
        bt.Mesh(v, [[0, 1, 9]])
    assert "repair=True" not in str(bad_index.value)
    mesh = bt.Mesh(v, f, repair=True)
    repairs = bt.info(mesh)["repairs"]
    assert repairs["cut_edges"] == [[0, 1]]
    assert mesh.n_faces == 3 and mesh.n_vertices > len(v)
    # The same as reading the file with repair=True.
    class Shape:
        vertices = v
        faces = f

    same = bt.from_trimesh(Shape(), repair=True)
    np.testing.assert_array_equal(same.faces, mesh.faces)
    np.testing.assert_array_equal(same.vertices, mesh.vertices)
    # A sound mesh keeps its faces; a vertex no face uses goes, as read(repair=True)
    # removes it.
    sound = bt.Mesh(np.vstack([TETRA_V, [[9.0, 9.0, 9.0]]]), TETRA_F, repair=True)
    np.testing.assert_array_equal(sound.faces, TETRA_F)
    assert sound.n_vertices == 4
    assert bt.info(sound)["repairs"]["removed_vertices"] == [4]
    # A face of two vertices is dropped by the repair, named without it.
    with pytest.raises(bt.MeshError, match="face 1 has 2 vertices"):
        bt.Mesh(TETRA_V, [[0, 1, 2], [1, 3]])
    dropped = bt.Mesh(TETRA_V, [[0, 1, 2], [1, 3]], repair=True)
    assert dropped.n_faces == 1
    # A repair that leaves no face is refused.
    with pytest.raises(bt.MeshError, match="left none of the 1 face"):
        bt.Mesh(TETRA_V, [[0, 0, 1]], repair=True)


def test_repr_names_the_counts():
    assert repr(bt.Mesh(TETRA_V, TETRA_F)) == "Mesh(4 vertices, 4 faces)"


def test_trimesh_round_trip():
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.icosphere(subdivisions=2)
    mesh = bt.from_trimesh(box)
    np.testing.assert_array_equal(mesh.vertices, box.vertices)
    np.testing.assert_array_equal(mesh.faces, box.faces)
    back = bt.to_trimesh(mesh)
    assert isinstance(back, trimesh.Trimesh)
    np.testing.assert_array_equal(back.vertices, box.vertices)
    np.testing.assert_array_equal(back.faces, box.faces)
    assert bt.info(mesh)["volume"] == pytest.approx(back.volume, rel=1e-12)


def test_open3d_round_trip():
    o3d = pytest.importorskip("open3d")
    sphere = o3d.geometry.TriangleMesh.create_sphere(resolution=8)
    mesh = bt.from_open3d(sphere)
    np.testing.assert_array_equal(mesh.vertices, np.asarray(sphere.vertices))
    back = bt.to_open3d(mesh)
    np.testing.assert_array_equal(np.asarray(back.triangles), np.asarray(sphere.triangles))


def test_duck_typed_from_trimesh():
    class Shape:
        vertices = TETRA_V
        faces = TETRA_F

    assert bt.from_trimesh(Shape()).n_faces == 4


def test_a_polygon_mesh_round_trips_through_its_list_of_faces():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    mixed = bt.Mesh(v, [[0, 1, 2, 3], [1, 4, 2]])
    faces = mixed.faces
    assert [f.tolist() for f in faces] == [[0, 1, 2, 3], [1, 4, 2]]
    assert not any(f.flags.writeable for f in faces)
    again = bt.Mesh(mixed.vertices, faces)
    assert [f.tolist() for f in again.faces] == [[0, 1, 2, 3], [1, 4, 2]]
    with pytest.raises(bt.MeshError, match="face 1 has 2 vertices"):
        bt.Mesh(v, [[0, 1, 2, 3], [1, 4]])
    with pytest.raises(bt.MeshError, match="face 1 must be a sequence of vertex indices"):
        bt.Mesh(v, [[0, 1, 2, 3], [1.5, 4, 2]])
    with pytest.raises(bt.MeshError, match="face 1 refers to vertex 9"):
        bt.Mesh(v, [[0, 1, 2, 3], [1, 9, 2]])
    with pytest.raises(bt.MeshError, match="face 1 has 0 vertices"):
        bt.Mesh(v, [[0, 1, 2, 3], []])


def test_no_faces_and_unsigned_indices_beyond_int64():
    points = bt.Mesh(TETRA_V, [])
    assert points.n_faces == 0 and len(points.vertices) == 4
    assert bt.Mesh(TETRA_V, np.zeros((0, 3), dtype=int)).n_faces == 0
    # Rows without columns are not "no faces".
    with pytest.raises(bt.MeshError, match="got shape"):
        bt.Mesh(TETRA_V, np.zeros((4, 0), dtype=int))
    with pytest.raises(bt.MeshError, match="no faces; subdivide needs a surface"):
        bt.subdivide(points, "loop", steps=2**62)
    # Every editing call refuses a mesh without faces, as the commands do.
    for call, name in [
        (lambda m: bt.fill_holes(m), "fill_holes"),
        (lambda m: bt.delaunay(m), "delaunay"),
        (lambda m: bt.remove_flat_triangles(m), "remove_flat_triangles"),
    ]:
        for empty in (points, bt.Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int))):
            with pytest.raises(bt.MeshError, match=f"no faces; {name} needs a surface"):
                call(empty)
    huge = np.array([[0, 1, 2], [0, 2, 2**64 - 1]], dtype=np.uint64)
    with pytest.raises(bt.MeshError, match="face 1 refers to vertex 18446744073709551615"):
        bt.Mesh(TETRA_V, huge)


def test_a_mesh_pickles_and_copies():
    import copy
    import pickle

    mesh = bt.Mesh(TETRA_V, TETRA_F)
    back = pickle.loads(pickle.dumps(mesh))
    assert np.array_equal(back.vertices, mesh.vertices)
    assert np.array_equal(back.faces, mesh.faces)
    assert copy.copy(mesh) is mesh and copy.deepcopy(mesh) is mesh


def test_polygons_are_split_into_triangles_with_the_repair():
    cube = str(FIXTURES / "cube_quads.obj")
    quads = bt.read(cube)
    assert quads.n_faces == 6
    for mesh in (
        bt.read(cube, repair=True, triangulate=True),
        bt.Mesh(quads.vertices, quads.faces, repair=True, triangulate=True),
    ):
        assert mesh.n_faces == 12 and mesh.faces.shape == (12, 3)
        np.testing.assert_array_equal(mesh.vertices, quads.vertices)
        assert bt.info(mesh)["repairs"]["triangulated_faces"] == [0, 1, 2, 3, 4, 5]
        assert bt.info(mesh)["closed"]
        bt.subdivide(mesh)  # a command that needs triangles takes it
    with pytest.raises(ValueError, match="triangulate=True applies with repair=True"):
        bt.read(cube, triangulate=True)
    with pytest.raises(ValueError, match="triangulate=True applies with repair=True"):
        bt.Mesh(quads.vertices, quads.faces, triangulate=True)
    with pytest.raises(bt.MeshError, match="triangulate=True"):
        bt.subdivide(quads)
