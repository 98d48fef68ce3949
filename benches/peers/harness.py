"""What every peer driver shares: reading the benchmark meshes, timing with
repetitions, and appending one JSON record per measurement to out/records.jsonl.

A record holds the median, minimum and maximum wall time of the repetitions, the
CPU/wall ratio of the median run (1.0 = one core busy, 2.0 = both), and
ns per vertex-iteration = median seconds * 1e9 / (vertices * iterations).
"""
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.environ.get("PEERS_MESH_DIR", os.path.join(HERE, "meshes"))
OUT = os.environ.get("PEERS_OUT_DIR", os.path.join(HERE, "out"))
RECORDS = os.path.join(OUT, "records.jsonl")

ITERATIONS = int(os.environ.get("ITERATIONS", "100"))
LAMBDA = 0.8
REPS = int(os.environ.get("REPS", "3"))
# A run longer than this many seconds is not repeated (the range is then empty).
LONG = float(os.environ.get("LONG_RUN_SECONDS", "40"))
# Numerical agreement with beltrami is checked only on meshes up to this size.
CHECK_MAX_VERTICES = 300_000

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def read_ply(path):
    """Binary little-endian triangle PLY -> (V float64 (n, 3), F int64 (m, 3)).

    Reads what `beltrami` writes (and most tools): a vertex element of scalar
    properties containing x, y, z, then a face element whose only property is a
    list of three indices."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError(f"{path}: not a PLY file")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise ValueError(f"{path}: only binary little-endian PLY is read here")
    elements = []
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            elements.append([words[1], int(words[2]), []])
        elif words[:1] == ["property"]:
            elements[-1][2].append(words[1:])
    offset = end + len(b"end_header\n")
    V = F = None
    for name, count, props in elements:
        if name == "vertex":
            dtype = np.dtype([(p[-1], "<" + _PLY_TYPES[p[0]]) for p in props])
            rows = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            V = np.stack([rows["x"], rows["y"], rows["z"]], axis=1).astype(np.float64)
            offset += dtype.itemsize * count
        elif name == "face":
            if len(props) != 1 or props[0][0] != "list":
                raise ValueError(f"{path}: face element must be one index list")
            dtype = np.dtype([("n", "<" + _PLY_TYPES[props[0][1]]),
                              ("i", "<" + _PLY_TYPES[props[0][2]], (3,))])
            rows = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            if (rows["n"] != 3).any():
                raise ValueError(f"{path}: only triangles are read here")
            F = rows["i"].astype(np.int64)
            offset += dtype.itemsize * count
        else:
            raise ValueError(f"{path}: unexpected element {name!r}")
    return V, F


def mesh_path(name, clean=False):
    return os.path.join(MESHES, name + ("_clean" if clean else "") + ".ply")


def load(name):
    return read_ply(mesh_path(name))


def meshes_from_argv():
    names = sys.argv[1:]
    if not names:
        sys.exit("error: name the meshes to run, e.g. sphere6 sphere8")
    return names


def mean_edge(V, F):
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return float(np.linalg.norm(V[e[:, 0]] - V[e[:, 1]], axis=1).mean())


def is_closed(F):
    """Every undirected edge has exactly two faces."""
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e[:, 0] * (int(F.max()) + 1) + e[:, 1], return_counts=True)
    return bool((counts == 2).all())


def repeat(run, setup=None, reps=None):
    """Calls setup() untimed, then run(state) timed, `reps` times (once more only while
    a run stays under LONG seconds). Returns (times, cpu/wall of the median run, last
    result)."""
    reps = reps or REPS
    times, ratios, result = [], [], None
    for _ in range(reps):
        state = setup() if setup else None
        c0, t0 = time.process_time(), time.perf_counter()
        result = run(state)
        t1, c1 = time.perf_counter(), time.process_time()
        times.append(t1 - t0)
        ratios.append((c1 - c0) / max(t1 - t0, 1e-9))
        if t1 - t0 > LONG:
            break
    median_run = int(np.argsort(times)[(len(times) - 1) // 2])
    return times, ratios[median_run], result


def record(tool, operation, mesh, vertices, times, iterations, *, scheme, weights,
           cpu_wall=None, threads="1", check="", semantics="", kind="smooth", extra=None):
    """Appends one measurement. `scheme` is uniform/distance/cotangent (or another
    word for non-smoothing kinds), `weights` is every/once/- ."""
    times = [float(t) for t in times]
    med = float(np.median(times))
    rec = dict(
        kind=kind, tool=tool, operation=operation, mesh=mesh, vertices=int(vertices),
        iterations=int(iterations), scheme=scheme, weights=weights,
        seconds=med, seconds_min=min(times), seconds_max=max(times), runs=len(times),
        ns_per_vertex_iteration=med * 1e9 / (vertices * max(iterations, 1)),
        cpu_wall=None if cpu_wall is None else round(float(cpu_wall), 2),
        threads=threads, check=check, semantics=semantics,
    )
    if extra:
        rec.update(extra)
    os.makedirs(OUT, exist_ok=True)
    with open(RECORDS, "a") as f:
        f.write(json.dumps(rec) + "\n")
    spread = f"[{rec['seconds_min']:.3f}-{rec['seconds_max']:.3f}]" if len(times) > 1 else ""
    print(f"  {tool:9s} {mesh:9s} {scheme:9s} {weights:5s} {med:9.3f} s {spread:17s} "
          f"{rec['ns_per_vertex_iteration']:9.1f} ns/v-it  {operation}"
          + (f"  ({check})" if check else ""), flush=True)
    return rec


def whole_process(tool, operation, mesh, vertices, read, smooth, write, *, scheme, weights,
                  semantics="", reps=None):
    """Times what a user's script does with `tool`: read the benchmark file with the tool's
    own reader (`read(path) -> state`), smooth (`smooth(state) -> result`) and write the
    result with its own writer (`write(result, path)`, to out/whole/), `reps` times. The
    interpreter's start and the imports are not counted, in the peer's favour; beltrami's
    counterpart is its whole process (start, read, smooth, write). Records kind "whole"
    with the median run's read, smooth and write seconds."""
    src = mesh_path(mesh)
    os.makedirs(os.path.join(OUT, "whole"), exist_ok=True)
    dst = os.path.join(OUT, "whole", f"{tool}_{mesh}_{scheme}_{weights}.ply")
    times, parts = [], []
    for _ in range(reps or REPS):
        t0 = time.perf_counter()
        state = read(src)
        t1 = time.perf_counter()
        result = smooth(state)
        t2 = time.perf_counter()
        write(result, dst)
        t3 = time.perf_counter()
        times.append(t3 - t0)
        parts.append((t1 - t0, t2 - t1, t3 - t2))
        if t3 - t0 > LONG:
            break
    med = int(np.argsort(times)[(len(times) - 1) // 2])
    return record(tool, operation, mesh, vertices, times, ITERATIONS, scheme=scheme,
                  weights=weights, kind="whole", semantics=semantics,
                  extra=dict(read_seconds=parts[med][0], smooth_seconds=parts[med][1],
                             write_seconds=parts[med][2]))


def beltrami_output(mesh, scheme, weights, variant=""):
    """Positions beltrami produced for a configuration (written by bench_beltrami.py),
    or None when that run is not there."""
    path = os.path.join(OUT, "beltrami", f"{mesh}_{scheme}_{weights}{variant}.ply")
    return read_ply(path)[0] if os.path.exists(path) else None


def agreement(X, mesh, scheme, weights, V, F, variant=""):
    """'max dev. from beltrami k h' (largest vertex distance) for the check column (h = mean edge of the input),
    or '' when the mesh is too large or beltrami's output is missing."""
    if len(V) > CHECK_MAX_VERTICES:
        return ""
    ref = beltrami_output(mesh, scheme, weights, variant)
    if ref is None:
        return ""
    X = np.asarray(X, dtype=np.float64)
    bad = int((~np.isfinite(X).all(axis=1)).sum())
    if bad:
        return f"{bad} non-finite vertices"
    d = np.linalg.norm(X - ref, axis=1).max() / mean_edge(V, F)
    return f"max dev. from beltrami {d:.1e} h"
