"""The mesh algorithms: quality figures, subdivision and Delaunay flips, against closed
forms and the command line."""

from __future__ import annotations

import os

import json
import subprocess

import numpy as np
import pytest

import beltrami as bt


def grid(nx: int, ny: int) -> bt.Mesh:
    """Unit squares over [0, nx] x [0, ny], each cut along its (i, j)-(i+1, j+1) diagonal."""
    xs, ys = np.meshgrid(np.arange(nx + 1.0), np.arange(ny + 1.0))
    vertices = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    faces = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            faces += [[a, b, c], [a, c, d]]
    return bt.Mesh(vertices, np.array(faces))


def test_a_grid_has_right_isosceles_triangles():
    q = bt.quality(grid(4, 4))
    assert q["min_angle_degrees"] == pytest.approx(45.0, abs=1e-12)
    assert q["max_angle_degrees"] == pytest.approx(90.0, abs=1e-12)
    assert q["max_aspect_ratio"] == pytest.approx(np.sqrt(3.0), abs=1e-12)
    assert q["negative_cotangent_edges"] == 0
    assert q["valence_histogram"][6] == 9
    assert q["flipped_faces"] is None
    assert sum(q["aspect_ratio_histogram"]) == 32


def test_flipped_faces_against_a_reference():
    g = grid(3, 3)
    moved = g.vertices.copy()
    moved[5, 0] += 3.0  # drag an interior vertex across its neighbours
    q = bt.quality(bt.Mesh(moved, g.faces), reference=g)
    assert q["flipped_faces"] > 0
    with pytest.raises(bt.MeshError, match="same faces"):
        bt.quality(g, reference=grid(2, 2))


def test_quality_refuses_polygons():
    quad = bt.Mesh(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]]), np.array([[0, 1, 2, 3]]))
    with pytest.raises(bt.MeshError, match="triangle mesh"):
        bt.quality(quad)


def test_loop_subdivision_counts_and_kept_vertices(sphere):
    fine = bt.subdivide(sphere, "loop", steps=2)
    assert len(fine.faces) == 16 * len(sphere.faces)
    assert len(fine.vertices) == len(sphere.vertices) + len(sphere.faces) * 3 // 2 + (
        4 * len(sphere.faces) * 3 // 2
    )
    sqrt3 = bt.subdivide(sphere, "sqrt3", steps=2)
    assert len(sqrt3.faces) == 9 * len(sphere.faces)
    with pytest.raises(ValueError, match="unknown scheme"):
        bt.subdivide(sphere, "butterfly")
    # No steps: an unchanged copy, as documented.
    same = bt.subdivide(sphere, "loop", steps=0)
    assert np.array_equal(same.vertices, sphere.vertices)
    assert np.array_equal(same.faces, sphere.faces)


@pytest.mark.skipif(not os.path.exists("/proc/meminfo"), reason="the memory check reads /proc/meminfo")
def test_a_subdivision_too_large_for_the_memory_is_refused_before_it_allocates():
    # 13 Loop steps of the icosahedron: 1.3 billion faces, about 340 GB. Raised at once
    # (no allocation, no killed interpreter), naming the most steps that fit.
    import time

    ico = bt.generate("sphere", level=0)
    start = time.perf_counter()
    with pytest.raises(MemoryError, match=r"steps=13 of loop subdivision would make 1342177280 faces.*at most steps=\d+ fits"):
        bt.subdivide(ico, "loop", steps=13)
    assert time.perf_counter() - start < 1.0
    # Past what a mesh can hold at all: MeshError, as before.
    with pytest.raises(bt.MeshError, match="a mesh holds at most"):
        bt.subdivide(ico, "loop", steps=20)


def test_delaunay_removes_negative_weights_of_a_plane():
    g = grid(8, 8)
    rng = np.random.default_rng(5)
    v = g.vertices.copy()
    v[:, :2] += rng.uniform(-0.35, 0.35, (len(v), 2))
    jittered = bt.Mesh(v, g.faces)
    before = bt.quality(jittered)["negative_cotangent_edges"]
    flipped, report = bt.delaunay(jittered)
    assert before > 0 and report["negative_before"] == before
    assert report["negative_after"] == 0
    assert bt.quality(flipped)["negative_cotangent_edges"] == 0
    np.testing.assert_array_equal(flipped.vertices, v)
    assert report["max_deviation"] < 1e-12  # a plane stays a plane
    with pytest.raises(ValueError, match="between 0 and 180"):
        bt.delaunay(jittered, max_dihedral=200.0)


