#!/usr/bin/env python3
"""Every ISO 25178-2 parameter beltrami shares with surfalize, on the same X3P files.

    pip install surfalize
    cargo build --release -p beltrami-cli
    python3 benches/peers/areal_surfalize.py [path/to/beltrami] [--check]

Four textures on a 200 x 200 grid of 5 um spacing (a 1 mm square), written by
surfalize as X3P: two crossed waves (the texture of docs/metrics.md's convergence
table), grooves with a fine cross-wave (anisotropic), a seeded isotropic random field
(Gaussian-filtered white noise), and the same field folded to a plateau (-abs(z),
negatively skewed, as honed cylinder bores are). For each file, `beltrami residual
FILE --form plane --json` against surfalize's parameters after `level()`.

Units: beltrami reports X3P data in metres and lengths in the file's unit; the table
gives heights, lengths and volumes per area in um (1 um = 1 mL/m^2 for the volume
parameters), Sdr and the material ratios in %, Std in degrees.

Std: surfalize reports the direction of the maximum of the angular power spectrum in
image coordinates (y pointing down); beltrami reports the lay (90 degrees from the
spectrum's maximum) counter-clockwise from x with y up. A sine whose crests run along
y gives surfalize 0 and beltrami 90; the script converts surfalize's value a to
(90 - a) mod 180 before comparing (checked on that sine and on a diagonal wave).

With --check the script exits 1 when a parameter differs by more than its tolerance
(the TOLERANCE table below, per cent of the surfalize value or absolute where the
value can be near zero). Not run by CI (surfalize is not a dependency); the figures go
to docs/metrics.md.
"""

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from surfalize import Surface

ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
BELTRAMI = ARGS[0] if ARGS else "target/release/beltrami"
CHECK = "--check" in sys.argv
N = 200
STEP = 5.0  # um

# (beltrami key, surfalize call, scale from beltrami's unit to the table's, kind)
# kind: "height" (um), "ratio" (dimensionless), "percent" (beltrami fraction -> %),
# "mr" (both in %), "angle" (degrees), "length" (um).
PARAMETERS = [
    ("sa", lambda s: s.Sa(), "height"),
    ("sq", lambda s: s.Sq(), "height"),
    ("sp", lambda s: s.Sp(), "height"),
    ("sv", lambda s: s.Sv(), "height"),
    ("sz", lambda s: s.Sz(), "height"),
    ("ssk", lambda s: s.Ssk(), "ratio"),
    ("sku", lambda s: s.Sku(), "ratio"),
    ("sdq", lambda s: s.Sdq(), "ratio"),
    ("sdr", lambda s: s.Sdr(), "percent"),
    ("sk", lambda s: s.Sk(), "height"),
    ("spk", lambda s: s.Spk(), "height"),
    ("svk", lambda s: s.Svk(), "height"),
    ("smr1", lambda s: s.Smr1(), "mr"),
    ("smr2", lambda s: s.Smr2(), "mr"),
    ("sxp", lambda s: s.Sxp(), "height"),
    ("vmp", lambda s: s.Vmp(), "height"),
    ("vmc", lambda s: s.Vmc(), "height"),
    ("vvc", lambda s: s.Vvc(), "height"),
    ("vvv", lambda s: s.Vvv(), "height"),
    ("sal", lambda s: s.Sal(), "length"),
    ("str", lambda s: s.Str(), "ratio"),
    ("std", lambda s: (90.0 - s.Std()) % 180.0, "angle"),
]

# Largest accepted difference: (per cent of |surfalize|, absolute floor in the table's
# unit). The floor covers values near zero (Ssk of a symmetric texture, Smr1 of a
# texture without peaks); the per cent covers quadrature and construction differences
# documented in docs/metrics.md.
TOLERANCE = {
    "sa": (1.0, 0.0), "sq": (1.0, 0.0), "sp": (2.0, 0.0), "sv": (2.0, 0.0),
    "sz": (2.0, 0.0), "ssk": (3.0, 0.01), "sku": (2.0, 0.0), "sdq": (2.0, 0.0),
    "sdr": (3.0, 0.0), "sk": (3.0, 0.0), "spk": (5.0, 0.005), "svk": (5.0, 0.005),
    "smr1": (5.0, 0.2), "smr2": (5.0, 0.2), "sxp": (3.0, 0.0), "vmp": (5.0, 0.0005),
    "vmc": (3.0, 0.0), "vvc": (3.0, 0.0), "vvv": (5.0, 0.0005), "sal": (5.0, 0.0),
    "str": (10.0, 0.02), "std": (0.0, 1.0),
}


def waves(X, Y):
    return np.sin(2 * np.pi * X / 100) * np.cos(2 * np.pi * Y / 130) + 0.5 * np.sin(
        2 * np.pi * (X + Y) / 37
    )


def grooves(X, Y):
    return np.sin(2 * np.pi * X / 50) + 0.1 * np.sin(2 * np.pi * Y / 13)


ANALYTIC = {"two waves": waves, "grooves": grooves}


