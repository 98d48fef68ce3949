"""`smooth`: every option family, the report, the observer and the errors."""

from __future__ import annotations

import pathlib
import threading

import numpy as np
import pytest

import beltrami as bt

REPORT_KEYS = {
    "input", "output", "vertices", "faces", "parameters", "iterations", "stop",
    "max_stuck_vertices", "scattered_sweeps", "seconds", "steps",
}
PARAMETER_KEYS = {
    "weights", "lambda", "iterations", "boundary", "update", "cotangent_negative", "summation",
    "normalize", "vertex_area", "pinned", "method", "mu", "hc", "preserve_volume",
    "time", "cutoff", "until_change", "lambda_used", "iterations_planned",
}


def boundary_vertices(mesh: bt.Mesh) -> np.ndarray:
    """Vertices on an edge used by one face only."""
    faces = mesh.faces
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return np.unique(unique[counts == 1])


def moved(a: bt.Mesh, b: bt.Mesh) -> np.ndarray:
    return np.linalg.norm(a.vertices - b.vertices, axis=1)


def test_defaults_and_report(sphere):
    out, report = bt.smooth(sphere)
    assert isinstance(out, bt.Mesh)
    np.testing.assert_array_equal(out.faces, sphere.faces)
    assert set(report) == REPORT_KEYS
    assert set(report["parameters"]) == PARAMETER_KEYS
    p = report["parameters"]
    assert (p["weights"], p["lambda"], p["iterations"], p["method"]) == ("cotangent", 0.8, 10, "explicit")
    assert (p["boundary"], p["update"], p["normalize"]) == ("fixed", "every", "sum")
    assert report["iterations"] == 10 and report["stop"] == "completed"
    assert [s["iteration"] for s in report["steps"]] == list(range(1, 11))
    assert report["steps"][0]["max_displacement"] > report["steps"][-1]["max_displacement"]
    assert moved(out, sphere).max() > 0
    # The input is untouched.
    assert moved(out, sphere).max() == pytest.approx(moved(out, sphere).max())


def test_smoothing_removes_noise(sphere):
    clean = bt.generate("sphere", level=3)
    out, _ = bt.smooth(sphere, method="taubin", iterations=20)
    radius = lambda m: np.linalg.norm(m.vertices, axis=1)  # noqa: E731
    assert np.std(radius(out)) < 0.5 * np.std(radius(sphere))
    assert np.std(radius(clean)) < 1e-12


def test_fixed_boundary_is_bit_identical(patch):
    out, _ = bt.smooth(patch, iterations=5)
    b = boundary_vertices(patch)
    assert len(b) > 0
    np.testing.assert_array_equal(out.vertices[b], patch.vertices[b])
    free, _ = bt.smooth(patch, iterations=5, boundary="free")
    assert moved(free, patch)[b].max() > 0
    curve, _ = bt.smooth(patch, iterations=5, boundary="curve")
    assert moved(curve, patch)[b].max() > 0


@pytest.mark.parametrize(
    "options",
    [
        {"method": "taubin"},
        {"method": "taubin", "lam": 0.5, "mu": -0.53},
        {"method": "hc"},
        {"method": "hc", "hc_alpha": 0.2, "hc_beta": 0.5},
        {"method": "implicit", "lam": 5.0},
        {"method": "implicit", "lam": 5.0, "solver": "cholesky", "update": "once"},
        {"update": "once"},
        {"weights": "uniform"},
        {"weights": "distance"},
        {"normalize": "area", "lam": 1e-4},
        {"normalize": "area", "vertex_area": "barycentric", "lam": 1e-4},
        {"cotangent_negative": "clamp"},
        {"cotangent_negative": "abs"},
        {"preserve_volume": True},
        {"time": 1e-3},
        {"cutoff": 0.3},
        {"method": "implicit", "time": 1e-2, "normalize": "area"},
        {"step_stats": False},
    ],
)
def test_every_option_family_runs_and_moves(sphere, options):
    out, report = bt.smooth(sphere, **options)
    assert report["stop"] == "completed"
    assert moved(out, sphere).max() > 0
    assert np.isfinite(out.vertices).all()
    p = report["parameters"]
    for key in ("method", "weights", "update", "normalize", "time", "cutoff"):
        if key in options and key not in ("time",):
            assert p[key] == options[key]
    if options.get("step_stats") is False:
        assert report["steps"] == []
    if options.get("method") == "implicit":
        assert report["implicit"]["solver"] == options.get("solver", "cg")
    if "time" in options or "cutoff" in options:
        assert p["time"] > 0 and p["iterations_planned"] >= 1