def test_remove_flat_triangles_flips_a_cap():
    # A square whose diagonal carries a vertex at its midpoint, closed by a cap.
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]], dtype=float)
    capped = bt.Mesh(v, np.array([[0, 1, 4], [1, 2, 4], [0, 2, 3], [0, 4, 2]]))
    assert bt.info(capped)["degenerate_faces"] == 1
    clean, report = bt.remove_flat_triangles(capped)
    assert (report["before"], report["after"], report["flips"], report["max_move"]) == (1, 0, 1, 0.0)
    assert report["alone"] == report["deleted"] == 0 and report["max_height"] < 1e-15
    assert bt.info(clean)["degenerate_faces"] == 0
    np.testing.assert_array_equal(clean.vertices, v[report["vertex_origin"]])
    assert bt.info(clean)["area"] == pytest.approx(1.0, abs=1e-15)
    # A sound mesh comes back as it was.
    same, report = bt.remove_flat_triangles(clean)
    np.testing.assert_array_equal(same.faces, clean.faces)
    assert report["before"] == 0
    with pytest.raises(ValueError, match="between 0 and 0.1"):
        bt.remove_flat_triangles(capped, max_height_ratio=0.5)
    with pytest.raises(ValueError, match=">= 0"):
        bt.remove_flat_triangles(capped, max_move=-1.0)
    with pytest.raises(bt.MeshError, match="needs a triangle mesh"):
        bt.remove_flat_triangles(bt.Mesh(v[:4], [[0, 1, 2, 3]]))
    # A mesh of one flat triangle would be left without faces: refused, as the command does.
    line = bt.Mesh(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], dtype=float), [[0, 1, 2]])
    with pytest.raises(bt.MeshError, match="left no face"):
        bt.remove_flat_triangles(line)


def run(cli, *args):
    done = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_quality_and_algorithms_match_the_cli(cli, tmp_path):
    src = tmp_path / "noisy.ply"
    run(cli, "generate", "sphere", src, "--level", "3", "--noise", "0.3", "--seed", "4")
    mesh = bt.read(src)
    expected = json.loads(run(cli, "info", src, "--json", "--quality"))["quality"]
    assert bt.quality(mesh) == expected

    out = tmp_path / "fine.ply"
    run(cli, "subdivide", src, out, "--scheme", "sqrt3", "--steps", "2")
    fine = bt.subdivide(mesh, "sqrt3", 2)
    from_cli = bt.read(out)
    np.testing.assert_array_equal(fine.vertices, from_cli.vertices)
    np.testing.assert_array_equal(fine.faces, from_cli.faces)

    out = tmp_path / "flipped.ply"
    summary = json.loads(run(cli, "delaunay", src, out, "--json", "--max-dihedral", "5"))
    flipped, report = bt.delaunay(mesh, max_dihedral=5.0)
    np.testing.assert_array_equal(flipped.faces, bt.read(out).faces)
    for key in ("flips", "negative_before", "negative_after", "kept_by_dihedral"):
        assert report[key] == summary[key]
    # The same keys as the command's, but those about its run (files, notes, timing).
    assert set(report) == set(summary) - {"input", "output", "notes", "seconds"}
    assert report == {k: summary[k] for k in report}


