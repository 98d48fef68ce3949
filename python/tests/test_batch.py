"""`beltrami.batch`: smooth -> residual -> areal parameters over many scans, in a loop and
on a Dask cluster, with the same numbers."""

from __future__ import annotations

import math

import pytest

import beltrami as bt
import beltrami.batch

pandas = pytest.importorskip("pandas")

SMOOTH = {"method": "taubin", "iterations": 8}
RESIDUAL = {"remove_mean": True}


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    """20 generated scans: noisy lens patches and spheres of several seeds and sizes."""
    folder = tmp_path_factory.mktemp("scans")
    paths = []
    for i in range(20):
        if i % 2 == 0:
            mesh = bt.generate("flens", size="small", noise=0.1 + 0.02 * i, seed=i + 1)
        else:
            mesh = bt.generate("sphere", level=2 + i % 3, noise=0.2, seed=i + 1)
        path = folder / f"scan_{i:02d}.ply"
        bt.write(path, mesh)
        paths.append(str(path))
    (folder / "notes.txt").write_text("not a scan")
    return folder, paths


def test_a_row_is_the_residual_of_the_smoothed_scan(scans):
    _, paths = scans
    row = beltrami.batch.process_scan(paths[0], smooth=SMOOTH, residual=RESIDUAL)
    mesh = bt.read(paths[0])
    smoothed, report = bt.smooth(mesh, **SMOOTH)
    want = bt.residual(mesh, smoothed, **RESIDUAL)
    assert row["scan"] == paths[0]
    assert row["vertices"] == mesh.n_vertices and row["faces"] == mesh.n_faces
    assert row["iterations"] == report["iterations"] == 8
    for key in ("sa", "sq", "sz", "sp", "sv", "ssk", "sku"):
        assert row[key] == want[key], key
    assert 0 < row["sa"] < row["sq"] < row["sz"]
    assert "heights" not in row and "form" not in row


def test_a_folder_gives_its_scans_in_name_order(scans):
    folder, paths = scans
    assert beltrami.batch.scans_in(folder) == paths
    with pytest.raises(NotADirectoryError):
        beltrami.batch.scans_in(folder / "notes.txt")
    with pytest.raises(ValueError, match="no scan files"):
        beltrami.batch.scans_in(folder.parent)
    with pytest.raises(FileNotFoundError, match="no such directory"):
        beltrami.batch.scans_in(folder / "missing")


def test_a_missing_parquet_engine_is_reported_before_any_scan(scans, monkeypatch):
    import importlib.util

    folder, _ = scans
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name in ("pyarrow", "fastparquet") else real(name, *a),
    )
    ran = []
    monkeypatch.setattr(beltrami.batch, "process_scan", lambda *a, **k: ran.append(a))
    with pytest.raises(ImportError, match="no scan was run"):
        beltrami.batch.run(folder, parquet=folder / "table.parquet")
    assert ran == []


def test_the_loop_collects_one_row_per_scan(scans, tmp_path):
    folder, paths = scans
    table = beltrami.batch.run(folder, smooth=SMOOTH, residual=RESIDUAL)
    assert list(table["scan"]) == paths
    assert len(table) == 20
    assert (table["stop"] == "completed").all()
    assert (table["sq"] > 0).all()
    # The spheres' residual (after the mean is removed) is the noise the smoothing took
    # out, which grows with the noise; lens patches with more noise have a larger Sq.
    lens = table[table.index % 2 == 0]
    assert lens["sq"].is_monotonic_increasing
    pyarrow = pytest.importorskip("pyarrow")
    assert pyarrow
    out = tmp_path / "table.parquet"
    again = beltrami.batch.run(paths[:3], smooth=SMOOTH, residual=RESIDUAL, parquet=out)
    pandas.testing.assert_frame_equal(pandas.read_parquet(out), again)


def test_a_local_dask_cluster_gives_the_same_numbers_as_the_loop(scans):
    distributed = pytest.importorskip("dask.distributed")
    folder, _ = scans
    sequential = beltrami.batch.run(folder, smooth=SMOOTH, residual=RESIDUAL)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        table = beltrami.batch.run(folder, client=client, smooth=SMOOTH, residual=RESIDUAL)
    assert list(table.columns) == list(sequential.columns)
    for column in sequential.columns:
        for got, want in zip(table[column], sequential[column]):
            if isinstance(want, float) and math.isnan(want):
                assert math.isnan(got), column
            else:
                assert got == want, column


def test_a_failing_scan_raises_its_error(scans, tmp_path):
    _, paths = scans
    bad = tmp_path / "broken.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 3\nend_header\n0 0\n")
    with pytest.raises(bt.FormatError, match="broken.ply"):
        beltrami.batch.run([paths[0], bad], smooth=SMOOTH)
