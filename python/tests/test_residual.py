"""`beltrami.residual` against closed forms and against `beltrami residual --json`."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

import beltrami as bt


def textured_plane(n: int = 40, tilt: float = 0.02) -> bt.Mesh:
    """A tilted plane carrying a sine of amplitude 0.1 along x (wavelength 8)."""
    xs, ys = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0))
    z = tilt * xs + 0.1 * np.sin(2 * np.pi * xs / 8.0)
    vertices = np.stack([xs.ravel(), ys.ravel(), z.ravel()], axis=1)
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            faces += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return bt.Mesh(vertices, np.array(faces))


def test_a_plane_form_leaves_the_sine():
    r = bt.residual(textured_plane(), form="plane")
    # A sine of amplitude a has Sq = a / sqrt(2) and Sa = 2a / pi. The least-squares
    # plane also takes up the sine's small correlation with x over five periods (about
    # 1 %), so the tolerances are 2 % and 3 %.
    assert r["sq"] == pytest.approx(0.1 / np.sqrt(2), rel=2e-2)
    assert r["sq"] < 0.1 / np.sqrt(2)
    # Sa's |z| has kinks at the zeros: on 8 samples per period the lumped rule gives the
    # samples' mean |sin| (0.604), not 2/pi (0.637).
    sampled = 0.1 * np.mean(np.abs(np.sin(2 * np.pi * np.arange(8) / 8)))
    assert r["sa"] == pytest.approx(sampled, rel=2e-2)
    assert r["form"]["kind"] == "plane"
    assert r["smoothed"] is None and r["measured"] is None
    assert r["heights"].shape == (41 * 41,)
    assert r["std"] == pytest.approx(90.0, abs=1.0)  # crests along y: the lay is 90 deg


def test_options_and_material_ratio_points():
    r = bt.residual(textured_plane(), form="poly:2", remove_mean=True, smr=[0.0], smc=[50.0])
    assert r["datum"] == "mean"
    assert r["form"]["degree"] == 2
    assert r["smr"][0]["height"] == 0.0 and 0.0 < r["smr"][0]["ratio"] < 100.0
    assert r["smc"][0]["ratio"] == 50.0
    exact = bt.residual(textured_plane(), form="plane", quadrature="exact")
    assert exact["quadrature"] == "exact" and exact["sq"] < r["sq"] * 1.01


def test_bad_arguments_raise_value_error():
    mesh = textured_plane(8)
    with pytest.raises(ValueError, match="smoothed or form"):
        bt.residual(mesh)
    with pytest.raises(ValueError, match="not both"):
        bt.residual(mesh, mesh, form="plane")
    with pytest.raises(ValueError, match="poly:N"):
        bt.residual(mesh, form="cone")
    with pytest.raises(ValueError, match="0 to 100"):
        bt.residual(mesh, form="plane", smc=[150.0])
    with pytest.raises(ValueError, match="lumped"):
        bt.residual(mesh, form="plane", quadrature="simpson")
    with pytest.raises(bt.MetricsError):
        bt.residual(mesh, textured_plane(9))


def run(cli, *args):
    done = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.mark.parametrize("extra", [["--form", "plane"], ["--form", "sphere", "--remove-mean"], []])
def test_residual_matches_the_cli(cli, tmp_path, extra):
    noisy = tmp_path / "noisy.ply"
    smoothed = tmp_path / "smoothed.ply"
    run(cli, "generate", "sphere", noisy, "--level", "3", "--noise", "0.2", "--seed", "3")
    run(cli, "smooth", noisy, smoothed, "--iterations", "5")
    args = [noisy, *extra] if extra else [noisy, smoothed]
    expected = json.loads(run(cli, "residual", *args, "--json", "--smr", "0", "--smc", "20"))
    mesh = bt.read(noisy)
    kwargs = {"smr": [0.0], "smc": [20.0]}
    if extra:
        kwargs["form"] = extra[1]
        kwargs["remove_mean"] = "--remove-mean" in extra
        got = bt.residual(mesh, **kwargs)
    else:
        got = bt.residual(mesh, bt.read(smoothed), **kwargs)
    heights = got.pop("heights")
    assert len(heights) == expected["vertices"]
    # The command's notes on reading its files are not part of a call (python.md).
    assert expected.pop("notes") == []
    assert got == expected