@pytest.mark.parametrize("weights", ["cotangent", "distance"])
def test_scatter_summation_is_the_row_summation_to_rounding(sphere, weights):
    rows, report = bt.smooth(sphere, iterations=20, weights=weights)
    scattered, s_report = bt.smooth(sphere, iterations=20, weights=weights, summation="scatter")
    assert report["parameters"]["summation"] == "rows"
    assert s_report["parameters"]["summation"] == "scatter"
    assert (report["scattered_sweeps"], s_report["scattered_sweeps"]) == (0, 20)
    scale = np.abs(sphere.vertices).max()
    assert np.abs(rows.vertices - scattered.vertices).max() <= 1e-13 * scale
    again, _ = bt.smooth(sphere, iterations=20, weights=weights, summation="scatter")
    np.testing.assert_array_equal(again.vertices, scattered.vertices)


def test_taubin_defaults_are_the_classic_pair(sphere):
    _, report = bt.smooth(sphere, method="taubin")
    p = report["parameters"]
    assert p["lambda"] == 0.6307
    assert 1 / p["lambda"] + 1 / p["mu"] == pytest.approx(0.1)
    _, report = bt.smooth(sphere, method="hc")
    assert report["parameters"]["hc"] == [0.1, 0.6]


def test_preserve_volume_keeps_the_volume(sphere):
    before = bt.info(sphere)["volume"]
    shrunk, _ = bt.smooth(sphere, iterations=30)
    kept, _ = bt.smooth(sphere, iterations=30, preserve_volume=True)
    assert bt.info(shrunk)["volume"] < 0.99 * before
    assert bt.info(kept)["volume"] == pytest.approx(before, rel=1e-9)


def test_pinned_vertices_do_not_move(sphere):
    out, report = bt.smooth(sphere, pin=np.array([0, 5, 17], dtype=np.int32))
    np.testing.assert_array_equal(out.vertices[[0, 5, 17]], sphere.vertices[[0, 5, 17]])
    assert report["parameters"]["pinned"] == 3


def test_until_change_converges(sphere):
    _, report = bt.smooth(sphere, iterations=10_000, until_change=1e-4, update="once")
    assert report["stop"] == "converged"
    assert report["iterations"] < 10_000
    assert report["steps"][-1]["max_displacement"] <= 1e-4


def test_frozen_weights_differ_from_the_flow(sphere):
    every, _ = bt.smooth(sphere)
    once, _ = bt.smooth(sphere, update="once")
    assert not np.array_equal(every.vertices, once.vertices)


def test_runs_are_deterministic(sphere):
    a, _ = bt.smooth(sphere, method="hc", iterations=7)
    b, _ = bt.smooth(sphere, method="hc", iterations=7)
    np.testing.assert_array_equal(a.vertices, b.vertices)


