"""Weight schemes written in Python."""

from __future__ import annotations

import numpy as np
import pytest

import beltrami as bt


def python_cotangent(h):
    return 0.5 * (h["opposite_cotangent"] + h["opposite_cotangent"][h["twin"]])


bt.register_weight("py-cotangent", python_cotangent, description="cotangent, in numpy")
bt.register_weight("py-uniform", lambda h: np.ones(len(h["from_vertex"])), depends_on_positions=False)


def test_the_cotangent_scheme_in_numpy_equals_the_builtin(sphere, patch):
    for mesh in (sphere, patch):
        rust, _ = bt.smooth(mesh, weights="cotangent", iterations=5)
        python, report = bt.smooth(mesh, weights="py-cotangent", iterations=5)
        np.testing.assert_allclose(python.vertices, rust.vertices, rtol=0, atol=1e-12)
        assert report["parameters"]["weights"] == "py-cotangent"


def test_uniform_in_numpy_equals_the_builtin(sphere):
    rust, _ = bt.smooth(sphere, weights="uniform", method="taubin")
    python, _ = bt.smooth(sphere, weights="py-uniform", method="taubin")
    np.testing.assert_array_equal(python.vertices, rust.vertices)


def test_the_arrays_describe_the_halfedges(sphere):
    seen = {}

    def spy(h):
        seen.update(h)
        return np.ones(len(h["from_vertex"]))

    bt.register_weight("spy", spy)
    bt.smooth(sphere, weights="spy", iterations=1)
    n = 2 * sphere.n_edges
    assert seen["from_vertex"].shape == (n,) and seen["edge_vector"].shape == (n, 3)
    v = seen["positions"]
    np.testing.assert_allclose(
        seen["edge_vector"], v[seen["to_vertex"]] - v[seen["from_vertex"]], atol=1e-15
    )
    np.testing.assert_allclose(seen["edge_length"], np.linalg.norm(seen["edge_vector"], axis=1))
    np.testing.assert_array_equal(seen["from_vertex"][seen["twin"]], seen["to_vertex"])
    assert (seen["face"] >= 0).all()  # closed: no boundary halfedges
    np.testing.assert_allclose(np.linalg.norm(seen["face_normal"], axis=1), 1.0)
    assert "spy" in bt.weight_schemes()


def test_a_failing_scheme_raises_its_exception(sphere):
    def broken(h):
        raise ZeroDivisionError("no weights today")

    bt.register_weight("broken", broken)
    with pytest.raises(ZeroDivisionError, match="no weights today"):
        bt.smooth(sphere, weights="broken")


def test_the_operator_raises_the_schemes_exception_and_keeps_none_for_later(sphere):
    # A scheme that fails once: bt.laplacian raises its exception (not a complaint about
    # the NaN weights it left), and the next call, where it succeeds, raises nothing.
    calls = [0]

    def flaky(h):
        calls[0] += 1
        if calls[0] == 1:
            raise RuntimeError("transient")
        return np.ones(len(h["twin"]))

    bt.register_weight("flaky", flaky)
    with pytest.raises(RuntimeError, match="transient"):
        bt.laplacian(sphere, weights="flaky")
    smoothed, report = bt.smooth(sphere, weights="flaky", iterations=1)
    assert report["iterations"] == 1


def test_a_wrong_length_is_a_value_error(sphere):
    bt.register_weight("short", lambda h: np.ones(3))
    with pytest.raises(ValueError, match="returned 3 weights for 3840 halfedges"):
        bt.smooth(sphere, weights="short")


def test_names_are_checked():
    with pytest.raises(ValueError, match="already registered"):
        bt.register_weight("cotangent", python_cotangent)
    with pytest.raises(ValueError, match="invalid weight scheme name"):
        bt.register_weight("Bad Name", python_cotangent)


def test_a_scheme_of_ones_own_is_replaced_when_asked(sphere):
    # A notebook cell run again: the same name, a new function.
    bt.register_weight("cell", lambda h: np.ones(len(h["twin"])))
    with pytest.raises(ValueError, match="already registered"):
        bt.register_weight("cell", lambda h: 2 * np.ones(len(h["twin"])))
    seen = []

    def second(h):
        seen.append(True)
        return 2 * np.ones(len(h["twin"]))

    bt.register_weight("cell", second, replace=True)
    bt.smooth(sphere, weights="cell", iterations=1)
    assert seen
    assert bt.weight_schemes().count("cell") == 1
    # A built-in stays.
    with pytest.raises(ValueError, match="built-in"):
        bt.register_weight("cotangent", second, replace=True)


def test_a_function_that_is_not_callable_is_refused_at_once():
    with pytest.raises(TypeError, match="must be callable"):
        bt.register_weight("not-callable", np.ones(3))
    assert "not-callable" not in bt.weight_schemes()


def test_a_run_raises_its_own_schemes_exception_when_replaced_meanwhile(sphere):
    # The scheme's function waits inside the run until the main thread has replaced the
    # scheme, then raises: the run must raise that exception, not report the NaN weights
    # it left (the replacement's slot is empty).
    import threading

    inside, replaced = threading.Event(), threading.Event()

    def failing(h):
        inside.set()
        replaced.wait(10)
        raise ArithmeticError("the first version failed")

    bt.register_weight("race_scheme", failing, replace=True)
    seen = []

    def run():
        try:
            bt.smooth(sphere, weights="race_scheme", iterations=1)
        except Exception as e:  # noqa: BLE001
            seen.append(e)

    worker = threading.Thread(target=run)
    worker.start()
    assert inside.wait(10)
    bt.register_weight("race_scheme", lambda h: np.ones(len(h["from_vertex"])), replace=True)
    replaced.set()
    worker.join(10)
    assert len(seen) == 1 and isinstance(seen[0], ArithmeticError), seen
    # The replacement works, and nothing is left over for it to raise.
    bt.smooth(sphere, weights="race_scheme", iterations=1)


def test_a_name_that_is_no_string_is_a_type_error():
    with pytest.raises(TypeError, match="the scheme's name must be a str, got int"):
        bt.register_weight(5, lambda h: np.ones(len(h["from"])))
