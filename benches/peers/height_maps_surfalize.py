#!/usr/bin/env python3
"""Checks beltrami's X3P and SDF readers and writers against surfalize, both ways.

    pip install surfalize
    cargo build -p beltrami-cli
    python3 benches/peers/height_maps_surfalize.py [path/to/beltrami]

1. surfalize writes an analytic texture on a tilted plane as X3P, binary SDF and
   ascii SDF; `beltrami residual FILE --form plane --json` reads each, and its Sq
   is compared with surfalize's Sq after levelling (surfalize's `level()` removes
   the least-squares plane; its Sq is the mean over pixels, beltrami's the lumped
   rule over the triangulated grid, and its residual is orthogonal to the plane,
   not vertical: they differ by a few parts in a thousand at the border).
2. beltrami writes the heights it read (`repair FILE.x3p OUT.x3p`, which keeps the
   grid, and OUT.sdf), surfalize reads them: the heights must be those surfalize
   reads from its own X3P file, bit for bit.

Not run by CI (surfalize is not a dependency); the figures go to docs/metrics.md.
"""

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from surfalize import Surface

BELTRAMI = sys.argv[1] if len(sys.argv) > 1 else "target/debug/beltrami"


def texture(nx=200, ny=150, step=0.5):
    """Heights in micrometres on a grid of `step` micrometres."""
    x = np.arange(nx) * step
    y = np.arange(ny) * step
    X, Y = np.meshgrid(x, y)
    return (
        0.002 * X
        + 0.001 * Y
        + 0.3 * np.sin(2 * np.pi * X / 17.0) * np.cos(2 * np.pi * Y / 23.0)
        + 0.05 * np.sin(2 * np.pi * (X + Y) / 7.1)
    )


def beltrami_json(*args):
    out = subprocess.run([BELTRAMI, *args, "--json"], check=True, capture_output=True)
    return json.loads(out.stdout)


def main():
    z = texture()
    step = 0.5
    surface = Surface(z.copy(), step, step)
    levelled = Surface(z.copy(), step, step).level()
    sq_surfalize = levelled.Sq()  # micrometres
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        files = {
            "x3p": tmp / "s.x3p",
            "sdf (binary)": tmp / "s.sdf",
            "sdf (ascii)": tmp / "a.sdf",
        }
        surface.save(files["x3p"])
        surface.save(files["sdf (binary)"])
        surface.save(files["sdf (ascii)"], binary=False)
        print("| file written by surfalize | Sq beltrami (µm) | Sq surfalize (µm) | difference |")
        print("|---|---|---|---|")
        for name, path in files.items():
            sq = beltrami_json("residual", str(path), "--form", "plane")["sq"] * 1e6
            diff = sq / sq_surfalize - 1
            print(f"| {name} | {sq:.6f} | {sq_surfalize:.6f} | {diff * 100:+.3f} % |")
            failures += abs(diff) > 0.005
        # beltrami writes, surfalize reads: the same heights as surfalize reads from its
        # own X3P file (the files hold metres; surfalize converts to micrometres).
        original = Surface.load(files["x3p"]).data
        for ext in ["x3p", "sdf"]:
            out = tmp / f"out.{ext}"
            subprocess.run(
                [BELTRAMI, "repair", str(files["x3p"]), str(out)],
                check=True,
                capture_output=True,
            )
            back = Surface.load(out)
            same = np.array_equal(back.data, original)
            step_ok = abs(back.step_x - step) < 1e-12 and abs(back.step_y - step) < 1e-12
            print(f"surfalize reads beltrami's .{ext}: heights equal {same}, steps equal {step_ok}")
            failures += not (same and step_ok)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
