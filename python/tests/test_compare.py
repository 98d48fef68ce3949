"""`compare` and `distances` against a reference surface."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

import beltrami as bt

COMPARE_KEYS = {
    "mesh", "reference", "rms", "mean", "max", "area_rms", "signed", "hausdorff",
    "hausdorff_mesh_to_reference", "hausdorff_reference_to_mesh", "hausdorff_samples",
    "surface_rms", "same_topology", "displacement", "normal_deviation_deg", "normal_area_weighted_error",
    "volume", "area", "scalars", "png", "seconds",
}


def test_a_mesh_against_itself_is_zero():
    sphere = bt.generate("sphere", level=2)
    c = bt.compare(sphere, sphere)
    assert set(c) == COMPARE_KEYS
    assert c["max"] == 0.0 and c["hausdorff"] == 0.0
    assert c["same_topology"] and c["displacement"]["max"] == 0.0
    assert c["volume"]["ratio"] == 1.0


def test_smoothing_brings_a_noisy_sphere_closer():
    clean = bt.generate("sphere", level=3)
    noisy = bt.generate("sphere", level=3, noise=0.2, seed=4)
    smoothed, _ = bt.smooth(noisy, method="taubin", iterations=20)
    before, after = bt.compare(noisy, clean), bt.compare(smoothed, clean)
    assert after["rms"] < 0.6 * before["rms"]
    assert before["normal_deviation_deg"]["mean"] > after["normal_deviation_deg"]["mean"]


def test_distances_per_vertex():
    clean = bt.generate("sphere", level=3)
    points = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, 0.5]])
    d = bt.distances(points, clean)
    np.testing.assert_allclose(d, [1.0, 0.5], atol=5e-3)
    s = bt.distances(points, clean, signed=True)
    assert s[0] > 0 > s[1]
    noisy = bt.generate("sphere", level=3, noise=0.2, seed=4)
    c = bt.compare(noisy, clean)
    assert np.abs(bt.distances(noisy, clean)).max() == pytest.approx(c["max"], rel=1e-12)


def test_open_meshes_have_no_volume_and_samples_count():
    patch = bt.generate("flens", size="small")
    c = bt.compare(patch, patch, samples=1000)
    assert c["volume"] is None and c["hausdorff_samples"] == 1000


def test_a_reference_of_no_volume_has_no_ratio():
    # A closed tetrahedron squashed flat: no volume, so no ratio (None, not NaN or inf).
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, 0]], float)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    flat = bt.Mesh(v, f)
    lifted = v.copy()
    lifted[3, 2] = 1.0
    tetra = bt.Mesh(lifted, f)
    for mesh in (flat, tetra):
        volume = bt.compare(mesh, flat)["volume"]
        assert volume["reference"] == 0.0 and volume["ratio"] is None
    assert bt.compare(flat, tetra)["volume"]["ratio"] == 0.0


def test_different_topologies_have_no_displacement():
    a, b = bt.generate("sphere", level=2), bt.generate("sphere", level=3)
    c = bt.compare(a, b)
    assert not c["same_topology"] and c["displacement"] is None


def test_points_are_no_surface():
    points = bt.Mesh(np.eye(3), np.zeros((0, 3), dtype=int))
    with pytest.raises(bt.MeshError, match="no faces"):
        bt.compare(points, bt.generate("sphere", level=1))


def test_surface_rms_measures_whole_faces_and_matches_the_cli(cli, tmp_path):
    # A sphere 5 % larger than the level-4 sphere lies about 0.05 from it everywhere,
    # face interiors included (up to the triangles' sagitta, 1.1e-3).
    sphere = bt.generate("sphere", level=4)
    larger = bt.Mesh(1.05 * sphere.vertices, sphere.faces)
    c = bt.compare(larger, sphere, samples=20000)
    rms = c["surface_rms"]
    assert rms["symmetric"] == max(rms["mesh_to_reference"], rms["reference_to_mesh"])
    assert rms["symmetric"] == pytest.approx(0.05, abs=2e-3)
    assert bt.compare(larger, sphere)["surface_rms"] is None
    # The command line gives the same numbers.
    a, b = tmp_path / "larger.ply", tmp_path / "sphere.ply"
    bt.write(a, larger)
    bt.write(b, sphere)
    done = subprocess.run(
        [str(cli), "compare", str(a), str(b), "--json", "--samples", "20000"],
        capture_output=True, text=True, check=True,
    )
    assert json.loads(done.stdout)["surface_rms"] == rms