def continuous(f, m=4000):
    """The height and volume parameters of an analytic texture over the same 1 mm
    square, from m x m cell-centre samples (the midpoint rule; its error is far below
    the differences compared here): the truth the sampled grids approximate."""
    x = (np.arange(m) + 0.5) * (N * STEP / m)
    X, Y = np.meshgrid(x, x)
    z = f(X, Y).ravel()
    z = z - z.mean()
    sq = np.sqrt(np.mean(z**2))
    h = np.sort(z)[::-1]
    mr = (np.arange(h.size) + 0.5) / h.size
    c10, c80 = np.interp([0.1, 0.8], mr, h)
    vmp = np.sum(np.where(mr <= 0.1, h - c10, 0.0)) / h.size
    vm80 = np.sum(np.where(mr <= 0.8, h - c80, 0.0)) / h.size
    vvv = np.sum(np.where(mr >= 0.8, c80 - h, 0.0)) / h.size
    vv10 = np.sum(np.where(mr >= 0.1, c10 - h, 0.0)) / h.size
    return {
        "sa": np.mean(np.abs(z)), "sq": sq, "sp": z.max(), "sv": -z.min(),
        "sz": z.max() - z.min(), "ssk": np.mean(z**3) / sq**3,
        "sku": np.mean(z**4) / sq**4, "vmp": vmp, "vmc": vm80 - vmp,
        "vvc": vv10 - vvv, "vvv": vvv,
    }


def textures():
    x = np.arange(N) * STEP
    X, Y = np.meshgrid(x, x)
    rng = np.random.default_rng(20261126)
    white = rng.standard_normal((N, N))
    k = np.fft.fftfreq(N)
    K2 = k[None, :] ** 2 + k[:, None] ** 2
    sigma = 3.0  # pixels
    field = np.real(np.fft.ifft2(np.fft.fft2(white) * np.exp(-2 * (np.pi * sigma) ** 2 * K2)))
    field /= field.std()
    plateau = -np.abs(field)
    return {
        "two waves": waves(X, Y),
        "grooves": grooves(X, Y),
        "isotropic random": field,
        "plateau, -abs(random)": plateau,
    }


def beltrami_parameters(path):
    out = subprocess.run(
        [BELTRAMI, "residual", str(path), "--form", "plane", "--json"],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout)


def to_table_unit(value, kind):
    if value is None:
        return None
    if kind in ("height", "length"):
        return value * 1e6
    if kind == "percent":
        return value * 100.0
    return value


def main():
    failures = []
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, z in textures().items():
            path = Path(tmp) / "texture.x3p"
            Surface(z, STEP, STEP).save(str(path))
            theirs = Surface.load(str(path))
            theirs = theirs.level()
            ours = beltrami_parameters(path)
            truth = continuous(ANALYTIC[name]) if name in ANALYTIC else {}
            for key, call, kind in PARAMETERS:
                b = to_table_unit(ours.get(key), kind)
                try:
                    s = float(call(theirs))
                except Exception:  # surfalize raises or warns where undefined
                    s = float("nan")
                t = truth.get(key)
                if b is None or not np.isfinite(s):
                    rows.append((name, key, b, s, None, t))
                    continue
                diff = b - s
                if kind == "angle":
                    diff = (diff + 90.0) % 180.0 - 90.0
                rel = 100.0 * abs(diff) / abs(s) if s != 0 else (0.0 if diff == 0 else float("inf"))
                rows.append((name, key, b, s, rel, t))
                pct, floor = TOLERANCE[key]
                near = lambda ref, d: abs(d) <= max(pct / 100.0 * abs(ref), floor)
                # Within tolerance of surfalize, or of the continuous value where the
                # texture has one (surfalize's material-ratio curve can be the one off).
                if not near(s, diff) and not (t is not None and near(t, b - t)):
                    failures.append(f"{name} {key}: beltrami {b:.6g}, surfalize {s:.6g}")
    print("| texture | parameter | beltrami | surfalize | difference | continuous | beltrami − continuous | surfalize − continuous |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name, key, b, s, rel, t in rows:
        bs = "-" if b is None else f"{b:.5g}"
        ss = "-" if not np.isfinite(s) else f"{s:.5g}"
        absolute = key in ("ssk", "std")  # near zero: the difference itself
        if rel is None:
            rs = "-"
        elif absolute:
            rs = f"{abs(b - s) if key != 'std' else abs((b - s + 90.0) % 180.0 - 90.0):.2g}"
        else:
            rs = f"{rel:.2f} %"
        if absolute and t is not None and b is not None and np.isfinite(s):
            print(f"| {name} | {key} | {b:.5g} | {s:.5g} | {rs} | {t:.2g} | {b - t:+.2g} | {s - t:+.2g} |")
            continue
        if t is None or b is None or not np.isfinite(s) or t == 0:
            ts = bt = st = "-"
        else:
            ts = f"{t:.5g}"
            bt = f"{100.0 * (b - t) / abs(t):+.2f} %"
            st = f"{100.0 * (s - t) / abs(t):+.2f} %"
        print(f"| {name} | {key} | {bs} | {ss} | {rs} | {ts} | {bt} | {st} |")
    if failures:
        print("\nbeyond tolerance:", *failures, sep="\n  ", file=sys.stderr)
        if CHECK:
            sys.exit(1)


if __name__ == "__main__":
    main()