def test_remesh_evens_out_the_edges(sphere):
    # An irregular planar patch: a grid with every vertex pushed about in its plane.
    g = grid(12, 12)
    rng = np.random.default_rng(3)
    v = g.vertices.copy()
    inner = (v[:, 0] > 0) & (v[:, 0] < 12) & (v[:, 1] > 0) & (v[:, 1] < 12)
    v[inner, :2] += rng.uniform(-0.35, 0.35, (inner.sum(), 2))
    even, report = bt.remesh(bt.Mesh(v, g.faces), edge_length_relative=1.0)
    assert report["edge_length_cv"] < 0.8 * report["edge_length_cv_before"]
    assert report["mean_edge_length"] == pytest.approx(report["target_edge_length"], rel=0.15)
    assert bt.info(even)["boundary_loops"] == 1
    # The report's count of degenerate triangles is the one `info` finds.
    assert report["degenerate_faces"] == bt.info(even)["degenerate_faces"]
    assert report["degenerate_faces_before"] == bt.info(bt.Mesh(v, g.faces))["degenerate_faces"]
    closed, _ = bt.remesh(sphere, edge_length_relative=1.5)
    assert bt.info(closed)["closed"] and bt.info(closed)["genus"] == 0
    with pytest.raises(ValueError, match="one of"):
        bt.remesh(sphere, edge_length=0.1, edge_length_relative=1.0)
    with pytest.raises(ValueError):
        bt.remesh(sphere, edge_length=-1.0)
    # A length as long as the sphere: a solid (a tetrahedron at least) or refused,
    # never a flat mesh. Which of the two a length gives depends on the last few
    # collapses, so only both outcomes are required over these cases.
    clean = bt.generate("sphere", level=3)
    outcomes = []
    for mesh in (sphere, clean):
        for length in (1.5, 2.0, 2.5, 5.0):
            try:
                coarse, _ = bt.remesh(mesh, edge_length=length)
            except bt.MeshError as e:
                assert "too long for this surface" in str(e)
                outcomes.append("refused")
                continue
            i = bt.info(coarse)
            assert i["closed"] and i["degenerate_faces"] == 0
            assert len(coarse.vertices) >= 4
            outcomes.append("solid")
    assert "solid" in outcomes and "refused" in outcomes, outcomes


def test_remesh_keeps_given_feature_edges():
    # A flat 8 x 8 grid, interior vertices pushed about in the plane (those on y = 4
    # along it only): only the given edges keep the line y = 4.
    n = 8
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1))
    v = np.column_stack([i.ravel(), j.ravel(), np.zeros(i.size)]).astype(float)
    k = np.arange(len(v))
    inner = (v[:, 0] > 0) & (v[:, 0] < n) & (v[:, 1] > 0) & (v[:, 1] < n)
    v[inner, 0] += 0.3 * ((k[inner] * 7 % 5) / 5.0 - 0.4)
    off_line = inner & (v[:, 1] != 4)
    v[off_line, 1] += 0.3 * ((k[off_line] * 3 % 7) / 7.0 - 0.4)
    vid = lambda a, b: b * (n + 1) + a  # noqa: E731
    faces = []
    for b_ in range(n):
        for a_ in range(n):
            faces += [[vid(a_, b_), vid(a_ + 1, b_), vid(a_ + 1, b_ + 1)],
                      [vid(a_, b_), vid(a_ + 1, b_ + 1), vid(a_, b_ + 1)]]
    grid = bt.Mesh(v, np.array(faces))
    line = np.array([[vid(a_, 4), vid(a_ + 1, 4)] for a_ in range(n)])

    def covered(m):
        x, f = m.vertices, m.faces
        e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
        e = np.unique(e, axis=0)
        on = (x[e[:, 0], 1] == 4.0) & (x[e[:, 1], 1] == 4.0)
        return np.linalg.norm(x[e[on, 0]] - x[e[on, 1]], axis=1).sum()

    out, report = bt.remesh(grid, 1.3, feature_edges=line)
    assert report["given_feature_edges"] == n and report["feature_edges"] == 0
    assert covered(out) == pytest.approx(8.0, abs=1e-9)
    free, report = bt.remesh(grid, 1.3)
    assert report["given_feature_edges"] == 0 and covered(free) < 7.0
    with pytest.raises(ValueError, match="feature edge 1 .* no edge joins them"):
        bt.remesh(grid, 1.3, feature_edges=[line[0], [0, 20]])
    with pytest.raises(ValueError, match=r"\(K, 2\) array"):
        bt.remesh(grid, 1.3, feature_edges=[0, 1, 2])
    with pytest.raises(ValueError, match="row 0: vertex index -1"):
        bt.remesh(grid, 1.3, feature_edges=[[-1, 0]])
    # No pairs at all: as without the argument.
    _, report = bt.remesh(grid, 1.3, feature_edges=[])
    assert report["given_feature_edges"] == 0


