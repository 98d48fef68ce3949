"""The Python side in one process: `beltrami.smooth` against trimesh, Open3D, PyMeshLab
and libigl on the level-8 sphere (655,362 vertices), 100 iterations, and the overhead of
the binding against the `beltrami smooth` binary in the same run.

    python bench_python.py [--cli PATH] [--level 8] [--iterations 100] [--reps 5]
    python bench_python.py --memory [--level 8] [--iterations 100]

`--memory` measures instead the peak resident memory of a fresh process running
`beltrami.batch.process_scan` (read, smooth, residual: one Dask task) on the sphere,
per million vertices: what a batch worker needs per thread.

The binding's time is the wall time of the `bt.smooth(mesh, ...)` call as Python sees it:
the positions copied into the run, the GIL released, the smoothing, the result copied
into a new Mesh and the report built as a dict. The CLI's time is the smoothing time of
its `--report` (`seconds.weights + seconds.updates`, without reading and writing the
file), which is the same work; its process wall time is shown beside it. The overhead
is median(binding) / median(CLI smoothing) - 1, which the package aims to keep at most
5 %; beside it, the same against the CLI's wall time without reading and writing the
file (which includes the smoother's set-up, as the binding's time does).
Copying in (`bt.Mesh(V, F)`, which also builds the half-edge connectivity) and out
(`mesh.vertices`) are timed on their own.

Peers (each skipped when it does not import), with beltrami's run of the same
semantics beside it:
* trimesh filter_laplacian (uniform weights built once, operator prebuilt):
  beltrami uniform, update="once";
* Open3D filter_smooth_laplacian (inverse distance, recomputed every iteration):
  beltrami distance, update="every", boundary="free";
* PyMeshLab apply_coord_laplacian_smoothing (cotangent, no lambda: it is a different
  step, so the row is a cost comparison only);
* libigl cotmatrix rebuilt every iteration + a scipy step: beltrami cotangent.

Threads: every tool runs with what it uses by default on this machine (beltrami and
Open3D: all cores; trimesh, PyMeshLab, libigl: one); RAYON_NUM_THREADS limits
beltrami's. Prints a Markdown table and the machine line; writes nothing else.
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import beltrami as bt


def timed(run, setup=None, reps=5):
    """Median, min and max wall seconds of `run(setup())` over `reps` runs, and the last
    result. `setup` is not timed."""
    times, result = [], None
    for _ in range(reps):
        state = setup() if setup else None
        t0 = time.perf_counter()
        result = run(state)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), max(times), result


def cli_smooth(cli, path, out, report, args):
    """One CLI run: its smoothing seconds (from --report), its process wall time, and the
    wall time without reading and writing the mesh (the smoother's set-up and run,
    the report, process start and exit)."""
    t0 = time.perf_counter()
    subprocess.run([cli, "smooth", path, out, "--report", report, "--force", *args],
                   check=True, capture_output=True)
    wall = time.perf_counter() - t0
    with open(report) as f:
        seconds = json.load(f)["seconds"]
    return seconds["weights"] + seconds["updates"], wall, wall - seconds["read"] - seconds["write"]


# VmHWM, not getrusage's ru_maxrss, which a child inherits from its parent at fork.
MEMORY_CHILD = """
import sys
import beltrami.batch

def kib(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith(field))

base = kib("VmHWM:")
row = beltrami.batch.process_scan(sys.argv[1], smooth={"iterations": int(sys.argv[2])})
print(base * 1024, kib("VmHWM:") * 1024, row["vertices"])
"""


def memory(level, iterations):
    """Peak RSS of a fresh process running `beltrami.batch.process_scan` (read, smooth,
    residual) on the noisy sphere of `level`: (bytes after the imports, peak bytes,
    vertices)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sphere.ply")
        bt.write(path, bt.generate("sphere", level=level, noise=0.2, seed=1))
        out = subprocess.run([sys.executable, "-c", MEMORY_CHILD, path, str(iterations)],
                             check=True, capture_output=True, text=True).stdout.split()
    base, peak, vertices = (int(x) for x in out)
    return base, peak, vertices


