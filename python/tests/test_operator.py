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


@pytest.mark.parametrize(
    ("args", "options"),
    [
        ([], {}),
        (["--weights", "uniform"], {"weights": "uniform"}),
        (["--normalize", "area"], {"normalize": "area"}),
        (
            ["--normalize", "area", "--vertex-area", "barycentric", "--cotangent-negative", "clamp"],
            {"normalize": "area", "vertex_area": "barycentric", "cotangent_negative": "clamp"},
        ),
    ],
)
def test_the_cli_operator_files_are_the_package_laplacian(cli, tmp_path, args, options):
    import subprocess

    import scipy.io

    mesh = bt.generate("flens", size="small", noise=0.2, seed=4)
    scan = tmp_path / "scan.ply"
    bt.write(scan, mesh)
    want = bt.laplacian(bt.read(scan), **options)
    for ext in ("mtx", "npz"):
        out = tmp_path / f"L.{ext}"
        done = subprocess.run(
            [str(cli), "operator", str(scan), str(out), "--force", *args],
            capture_output=True,
            text=True,
        )
        assert done.returncode == 0, done.stderr
        got = scipy.io.mmread(out) if ext == "mtx" else scipy_sparse.load_npz(out)
        got = scipy_sparse.csr_matrix(got)
        assert got.shape == want.shape
        assert abs(got - want).max() <= 1e-15, ext
        if ext == "npz":
            assert got.format == "csr"
            # save_npz's CSR arrays, exactly: same structure and the same bits.
            np.testing.assert_array_equal(got.indptr, want.indptr)
            np.testing.assert_array_equal(got.indices, want.indices)
            np.testing.assert_array_equal(got.data, want.data)
        else:
            np.testing.assert_array_equal(got.toarray(), want.toarray())


def test_the_cli_mass_matrix_is_the_package_mass_matrix(cli, tmp_path):
    import subprocess

    scan = tmp_path / "scan.ply"
    bt.write(scan, bt.generate("sphere", level=3, noise=0.1))
    out = tmp_path / "M.npz"
    done = subprocess.run(
        [str(cli), "operator", str(scan), str(out), "--mass", "--vertex-area", "barycentric"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    want = bt.mass_matrix(bt.read(scan), vertex_area="barycentric")
    got = scipy_sparse.load_npz(out)
    np.testing.assert_array_equal(got.toarray(), want.toarray())


def test_normalize_none_is_the_default(sphere):
    # As smooth takes normalize=None.
    assert (bt.laplacian(sphere, normalize=None) != bt.laplacian(sphere)).nnz == 0