def test_remesh_adaptive_derives_what_is_not_given():
    sphere = bt.generate("sphere", level=3)
    # All three derived: a sphere has one curvature, so its density stays.
    even, report = bt.remesh(sphere, adaptive=True)
    mean = report["mean_edge_length_before"]
    assert report["adaptive"] is True
    assert report["min_edge"] == pytest.approx(mean / 4, rel=1e-12)
    assert report["max_edge"] == pytest.approx(4 * mean, rel=1e-12)
    assert len(even.vertices) == pytest.approx(len(sphere.vertices), rel=0.15)
    # A given value is kept; None entries are derived as with True.
    _, given = bt.remesh(sphere, adaptive=(None, None, 0.001))
    assert given["approx_error"] == 0.001
    assert given["min_edge"] == report["min_edge"]
    assert given["vertices"] > report["vertices"]
    _, plain = bt.remesh(sphere, edge_length_relative=1.0)
    assert plain["min_edge"] is None and plain["adaptive"] is False
    with pytest.raises(ValueError):
        bt.remesh(sphere, adaptive=(-1.0, None, None))


def test_remesh_projects_onto_the_smooth_surface_or_the_facets():
    # A smooth level-4 icosphere: by default the vertices land on the unit sphere the
    # triangles approximate; smooth_projection=False keeps them on the triangles, up to
    # a triangle's depth (1.1e-3) below the sphere.
    smooth = bt.generate("sphere", level=4)
    lifted, report = bt.remesh(smooth, edge_length_relative=1.5)
    faceted, flat_report = bt.remesh(smooth, edge_length_relative=1.5, smooth_projection=False)
    assert report["smooth_projection"] and not flat_report["smooth_projection"]
    off = lambda m: np.abs(np.linalg.norm(m.vertices, axis=1) - 1.0).max()
    assert off(lifted) < 1e-5 < 1e-4 < off(faceted) < 1.2e-3
    assert flat_report["hausdorff"] < 1e-12 < 1e-4 < report["hausdorff"] < 1.2e-3
    # Without projection there is nothing to lift.
    _, none = bt.remesh(smooth, edge_length_relative=1.5, projection=False)
    assert not none["smooth_projection"]


def test_decimate_reaches_the_target_and_keeps_the_topology(sphere):
    light, report = bt.decimate(sphere, ratio=0.25)
    assert report["target_reached"] and len(light.vertices) == report["target_vertices"]
    assert bt.info(light)["euler_characteristic"] == 2
    assert report["placement"] == "optimal" and report["quality_threshold"] == 0.4
    kept = {tuple(p) for p in sphere.vertices}
    # The default moves kept vertices to the quadric's minimum; endpoint placement (and
    # OpenMesh's mode) keeps input points.
    assert not all(tuple(p) in kept for p in light.vertices)
    for options in ({"placement": "endpoint"}, {"openmesh": True}):
        light, report = bt.decimate(sphere, ratio=0.25, **options)
        assert report["placement"] == "endpoint"
        assert all(tuple(p) in kept for p in light.vertices)
    assert report["quality_threshold"] == 0.0
    with pytest.raises(ValueError, match="placement"):
        bt.decimate(sphere, ratio=0.25, placement="middle")
    with pytest.raises(ValueError, match="quality_threshold"):
        bt.decimate(sphere, ratio=0.25, quality_threshold=2.0)
    with pytest.raises(ValueError, match="exactly one"):
        bt.decimate(sphere)


def test_decimate_flips_towards_valence_six_after_the_collapses(sphere):
    # A smooth sphere: its collapses leave quads flat enough to flip (on the noisy
    # fixture, whose quads fold by more than the tolerance, none is).
    smooth = bt.generate("sphere", level=4)
    # Without the final fit, which moves the vertices after the flips.
    flipped, report = bt.decimate(smooth, ratio=0.25, fit_rounds=0)
    plain, plain_report = bt.decimate(smooth, ratio=0.25, flip_tolerance=0.0, fit_rounds=0)
    assert report["flip_tolerance"] == 0.2 and plain_report["flips"] == 0
    assert report["flips"] > 0
    # The same vertices; only edges changed, towards valence 6.
    np.testing.assert_array_equal(flipped.vertices, plain.vertices)
    assert bt.quality(flipped)["regular_share"] > bt.quality(plain)["regular_share"]
    assert bt.decimate(sphere, ratio=0.25, openmesh=True)[1]["flips"] == 0
    with pytest.raises(ValueError, match="flip tolerance"):
        bt.decimate(sphere, ratio=0.25, flip_tolerance=-1.0)


