"""Shared fixtures: small generated surfaces, and the command-line binary when built."""

from __future__ import annotations

import os
import pathlib
import shutil

import pytest

import beltrami as bt

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def sphere() -> bt.Mesh:
    """A closed, noisy icosphere (level 3, 642 vertices)."""
    return bt.generate("sphere", level=3, noise=0.2, seed=7)


@pytest.fixture(scope="session")
def patch() -> bt.Mesh:
    """An open, noisy free-form patch (the coarse lens)."""
    return bt.generate("flens", size="small", noise=0.2, seed=3)


def cli_binary() -> pathlib.Path | None:
    """The `beltrami` command-line binary: $BELTRAMI_CLI, or a release or debug build
    in the Cargo target directory."""
    if "BELTRAMI_CLI" in os.environ:
        return pathlib.Path(os.environ["BELTRAMI_CLI"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("release", "debug"):
        candidate = target / profile / "beltrami"
        if candidate.is_file():
            return candidate
    found = shutil.which("beltrami")
    return pathlib.Path(found) if found else None


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    """The command-line binary; the test is skipped when it is not built."""
    binary = cli_binary()
    if binary is None:
        pytest.skip("the beltrami binary is not built (cargo build --release -p beltrami-cli)")
    return binary
