"""beltrami: the release `beltrami smooth` binary (path in $BELTRAMI), timed through
its `--report` JSON (seconds.weights + seconds.updates: operator assembly, weight
refreshes and sweeps, without file IO) and by the wall time of the whole process.
`--no-step-stats`: like the peers, no per-iteration displacement statistics.

Every scheme (uniform, distance, cotangent) with weights recomputed every iteration
and frozen, lambda 0.8, weight-sum normalisation, free boundary (the paper's and
Open3D's / trimesh's setting; the test spheres are closed, so it only matters on the
F-lens). Both cores (rayon's default); with ONE_THREAD_MESHES also on one core.
Inverse-distance and cotangent weights recomputed every iteration are also run with
`--summation scatter` (each edge's or triangle's weights once, the same results to
rounding).
On meshes small enough for the numerical checks it also writes the configuration
OpenMesh computes (lambda 0.5, weights once, fixed boundary)."""
import json
import os
import subprocess
import tempfile
import time

import numpy as np

import harness as H

BIN = os.environ["BELTRAMI"]
ONE_THREAD = os.environ.get("ONE_THREAD_MESHES", "sphere8").split()
SCHEMES = ("uniform", "distance", "cotangent")
NO_SYNC_MAX_VERTICES = 100_000


def smooth(src, dst, report, scheme, update, lam, boundary, threads=None, extra=()):
    cmd = [BIN, "smooth", src, dst, "--weights", scheme, "--update", update,
           "--iterations", str(H.ITERATIONS), "--lambda", str(lam), "--normalize", "sum",
           "--boundary", boundary, "--report", report, "--no-step-stats", *extra]
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    t0 = time.perf_counter()
    r0 = os.times()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    r1 = os.times()
    cpu = (r1.children_user - r0.children_user) + (r1.children_system - r0.children_system)
    with open(report) as f:
        rep = json.load(f)
    return wall, cpu, rep


def run_config(name, nv, scheme, update, lam=H.LAMBDA, boundary="free", threads=None,
               variant="", semantics="", reps=None, extra=()):
    src = H.mesh_path(name)
    os.makedirs(os.path.join(H.OUT, "beltrami"), exist_ok=True)
    dst = os.path.join(H.OUT, "beltrami", f"{name}_{scheme}_{update}{variant}.ply")
    runs = []
    for _ in range(reps or H.REPS):
        with tempfile.NamedTemporaryFile(suffix=".json") as tmp:
            wall, cpu, rep = smooth(src, dst, tmp.name, scheme, update, lam, boundary, threads,
                                    extra)
        runs.append((wall, cpu, rep["seconds"]))
        if wall > H.LONG:
            break
    smoothing = [s["weights"] + s["updates"] for _, _, s in runs]
    med = sorted(range(len(runs)), key=lambda k: smoothing[k])[(len(runs) - 1) // 2]
    wall, cpu, sec = runs[med]
    label = (f"smooth --weights {scheme} --update {update} --lambda {lam} --boundary {boundary}"
             + "".join(f" {a}" for a in extra)
             + (f" (RAYON_NUM_THREADS={threads})" if threads else ""))
    return H.record(
        "beltrami", label, name, nv, smoothing, H.ITERATIONS, scheme=scheme, weights=update,
        cpu_wall=cpu / wall, threads=str(threads or "all"), semantics=semantics,
        extra=dict(variant=variant, wall_seconds=wall,
                   wall_median=float(np.median([r[0] for r in runs])),
                   wall_min=min(r[0] for r in runs),
                   wall_max=max(r[0] for r in runs), read_seconds=sec["read"],
                   weights_seconds=sec["weights"], updates_seconds=sec["updates"],
                   write_seconds=sec["write"]))


def main():
    version = subprocess.run([BIN, "--version"], capture_output=True, text=True).stdout.strip()
    print(f"beltrami: {BIN} ({version or 'no --version'})", flush=True)
    for name in H.meshes_from_argv():
        V, F = H.load(name)
        nv = len(V)
        for scheme in SCHEMES:
            for update in ("every", "once"):
                run_config(name, nv, scheme, update,
                           semantics="x += 0.8 (sum_j w_ij x_j / W_i - x_i), Jacobi")
        for scheme in ("distance", "cotangent"):
            run_config(name, nv, scheme, "every", variant="_scatter",
                       extra=("--summation", "scatter"),
                       semantics="as above, each edge's or triangle's weights once")
        if nv <= NO_SYNC_MAX_VERTICES:
            # The peers' writers do not flush to disk; this is beltrami's like-for-like
            # whole process for the meshes where fixed costs matter.
            for scheme in SCHEMES:
                for update in ("every", "once"):
                    run_config(name, nv, scheme, update, variant="_nosync", extra=("--no-sync",),
                               semantics="as above, outputs not flushed to disk (as the peers')")
        if name in ONE_THREAD:
            for scheme in SCHEMES:
                for update in ("every", "once"):
                    run_config(name, nv, scheme, update, threads=1, variant="_1t",
                               semantics="as above, one thread")
        if nv <= H.CHECK_MAX_VERTICES:
            # What OpenMesh's JacobiLaplaceSmootherT computes, for its agreement check.
            for scheme in ("uniform", "cotangent"):
                run_config(name, nv, scheme, "once", lam=0.5, boundary="fixed", variant="_om",
                           semantics="OpenMesh's setting: lambda 0.5, weights once, fixed boundary",
                           reps=1)


if __name__ == "__main__":
    main()