def test_decimate_fits_the_surface_to_the_input():
    smooth = bt.generate("sphere", level=4)
    fitted, report = bt.decimate(smooth, ratio=0.25)
    plain, plain_report = bt.decimate(smooth, ratio=0.25, fit_rounds=0)
    assert report["fit_rounds"] == 2 and plain_report["fit_rounds"] == 0
    assert report["fit_rms_after"] < 0.8 * report["fit_rms_before"]
    # Only the vertices move, and the surface comes closer to the input's.
    np.testing.assert_array_equal(fitted.faces, plain.faces)
    assert bt.compare(fitted, smooth, samples=20000)["surface_rms"]["symmetric"] < 0.8 * (
        bt.compare(plain, smooth, samples=20000)["surface_rms"]["symmetric"]
    )
    assert bt.decimate(smooth, ratio=0.25, openmesh=True)[1]["fit_rounds"] == 0
    with pytest.raises(ValueError, match="fit_rounds"):
        bt.decimate(smooth, ratio=0.25, fit_rounds=-1)


def test_decimate_plane_weights_and_stabilizer(sphere):
    plain, report = bt.decimate(sphere, ratio=0.25)
    assert report["plane_weights"] == "area" and report["stabilizer"] == 0.0
    uniform, report = bt.decimate(sphere, ratio=0.25, plane_weights="uniform", stabilizer=0.001)
    assert report["plane_weights"] == "uniform" and report["stabilizer"] == 0.001
    assert report["target_reached"] and bt.info(uniform)["euler_characteristic"] == 2
    # Other quadrics, other positions (the same target count).
    assert len(uniform.vertices) == len(plain.vertices)
    assert not np.array_equal(uniform.vertices, plain.vertices)
    with pytest.raises(ValueError, match="plane_weights"):
        bt.decimate(sphere, ratio=0.25, plane_weights="volume")
    with pytest.raises(ValueError, match="stabilizer"):
        bt.decimate(sphere, ratio=0.25, stabilizer=-1.0)
    with pytest.raises(ValueError, match="openmesh"):
        bt.decimate(sphere, ratio=0.25, openmesh=True, stabilizer=0.001)


@pytest.mark.parametrize("power", [-500, 500])
def test_the_editing_calls_give_the_same_result_far_from_unit_size(sphere, power):
    """A mesh times 2**power gives the unit-size result times 2**power, bit for bit."""
    scale = 2.0**power
    # References at 0.75 of the unit size, so that the far runs, brought to [1, 2), are
    # computed at another size than theirs.
    sphere = bt.Mesh(sphere.vertices * 0.75, sphere.faces)
    far = bt.Mesh(sphere.vertices * scale, sphere.faces)
    holed = bt.generate("sphere", level=3, holes=2)
    holed = bt.Mesh(holed.vertices * 0.75, holed.faces)
    holed_far = bt.Mesh(holed.vertices * scale, holed.faces)
    for call, unit_mesh, far_mesh, length in [
        (lambda m: bt.decimate(m, ratio=0.3), sphere, far, "hausdorff"),
        (lambda m: bt.remesh(m, iterations=2), sphere, far, "mean_edge_length"),
        (lambda m: bt.fill_holes(m, fill_all=True), holed, holed_far, None),
    ]:
        (a, ra), (b, rb) = call(unit_mesh), call(far_mesh)
        np.testing.assert_array_equal(b.faces, a.faces)
        np.testing.assert_array_equal(b.vertices, a.vertices * scale)
        if length:
            assert rb[length] == ra[length] * scale
    quality = bt.quality(far)
    assert quality["min_angle_degrees"] == bt.quality(sphere)["min_angle_degrees"]