@pytest.mark.parametrize(
    ("options", "error", "message"),
    [
        ({"method": "laplace"}, ValueError, "method must be one of 'explicit', 'taubin', 'hc', 'implicit', got 'laplace'"),
        ({"boundary": "open"}, ValueError, "boundary must be one of"),
        ({"weights": "gaussian"}, ValueError, 'unknown weight scheme "gaussian"'),
        ({"mu": -0.5}, ValueError, "mu applies to method='taubin' only, not to method='explicit'"),
        ({"solver": "cg"}, ValueError, "solver applies to method='implicit' only"),
        ({"method": "hc", "time": 1.0}, ValueError, "time and cutoff apply to plain diffusion"),
        ({"time": 1.0, "iterations": 5}, ValueError, "exclude each other"),
        ({"method": "implicit", "preserve_volume": True}, ValueError, "preserve_volume does not apply"),
        ({"pin": [-1]}, ValueError, "pin: -1 is not a vertex index"),
        ({"pin": [True, False]}, TypeError, "pin: expected integers, got a boolean"),
        ({"pin": np.array([True, False])}, TypeError, "pin: expected vertex indices, got a boolean mask"),
        ({"pin": [2**200]}, ValueError, "is not a vertex index"),
        ({"vertex_area": "barycentric"}, ValueError, "vertex_area applies to normalize=.area. only"),
        ({"pin": [2**70]}, ValueError, "pin: 1180591620717411303424 is not a vertex index"),
        ({"pin": "12"}, TypeError, "pin: expected a sequence of vertex indices .integers., got str"),
        ({"pin": 3}, TypeError, "pin: expected a sequence of vertex indices .integers., got int"),
        ({"pin": [1.5]}, TypeError, "pin: expected integers, got float"),
        ({"lam": 1.5}, bt.SmoothError, "lambda"),
        ({"method": "taubin", "lam": 0.5, "mu": -0.4}, bt.SmoothError, "taubin|mu"),
        ({"pin": [100000]}, bt.SmoothError, "100000"),
        ({"normalize": "area", "lam": 10.0}, bt.SmoothError, "stab"),
        ({"time": 1e6, "max_iterations": 1000}, ValueError, "more than max_iterations=1000"),
        ({"summation": "edges"}, ValueError, "summation must be one of 'rows', 'scatter'"),
        ({"summation": "scatter", "update": "once"}, ValueError, "needs weights recomputed every iteration"),
        ({"summation": "scatter", "weights": "uniform"}, ValueError, "needs cotangent or inverse-distance weights"),
    ],
)
def test_bad_options_raise_the_right_exception(sphere, options, error, message):
    with pytest.raises(error, match=message):
        bt.smooth(sphere, **options)


def test_preserve_volume_needs_a_closed_mesh(patch):
    with pytest.raises(bt.SmoothError, match="closed"):
        bt.smooth(patch, preserve_volume=True)


def test_observer_sees_every_iteration(sphere):
    seen = []

    def observe(i, stats):
        seen.append((i, stats))

    _, report = bt.smooth(sphere, iterations=6, on_iteration=observe)
    assert [i for i, _ in seen] == [1, 2, 3, 4, 5, 6]
    assert [s for _, s in seen] == report["steps"]


def test_observer_stops_the_run(sphere):
    full, _ = bt.smooth(sphere, iterations=3)
    out, report = bt.smooth(sphere, iterations=50, on_iteration=lambda i, s: i < 3)
    assert report["stop"] == "observer"
    assert report["iterations"] == 3
    np.testing.assert_array_equal(out.vertices, full.vertices)
    # numpy's False (a comparison's result) stops as Python's does.
    out, report = bt.smooth(
        sphere, iterations=50, on_iteration=lambda i, s: np.float64(s["max_displacement"]) > 1e9
    )
    assert report["stop"] == "observer" and report["iterations"] == 1


def test_observer_returning_none_or_truthy_continues(sphere):
    _, report = bt.smooth(sphere, iterations=4, on_iteration=lambda i, s: None)
    assert report["iterations"] == 4
    _, report = bt.smooth(sphere, iterations=4, on_iteration=lambda i, s: 0)
    assert report["iterations"] == 4


def test_observer_exception_propagates(sphere):
    def fail(i, stats):
        if i == 2:
            raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        bt.smooth(sphere, iterations=10, on_iteration=fail)


def test_progress_bar(sphere):
    tqdm = pytest.importorskip("tqdm")
    del tqdm
    _, report = bt.smooth(sphere, iterations=5, progress=True)
    assert report["iterations"] == 5


def test_threads_with_callbacks_do_not_deadlock(sphere):
    results = {}
    counts = {}

    def run(k):
        counts[k] = 0

        def observe(i, stats):
            counts[k] += 1

        out, _ = bt.smooth(sphere, iterations=20, method="taubin", on_iteration=observe)
        results[k] = out.vertices

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
    assert not any(t.is_alive() for t in threads)
    assert counts == {k: 20 for k in range(4)}
    for k in range(1, 4):
        np.testing.assert_array_equal(results[k], results[0])