def machine():
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
    return (f"{cpu}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}, "
            f"Python {platform.python_version()}, numpy {np.__version__}, "
            f"RAYON_NUM_THREADS={os.environ.get('RAYON_NUM_THREADS', 'unset')}, commit {commit or '?'}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cli", default=os.environ.get("BELTRAMI_CLI", "beltrami"))
    ap.add_argument("--level", type=int, default=8)
    ap.add_argument("--iterations", type=int, default=100)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--peer-reps", type=int, default=3)
    ap.add_argument("--no-peers", action="store_true", help="only the binding against the CLI")
    ap.add_argument("--memory", action="store_true",
                    help="only measure a batch worker's peak memory per million vertices")
    a = ap.parse_args()
    if a.memory:
        base, peak, vertices = memory(a.level, a.iterations)
        mib = 1024 * 1024
        print(f"process_scan on the level-{a.level} sphere ({vertices} vertices, {a.iterations} "
              f"iterations): peak RSS {peak / mib:.0f} MiB, {base / mib:.0f} MiB after the "
              f"imports; {(peak - base) / vertices * 1e6 / mib:.0f} MiB per million vertices "
              f"above that, {peak / vertices * 1e6 / mib:.0f} MiB per million vertices in all")
        print(f"machine: {machine()}")
        return
    n, lam = a.iterations, 0.8
    rows = []

    def row(tool, what, med, lo, hi, note=""):
        rows.append((tool, what, med, lo, hi, note))
        print(f"  {tool:10s} {what:58s} {med:8.3f} s [{lo:.3f}-{hi:.3f}] {note}",
              file=sys.stderr, flush=True)

    sphere = bt.generate("sphere", level=a.level, noise=0.2, seed=1)
    V = sphere.vertices.copy()  # writeable: Open3D refuses read-only arrays
    F = np.ascontiguousarray(sphere.faces)
    nv = len(V)
    print(f"sphere level {a.level}: {nv} vertices, {len(F)} faces, {n} iterations",
          file=sys.stderr, flush=True)

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sphere.ply")
        bt.write(path, sphere)
        out, report = os.path.join(tmp, "out.ply"), os.path.join(tmp, "report.json")

        # The binding against the binary, run by run in turn, so that both see the same
        # machine (other work on it slows both alike).
        overhead = []
        for weights, update, boundary in (("cotangent", "every", "fixed"),
                                          ("uniform", "once", "fixed")):
            args = ["--iterations", str(n), "--weights", weights, "--update", update,
                    "--boundary", boundary]
            cli_s, cli_wall, cli_phase, py_s, result = [], [], [], [], None
            for _ in range(a.reps):
                smoothing, wall, phase = cli_smooth(a.cli, path, out, report, args)
                cli_s.append(smoothing)
                cli_wall.append(wall)
                cli_phase.append(phase)
                t0 = time.perf_counter()
                result = bt.smooth(sphere, weights=weights, iterations=n, update=update,
                                   boundary=boundary)
                py_s.append(time.perf_counter() - t0)
            same = np.array_equal(result[0].vertices, bt.read(out).vertices)
            cli_med, py_med = statistics.median(cli_s), statistics.median(py_s)
            ratio = py_med / cli_med - 1.0
            phase_med = statistics.median(cli_phase)
            overhead.append((weights, update, ratio, py_med / phase_med - 1.0))
            row("beltrami", f"CLI smooth --weights {weights} --update {update} (report)",
                cli_med, min(cli_s), max(cli_s),
                f"process wall {statistics.median(cli_wall):.3f} s, without read and write "
                f"{phase_med:.3f} s")
            row("beltrami", f"bt.smooth(weights={weights!r}, update={update!r})", py_med,
                min(py_s), max(py_s),
                f"binding overhead {100 * ratio:+.1f} %, positions "
                f"{'bit-identical' if same else 'DIFFER'}")
        med, lo, hi, _ = timed(lambda _: bt.Mesh(V, F), reps=a.reps)
        row("beltrami", "bt.Mesh(V, F): copy in + half-edge build", med, lo, hi)
        med, lo, hi, _ = timed(lambda _: sphere.vertices, reps=a.reps)
        row("beltrami", "mesh.vertices: copy out", med, lo, hi)

    def peer(name, body):
        try:
            body()
        except ImportError as e:
            print(f"  {name}: skipped ({e})", file=sys.stderr, flush=True)

    r = a.peer_reps

    def trimesh_rows():
        import trimesh
        from trimesh.smoothing import filter_laplacian, laplacian_calculation
        op = laplacian_calculation(trimesh.Trimesh(V, F, process=False), equal_weight=True)
        med, lo, hi, _ = timed(
            lambda m: filter_laplacian(m, lamb=lam, iterations=n, volume_constraint=False,
                                       laplacian_operator=op),
            setup=lambda: trimesh.Trimesh(V.copy(), F, process=False), reps=r)
        row("trimesh", f"filter_laplacian(lamb=0.8, {n}), operator prebuilt "
            f"({trimesh.__version__})", med, lo, hi)
        med, lo, hi, _ = timed(lambda _: bt.smooth(sphere, weights="uniform", iterations=n,
                                                   update="once", boundary="free"), reps=r)
        row("beltrami", "bt.smooth(weights='uniform', update='once')", med, lo, hi, "same semantics")

    def open3d_rows():
        import open3d as o3d

        def make():
            m = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(V),
                                          o3d.utility.Vector3iVector(F.astype(np.int32)))
            m.compute_adjacency_list()
            return m
        med, lo, hi, _ = timed(
            lambda m: m.filter_smooth_laplacian(number_of_iterations=n, lambda_filter=lam),
            setup=make, reps=r)
        row("open3d", f"filter_smooth_laplacian({n}, 0.8) ({o3d.__version__})", med, lo, hi)
        med, lo, hi, _ = timed(lambda _: bt.smooth(sphere, weights="distance", iterations=n,
                                                   boundary="free"), reps=r)
        row("beltrami", "bt.smooth(weights='distance')", med, lo, hi, "same semantics")

    def pymeshlab_rows():
        from importlib.metadata import version
        import pymeshlab

        def setup():
            ms = pymeshlab.MeshSet()
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F.astype(np.int32)))
            return ms
        med, lo, hi, _ = timed(
            lambda ms: ms.apply_coord_laplacian_smoothing(stepsmoothnum=n, boundary=True,
                                                          cotangentweight=True),
            setup=setup, reps=r)
        row("pymeshlab", f"apply_coord_laplacian_smoothing({n}, cotangentweight=True) "
            f"({version('pymeshlab')})", med, lo, hi, "no lambda: a different step")

    def igl_rows():
        from importlib.metadata import version
        import igl

        def explicit(_):
            X = V.copy()
            for _ in range(n):
                L = igl.cotmatrix(X, F)
                X += lam * (L @ X) / (-L.diagonal())[:, None]
            return X
        med, lo, hi, _ = timed(explicit, reps=r)
        row("libigl", f"igl.cotmatrix every iteration + scipy step ({version('libigl')})",
            med, lo, hi)
        med, lo, hi, _ = timed(lambda _: bt.smooth(sphere, iterations=n, boundary="free"), reps=r)
        row("beltrami", "bt.smooth(weights='cotangent')", med, lo, hi, "same semantics")

    if not a.no_peers:
        peer("trimesh", trimesh_rows)
        peer("open3d", open3d_rows)
        peer("pymeshlab", pymeshlab_rows)
        peer("libigl", igl_rows)

    print(f"Level-{a.level} sphere ({nv} vertices), {n} iterations, one process; "
          f"median of {a.reps} runs (beltrami vs CLI), {r} (peers).\n")
    print("| tool | call | median s | range s | note |")
    print("|---|---|---:|---:|---|")
    for tool, what, med, lo, hi, note in rows:
        print(f"| {tool} | {what} | {med:.3f} | {lo:.3f}-{hi:.3f} | {note} |")
    print()
    for weights, update, ratio, phase in overhead:
        print(f"binding overhead, {weights}/{update}: {100 * ratio:+.1f} % over the CLI's "
              f"smoothing seconds ({'within' if ratio <= 0.05 else 'over'} the 5 % budget), "
              f"{100 * phase:+.1f} % over its wall time without reading and writing")
    print(f"\nmachine: {machine()}")


if __name__ == "__main__":
    main()