def test_fill_holes_closes_a_cut_sphere():
    whole = bt.generate("sphere", level=3)
    centre = whole.vertices[0]
    cut = np.linalg.norm(whole.vertices[whole.faces].mean(axis=1) - centre, axis=1) > 0.3
    holed = bt.Mesh(whole.vertices, whole.faces[cut])
    closed, report = bt.fill_holes(holed, fill_all=True)
    assert report["boundary_loops_left"] == 0 and len(report["filled"]) == 1
    assert bt.info(closed)["closed"]
    np.testing.assert_array_equal(closed.vertices[: len(whole.vertices)], whole.vertices)
    # Faired on a sphere: the new vertices stay near it.
    new = closed.vertices[len(whole.vertices):]
    assert np.abs(np.linalg.norm(new, axis=1) - 1.0).max() < 0.05
    _, kept_open = bt.fill_holes(holed)  # the only loop is the outer boundary
    assert kept_open["skipped"][0]["reason"] == "outer_boundary"


def test_the_editing_commands_match_the_cli(cli, tmp_path):
    src = tmp_path / "noisy.ply"
    run(cli, "generate", "sphere", src, "--level", "3", "--noise", "0.1", "--seed", "2")
    mesh = bt.read(src)
    for command, extra, call in [
        ("remesh", ["--edge-length-relative", "1.2"], lambda: bt.remesh(mesh, edge_length_relative=1.2)),
        ("decimate", ["--ratio", "0.3"], lambda: bt.decimate(mesh, ratio=0.3)),
    ]:
        out = tmp_path / f"{command}.ply"
        summary = json.loads(run(cli, command, src, out, *extra, "--json"))
        got, report = call()
        from_cli = bt.read(out)
        np.testing.assert_array_equal(got.vertices, from_cli.vertices)
        np.testing.assert_array_equal(got.faces, from_cli.faces)
        for key, value in report.items():
            assert summary[key] == value, (command, key)


def test_remesh_and_decimate_progress_bars_change_nothing(sphere, capsys):
    # With or without tqdm installed, progress=True gives the same result.
    plain, plain_report = bt.remesh(sphere, edge_length_relative=1.5, iterations=3)
    shown, shown_report = bt.remesh(sphere, edge_length_relative=1.5, iterations=3, progress=True)
    np.testing.assert_array_equal(plain.vertices, shown.vertices)
    np.testing.assert_array_equal(plain.faces, shown.faces)
    assert plain_report == shown_report
    light, light_report = bt.decimate(sphere, ratio=0.25)
    shown, shown_report = bt.decimate(sphere, ratio=0.25, progress=True)
    np.testing.assert_array_equal(light.vertices, shown.vertices)
    assert light_report == shown_report
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return
    err = capsys.readouterr().err
    assert "remesh" in err and "3/3" in err
    assert "decimate" in err


def test_fill_holes_progress_bar_changes_nothing(capsys):
    # Two holes cut into a sphere: progress=True gives the same result, and the bar
    # (when tqdm is installed) counts the two boundary loops.
    s = bt.generate("sphere", level=3)
    keep = np.ones(len(s.faces), dtype=bool)
    keep[[0, 600]] = False
    holed = bt.Mesh(s.vertices, s.faces[keep])
    plain, plain_report = bt.fill_holes(holed, fill_all=True)
    shown, shown_report = bt.fill_holes(holed, fill_all=True, progress=True)
    np.testing.assert_array_equal(plain.vertices, shown.vertices)
    np.testing.assert_array_equal(plain.faces, shown.faces)
    assert plain_report == shown_report
    assert len(shown_report["filled"]) == 2 and bt.info(shown)["closed"]
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return
    err = capsys.readouterr().err
    assert "fill_holes" in err and "2/2" in err


