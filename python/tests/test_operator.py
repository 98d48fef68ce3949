"""The Laplacian and the mass matrix as scipy.sparse matrices."""

from __future__ import annotations

import numpy as np
import pytest

import beltrami as bt

scipy_sparse = pytest.importorskip("scipy.sparse")


def test_one_explicit_step_is_x_plus_lambda_l_x(sphere):
    L = bt.laplacian(sphere)
    assert scipy_sparse.issparse(L) and L.format == "csr"
    assert L.shape == (sphere.n_vertices, sphere.n_vertices)
    stepped, _ = bt.smooth(sphere, iterations=1, lam=0.5)
    x = sphere.vertices
    np.testing.assert_allclose(x + 0.5 * (L @ x), stepped.vertices, rtol=0, atol=1e-14)


def test_weight_sum_rows_sum_to_zero(sphere):
    L = bt.laplacian(sphere, weights="uniform")
    np.testing.assert_allclose(np.asarray(L.sum(axis=1)).ravel(), 0.0, atol=1e-14)
    np.testing.assert_array_equal(L.diagonal(), -1.0)


def test_area_laplacian_is_the_mean_curvature_normal_on_the_sphere():
    sphere = bt.generate("sphere", level=4)
    L = bt.laplacian(sphere, normalize="area")
    x = sphere.vertices
    # L x ≈ -2 H n = -2 x on the unit sphere.
    assert np.abs(L @ x + 2 * x).max() < 0.02 * 2


def test_cotangent_laplacian_of_a_linear_function_vanishes_inside_a_plane():
    rng = np.random.default_rng(5)
    n = 7
    ij = np.array([(i, j) for j in range(n) for i in range(n)], dtype=float)
    inside = (ij > 0).all(axis=1) & (ij < n - 1).all(axis=1)
    xy = ij + np.where(inside[:, None], rng.uniform(-0.2, 0.2, ij.shape), 0.0)
    vertices = np.c_[xy, np.zeros(len(xy))]
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i
            faces += [[a, b, c], [a, c, d]]
    grid = bt.Mesh(vertices, faces)
    f = 2.0 * xy[:, 0] - 3.0 * xy[:, 1] + 1.0
    for normalize in ("sum", "area"):
        L = bt.laplacian(grid, normalize=normalize)
        np.testing.assert_allclose((L @ f)[inside], 0.0, atol=1e-12)
        assert np.abs(L @ f)[~inside].max() > 1e-3


def test_mass_matrix_sums_to_the_area(sphere):
    M = bt.mass_matrix(sphere)
    assert M.shape == (sphere.n_vertices, sphere.n_vertices)
    assert M.sum() == pytest.approx(bt.info(sphere)["area"], rel=1e-12)
    assert bt.mass_matrix(sphere, vertex_area="barycentric").sum() == pytest.approx(
        bt.info(sphere)["area"], rel=1e-12
    )


def test_bad_words_are_value_errors(sphere):
    with pytest.raises(ValueError, match="normalize must be one of"):
        bt.laplacian(sphere, normalize="mass")
    with pytest.raises(ValueError, match="vertex_area must be one of"):
        bt.mass_matrix(sphere, vertex_area="voronoi")
