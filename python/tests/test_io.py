"""Reading, writing and `info`, and the exceptions of bad files."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import beltrami as bt

INFO_KEYS = {
    "file", "format", "vertices", "faces", "edges", "triangle_mesh", "boundary_loops",
    "boundary_loop_lengths", "components", "euler_characteristic", "closed", "genus",
    "component_genus", "isolated_vertices", "degenerate_faces", "bbox_min", "bbox_max",
    "mean_edge_length", "area", "volume", "repairs",
}


@pytest.mark.parametrize("ascii", [False, True])
def test_ply_round_trip_is_bit_exact(sphere, tmp_path, ascii):
    path = tmp_path / "sphere.ply"
    bt.write(path, sphere, ascii=ascii)
    back = bt.read(path)
    np.testing.assert_array_equal(back.vertices, sphere.vertices)
    np.testing.assert_array_equal(back.faces, sphere.faces)
    assert back.path == path


@pytest.mark.parametrize("suffix", [".obj", ".off", ".stl"])
def test_other_formats_round_trip(sphere, tmp_path, suffix):
    path = tmp_path / f"sphere{suffix}"
    bt.write(str(path), sphere)
    back = bt.read(str(path))
    assert (back.n_vertices, back.n_faces) == (sphere.n_vertices, sphere.n_faces)
    if suffix == ".stl":
        # STL stores float32 triangle corners; reading welds them in a new order.
        assert bt.info(back)["area"] == pytest.approx(bt.info(sphere)["area"], rel=1e-6)
        np.testing.assert_allclose(
            np.sort(back.vertices, axis=0), np.sort(sphere.vertices, axis=0), atol=1e-6
        )
    else:
        np.testing.assert_array_equal(back.vertices, sphere.vertices)


def test_scalars_are_written_as_ply_properties(sphere, tmp_path):
    path = tmp_path / "deviation.ply"
    values = np.linspace(-1, 1, sphere.n_vertices)
    bt.write(path, sphere, scalars={"deviation": values}, ascii=True)
    text = path.read_text()
    assert "property double deviation" in text
    assert bt.read(path).n_vertices == sphere.n_vertices


def test_scalars_need_a_ply_file(sphere, tmp_path):
    with pytest.raises(bt.FormatError, match="scalars are written to .ply files only"):
        bt.write(tmp_path / "a.obj", sphere, scalars={"d": np.zeros(sphere.n_vertices)})


def test_scalars_may_be_any_mapping(sphere, tmp_path):
    from types import MappingProxyType

    values = np.arange(sphere.n_vertices, dtype=float)
    bt.write(tmp_path / "a.ply", sphere, scalars=MappingProxyType({"d": values}))
    assert b"property double d" in (tmp_path / "a.ply").read_bytes()[:400]
    with pytest.raises(TypeError, match="must be a mapping"):
        bt.write(tmp_path / "b.ply", sphere, scalars=[values])


def test_scalars_of_the_wrong_length_are_a_format_error(sphere, tmp_path):
    with pytest.raises(bt.FormatError, match="has 3 values but the mesh has 642 vertices"):
        bt.write(tmp_path / "a.ply", sphere, scalars={"d": np.zeros(3)})


def test_missing_file_is_file_not_found(tmp_path):
    missing = tmp_path / "missing.ply"
    with pytest.raises(FileNotFoundError, match="missing.ply"):
        bt.read(missing)


def test_unwritable_directory_is_an_os_error(sphere, tmp_path):
    with pytest.raises(OSError):
        bt.write(tmp_path / "no" / "such" / "dir.ply", sphere)


def test_unknown_extension_is_a_format_error(tmp_path):
    path = tmp_path / "mesh.xyz"
    path.write_text("1 2 3\n")
    with pytest.raises(bt.FormatError, match=r"unsupported file extension \"xyz\""):
        bt.read(path)


def test_garbage_is_a_format_error_with_the_path(tmp_path):
    path = tmp_path / "bad.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nend_header\n0 0\n")
    with pytest.raises(bt.FormatError, match="bad.ply: "):
        bt.read(path)


def test_non_manifold_file_is_a_mesh_error_and_repair_fixes_it(tmp_path):
    path = tmp_path / "fan.off"
    path.write_text(
        "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n3 0 1 2\n3 1 0 3\n3 0 1 4\n"
    )
    with pytest.raises(bt.MeshError, match=r"fan.off: .*\(pass repair=True to repair it\)$"):
        bt.read(path)
    mesh = bt.read(path, repair=True)
    assert bt.info(mesh)["repairs"]["cut_edges"] == [[0, 1]]
    # STL would join the split copies again: refused; PLY keeps them.
    with pytest.raises(bt.FormatError, match="an STL file keeps no vertex indices"):
        bt.write(tmp_path / "fixed.stl", mesh)
    assert not (tmp_path / "fixed.stl").exists()
    bt.write(tmp_path / "fixed.ply", mesh)
    assert bt.info(bt.read(tmp_path / "fixed.ply"))["vertices"] == mesh.n_vertices


def test_stl_warns_about_vertices_in_no_face(tmp_path):
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]], dtype=float)
    mesh = bt.Mesh(vertices, np.array([[0, 1, 2]]))
    with pytest.warns(UserWarning, match="the 1 vertex in no face is not written"):
        bt.write(tmp_path / "a.stl", mesh)
    assert bt.read(tmp_path / "a.stl").n_vertices == 3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bt.write(tmp_path / "a.ply", mesh)
        bt.write(tmp_path / "b.stl", bt.Mesh(vertices[:3], np.array([[0, 1, 2]])))
    assert bt.read(tmp_path / "a.ply").n_vertices == 4


def test_weld_tolerance_is_checked(tmp_path):
    with pytest.raises(ValueError, match="at most 0.01"):
        bt.read(tmp_path / "a.stl", weld_tolerance=0.5)


def test_info_of_a_sphere(sphere, tmp_path):
    info = bt.info(sphere)
    assert set(info) == INFO_KEYS
    assert info["file"] is None and info["format"] is None
    assert (info["vertices"], info["faces"], info["edges"]) == (642, 1280, 1920)
    assert info["closed"] and info["genus"] == 0 and info["euler_characteristic"] == 2
    assert info["volume"] > 0 and info["area"] > 0
    path = tmp_path / "s.ply"
    bt.write(path, sphere)
    assert bt.info(bt.read(path))["format"] == "PLY"


def test_info_of_a_patch(patch):
    info = bt.info(patch)
    assert not info["closed"]
    assert info["boundary_loops"] == 1
    assert info["volume"] is None


def test_paths_may_be_str_bytes_or_pathlike(sphere, tmp_path):
    # As Python's own open(): bytes paths too; anything else names the argument.
    target = tmp_path / "a.ply"
    bt.write(bytes(target), sphere)
    assert bt.read(bytes(target)).n_vertices == sphere.n_vertices
    assert bt.read(str(target)).n_vertices == sphere.n_vertices
    with pytest.raises(TypeError, match="path: expected str, bytes or os.PathLike, got int"):
        bt.read(3)
    with pytest.raises(TypeError, match="path: expected str, bytes or os.PathLike, got list"):
        bt.write([str(target)], sphere)