def test_the_gil_is_released_while_smoothing(sphere):
    big = bt.generate("sphere", level=5, noise=0.2)
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        # Long enough (tens of milliseconds) that the ticker runs many times however fast
        # the sweeps get.
        bt.smooth(big, iterations=300)
    finally:
        stop.set()
        t.join()
    assert len(ticks) > 5


def test_weight_schemes_lists_the_builtins():
    names = bt.weight_schemes()
    assert {"uniform", "distance", "cotangent"} <= set(names)


def _smoothed_vertex_count(path: str) -> int:
    smoothed, _ = bt.smooth(bt.read(path), iterations=3)
    return smoothed.n_vertices


@pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(),
    reason="no fork start method on this platform",
)
def test_a_forked_child_runs_after_the_parent_did():
    # A child made by fork (multiprocessing's default on Linux) inherits the parent's
    # thread pool without its threads; it used to wait for them forever.
    import multiprocessing

    path = str(pathlib.Path(__file__).resolve().parents[2] / "fixtures" / "icosphere_2.ply")
    expected = _smoothed_vertex_count(path)
    with multiprocessing.get_context("fork").Pool(2) as pool:
        got = pool.map_async(_smoothed_vertex_count, [path, path]).get(timeout=120)
    assert got == [expected, expected]
    # And the parent still runs.
    assert _smoothed_vertex_count(path) == expected


def test_smoothing_that_moves_nothing_warns():
    # A quad mesh has no cotangent weights: the default smoothing moves no vertex, and
    # says so (as the command's note does) instead of looking like a finished run.
    quads = bt.read(str(pathlib.Path(__file__).resolve().parents[2] / "fixtures" / "cube_quads.obj"))
    with pytest.warns(UserWarning, match="polygon faces, on which cotangent weights are 0"):
        smoothed, report = bt.smooth(quads)
    assert report["max_stuck_vertices"] == 8
    np.testing.assert_array_equal(smoothed.vertices, quads.vertices)
    pytest.importorskip("scipy")
    with pytest.warns(UserWarning, match="8 of the 8 rows are zero"):
        assert bt.laplacian(quads).nnz == 0
    # Uniform weights move it, without a warning.
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        moved, report = bt.smooth(quads, weights="uniform", iterations=1)
    assert report["max_stuck_vertices"] == 0
    assert not np.array_equal(moved.vertices, quads.vertices)


@pytest.mark.parametrize("method", ["explicit", "implicit", "taubin", "hc"])
def test_area_normalisation_without_lam_scales_the_step_to_the_mesh(sphere, method):
    # 0.8 length² is beyond the unit sphere's stability limit (and would collapse it
    # implicitly): without `lam` the step is a share of that limit, as in the CLI.
    with pytest.raises(bt.SmoothError, match="stab"):
        bt.smooth(sphere, normalize="area", lam=0.8)
    out, report = bt.smooth(sphere, normalize="area", method=method)
    assert report["stop"] == "completed" and np.isfinite(out.vertices).all()
    p = report["parameters"]
    fraction = 0.6307 if method == "taubin" else 0.8
    assert p["lambda"] == fraction
    used = p["lambda_used"]
    # Beyond the limit (used / fraction) a step given directly is refused; just below
    # it runs.
    limit = used / fraction
    with pytest.raises(bt.SmoothError, match="stab"):
        bt.smooth(sphere, normalize="area", lam=limit * 1.001, iterations=1)
    bt.smooth(sphere, normalize="area", lam=limit * 0.999, iterations=1)
    if method == "taubin":
        assert p["mu"] == pytest.approx(-0.6732 * limit, rel=1e-4)
        # A mu given alone is checked with the default step against the limit.
        with pytest.raises(bt.SmoothError, match="must exceed -1"):
            bt.smooth(sphere, normalize="area", method="taubin", mu=-0.53)
    # The same step from the command line's rule: the same positions as given directly.
    given, _ = bt.smooth(sphere, normalize="area", method=method, lam=used, mu=p["mu"])
    np.testing.assert_array_equal(given.vertices, out.vertices)
