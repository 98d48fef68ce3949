"""Least-squares fits of spheres, circles and cylinders."""

from __future__ import annotations

import numpy as np
import pytest

import beltrami as bt


def test_sphere_fit_of_the_unit_sphere():
    fit = bt.fit_sphere(bt.generate("sphere", level=3))
    assert fit["shape"] == "sphere" and fit["converged"]
    assert fit["radius"] == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(fit["center"], [0, 0, 0], atol=1e-12)
    assert fit["points"] == 642
    assert "axis" not in fit


def test_weighted_sphere_fit_needs_a_mesh():
    sphere = bt.generate("sphere", level=2, noise=0.1)
    assert bt.fit_sphere(sphere, weighted=True)["weighted"]
    with pytest.raises(ValueError, match="weighted needs a Mesh"):
        bt.fit_sphere(sphere.vertices, weighted=True)


def test_circle_and_cylinder_of_points():
    t = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    circle = np.c_[3 + 2 * np.cos(t), 2 * np.sin(t), np.full_like(t, 5.0)]
    fit = bt.fit_circle(circle)
    assert fit["radius"] == pytest.approx(2.0, abs=1e-9)
    np.testing.assert_allclose(fit["center"], [3, 0, 5], atol=1e-9)
    np.testing.assert_allclose(np.abs(fit["axis"]), [0, 0, 1], atol=1e-9)
    assert fit["plane_rms"] == pytest.approx(0.0, abs=1e-9)
    z = np.repeat([0.0, 1.0, 2.0], 50)
    cylinder = np.c_[np.tile(circle[:, :2], (3, 1)), z]
    fit = bt.fit_cylinder(cylinder)
    assert fit["radius"] == pytest.approx(2.0, abs=1e-9)
    np.testing.assert_allclose(np.abs(fit["axis"]), [0, 0, 1], atol=1e-9)


def test_too_few_points_is_a_metrics_error():
    with pytest.raises(bt.MetricsError):
        bt.fit_sphere(np.zeros((2, 3)))