@pytest.mark.parametrize("name", ["smooth", "remesh", "decimate"])
def test_ctrl_c_stops_a_long_run(name):
    # Ctrl-C 0.2 s into a run that takes 5 to 25 s: the run stops soon after with
    # KeyboardInterrupt. Python runs signal handlers on the main thread
    # only, and the run's work is on a worker, so the calling thread looks for them.
    import os
    import signal
    import threading
    import time

    calls = {
        "smooth": (lambda m: bt.smooth(m, iterations=20000), ("sphere", 6)),
        "remesh": (lambda m: bt.remesh(m, iterations=1000), ("sphere", 5)),
        "decimate": (lambda m: bt.decimate(m, ratio=0.01), ("sphere", 8)),
    }
    call, (surface, level) = calls[name]
    mesh = bt.generate(surface, level=level)
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call(mesh)
    finally:
        # A run that ended before the signal must not leave it to hit the test session.
        timer.cancel()
    elapsed = time.perf_counter() - start
    # Within the set-up before the run's first step plus a tenth of a second: far below
    # the whole run (5 to 25 s).
    assert 0.2 <= elapsed < 1.5, elapsed


def test_a_run_started_inside_another_runs_callback_ends():
    # An observer that smooths another mesh, with a pool of one thread: the inner run
    # must run where it is called (on the pool's only worker), not wait for a job
    # queued behind the outer one.
    import subprocess
    import sys

    code = (
        "import beltrami as bt\n"
        "inner = bt.generate('sphere', level=1)\n"
        "seen = []\n"
        "def observe(i, stats):\n"
        "    seen.append(bt.smooth(inner, iterations=2)[1]['iterations'])\n"
        "bt.smooth(bt.generate('sphere', level=2), iterations=3, on_iteration=observe)\n"
        "assert seen == [2, 2, 2], seen\n"
        "print('ok')\n"
    )
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr


def test_a_signal_handler_of_the_users_stops_a_run():
    # A handler that raises (here a timeout by SIGALRM) stops the run with its exception,
    # and the package works as before afterwards.
    import signal
    import time

    class TookTooLong(Exception):
        pass

    def handler(signum, frame):
        raise TookTooLong

    mesh = bt.generate("sphere", level=6)
    previous = signal.signal(signal.SIGALRM, handler)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.2)
        start = time.perf_counter()
        with pytest.raises(TookTooLong):
            bt.smooth(mesh, iterations=20000)
        assert time.perf_counter() - start < 0.7
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    smoothed, report = bt.smooth(mesh, iterations=3)
    assert report["iterations"] == 3


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda s, d: bt.subdivide(s, "loop", -1), "steps"),
        (lambda s, d: bt.delaunay(s, max_flips=-1), "max_flips"),
        (lambda s, d: bt.remesh(s, iterations=-1), "iterations"),
        (lambda s, d: bt.smooth(s, iterations=-1), "iterations"),
        (lambda s, d: bt.smooth(s, max_iterations=-1), "max_iterations"),
        (lambda s, d: bt.generate("sphere", seed=-1), "seed"),
        (lambda s, d: bt.generate("sphere", level=-2), "level"),
        (lambda s, d: bt.generate("sphere", shuffle=-1), "shuffle"),
        (lambda s, d: bt.study(d / "study", seeds=-1), "seeds"),
        (lambda s, d: bt.study(d / "study", iterations=[10, -1]), "iterations"),
    ],
)
def test_a_negative_count_is_a_value_error_naming_the_argument(sphere, tmp_path, call, name):
    with pytest.raises(ValueError, match=f"^{name} must be 0 or more, got -"):
        call(sphere, tmp_path)
    assert not (tmp_path / "study").exists()


def test_a_count_too_large_for_its_type_is_a_value_error():
    with pytest.raises(ValueError, match="^level is too large: 1099511627776$"):
        bt.generate("sphere", level=2**40)


def test_generate_refuses_what_would_make_no_mesh_or_no_numbers():
    # Noise that overflows a position, a hole larger than the sphere, a size the level
    # overrides: each a ValueError, not a mesh of inf or of nothing.
    with pytest.raises(ValueError, match="leave every position finite"):
        bt.generate("sphere", level=2, noise=1e308, absolute_noise=True)
    with pytest.raises(ValueError, match="remove every face"):
        bt.generate("sphere", level=3, holes=1, hole_radius=1e9)
    with pytest.raises(ValueError, match="exclude each other"):
        bt.generate("sphere", level=3, size="small")
    with pytest.raises(ValueError, match="size must be 'paper' or 'small'"):
        bt.generate("sphere", level=3, size="huge")
