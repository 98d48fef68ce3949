"""remesh, decimate, fill_holes, compare, read and write: the limits, refusals and report
keys an audit found wrong, as the command line has them."""

from __future__ import annotations

import inspect
import os
import pathlib
import stat

import numpy as np
import pytest

import beltrami as bt

FIXTURES = pathlib.Path(__file__).resolve().parents[2] / "fixtures"


@pytest.fixture(scope="module")
def ico() -> bt.Mesh:
    return bt.generate("sphere", level=2)


@pytest.mark.parametrize("length", [1e100, 1e155, 1e200, 1e308])
def test_a_huge_target_length_is_refused_as_too_long(ico, length):
    with pytest.raises(bt.MeshError, match="too long for this surface"):
        bt.remesh(ico, edge_length=length)


def test_huge_relative_and_adaptive_lengths_are_refused_too(ico):
    with pytest.raises(bt.MeshError, match="too long"):
        bt.remesh(ico, edge_length_relative=1e200)
    with pytest.raises(bt.MeshError, match="too long"):
        bt.remesh(ico, adaptive=(1e155, 1e155, None))


def test_isolated_vertices_do_not_stop_remeshing():
    mesh = bt.read(FIXTURES / "bad" / "isolated_vertices.obj")
    out, report = bt.remesh(mesh, edge_length=0.1)
    assert report["faces"] > 0 and len(out.faces) == report["faces"]


@pytest.mark.parametrize(
    "options, name",
    [
        ({"openmesh": True, "placement": "optimal"}, "placement"),
        ({"openmesh": True, "placement": "endpoint"}, "placement"),
        ({"openmesh": True, "fit_rounds": 3}, "fit_rounds"),
        ({"openmesh": True, "fit_rounds": 0}, "fit_rounds"),
        ({"openmesh": True, "quality_threshold": 0.4}, "quality_threshold"),
        ({"openmesh": True, "flip_tolerance": 0.2}, "flip_tolerance"),
        ({"openmesh": True, "stabilizer": 0.1}, "stabilizer"),
        ({"openmesh": True, "plane_weights": "area"}, "plane_weights"),
        ({"fit_rounds": 3, "placement": "endpoint"}, "fit_rounds"),
        ({"fit_rounds": 3, "max_distance": 0.1}, "fit_rounds"),
        ({"fit_rounds": 1, "max_normal_deviation": 30}, "fit_rounds"),
        ({"flip_tolerance": 0.7, "max_distance": 1.0}, "flip_tolerance"),
        ({"flip_tolerance": 0.2, "max_normal_deviation": 30}, "flip_tolerance"),
    ],
)
def test_options_that_cannot_take_effect_are_refused(ico, options, name):
    with pytest.raises(ValueError, match=f"^{name} cannot be given with"):
        bt.decimate(ico, ratio=0.5, **options)


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"openmesh": True},
        {"placement": "endpoint"},
        {"max_distance": 1.0},
        {"max_normal_deviation": 30},
        {"fit_rounds": 0, "placement": "endpoint"},
        {"fit_rounds": 0, "max_distance": 1.0},
        {"flip_tolerance": 0.0, "max_normal_deviation": 30},
        {"flip_tolerance": 0.5, "placement": "endpoint"},
    ],
)
def test_defaults_and_zeros_never_trigger_the_refusal(ico, options):
    _, report = bt.decimate(ico, ratio=0.5, **options)
    fitted = report["fit_rounds"] > 0
    assert fitted == (options == {}), report["fit_rounds"]
    # No fit: None, not a 0.0 that reads as a perfect fit.
    assert (report["fit_rms_before"] is None) == (not fitted)
    assert (report["fit_rms_after"] is None) == (not fitted)


def test_decimate_can_skip_the_distance(ico):
    _, report = bt.decimate(ico, ratio=0.5, distance=False)
    assert report["hausdorff"] is None and report["hausdorff_to_input"] is None
    assert bt.decimate(ico, ratio=0.5)[1]["hausdorff"] > 0


def test_the_edit_reports_have_the_quality_before_and_after(ico):
    holed = bt.Mesh(ico.vertices, ico.faces[1:])
    for call, mesh in [
        (lambda m: bt.remesh(m, edge_length_relative=1.5), ico),
        (lambda m: bt.decimate(m, ratio=0.5), ico),
        (lambda m: bt.fill_holes(m, fill_all=True), holed),
    ]:
        out, report = call(mesh)
        assert report["quality_before"] == bt.quality(mesh)
        assert report["quality_after"] == bt.quality(out)


def test_fill_holes_leaves_a_lone_triangle_open():
    tri = bt.Mesh(np.eye(3), np.array([[0, 1, 2]]))
    out, report = bt.fill_holes(tri, fill_all=True)
    assert report["faces_added"] == 0 and len(out.faces) == 1
    assert report["skipped"][0]["reason"] == "no_manifold_triangulation"


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda m: bt.decimate(m, vertices=-1), "^vertices must be at least 1, got -1$"),
        (lambda m: bt.decimate(m, vertices=0), "^vertices must be at least 1, got 0$"),
        (lambda m: bt.fill_holes(m, max_loop_edges=-1), "^max_loop_edges must be at least 3, got -1$"),
        (lambda m: bt.fill_holes(m, max_loop_edges=2), "^max_loop_edges must be at least 3, got 2$"),
        (
            lambda m: bt.decimate(m, ratio=0.5, max_normal_deviation=200),
            "^max_normal_deviation must be between 0 and 180 degrees, got 200",
        ),
        (lambda m: bt.decimate(m, ratio=0.5, fit_rounds=101), "at most 100 rounds, got 101"),
        (lambda m: bt.remesh(m, iterations=1001), "^invalid option: remeshing takes at most 1000 iterations .*, got 1001$"),
        (lambda m: bt.compare(m, m, samples=0), "^samples must be between 1 and 10000000"),
        (lambda m: bt.compare(m, m, samples=-1), "^samples must be between 1 and 10000000"),
        (lambda m: bt.compare(m, m, samples=10**7 + 1), "^samples must be between 1 and 10000000"),
    ],
)
def test_messages_state_the_real_limits_and_units(ico, call, message):
    with pytest.raises(ValueError, match=message):
        call(ico)


@pytest.mark.parametrize("adaptive", [(1, 2), (1, 2, 3, 4), "yes", 3])
def test_a_bad_adaptive_value_says_what_adaptive_accepts(ico, adaptive):
    with pytest.raises(TypeError, match=r"adaptive must be True, False, None or a tuple \(min_edge, max_edge, error\)"):
        bt.remesh(ico, adaptive=adaptive)


def test_read_shows_its_real_default_weld_tolerance():
    parameter = inspect.signature(bt.read).parameters["weld_tolerance"]
    assert parameter.default == 1e-6


def test_write_refuses_a_write_protected_file_without_force(ico, tmp_path):
    target = tmp_path / "ro.ply"
    bt.write(target, bt.generate("sphere", level=1))
    before = target.read_bytes()
    os.chmod(target, stat.S_IRUSR | stat.S_IRGRP | stat.S_IROTH)
    try:
        with pytest.raises(PermissionError, match=r"write-protected \(pass force=True to replace it\)"):
            bt.write(target, ico)
        assert target.read_bytes() == before
        bt.write(target, ico, force=True)
        assert len(bt.read(target).vertices) == len(ico.vertices)
    finally:
        os.chmod(target, stat.S_IRUSR | stat.S_IWUSR)


def test_write_without_sync_writes_the_same_bytes_and_no_temporary_file(ico, tmp_path):
    parameter = inspect.signature(bt.write).parameters["sync"]
    assert parameter.default is True and parameter.kind is inspect.Parameter.KEYWORD_ONLY
    synced, unsynced = tmp_path / "synced.ply", tmp_path / "unsynced.ply"
    bt.write(synced, ico)
    bt.write(unsynced, ico, sync=False)
    assert unsynced.read_bytes() == synced.read_bytes()
    # Replacing a file without the flushes, too (the rename stays atomic).
    bt.write(unsynced, bt.generate("sphere", level=1), sync=False)
    assert len(bt.read(unsynced).vertices) == 42
    assert sorted(p.name for p in tmp_path.iterdir()) == ["synced.ply", "unsynced.ply"]
