"""Closest-point distances and binary PLY read/write on one mesh (default sphere8).

Distances: the noisy mesh's vertices (655 362 points on level 8) to the clean mesh's
triangles (1 310 720).
* beltrami compare NOISY CLEAN --json: wall time of the whole process (reads both
  files, builds both half-edge meshes and BVHs, unsigned and signed distances of the
  vertices, the symmetric Hausdorff distance over both vertex sets, areas, volumes,
  normal deviations).
* Open3D RaycastingScene (float32, Embree): scene build + compute_distance, one
  direction; and the two directions with both files read, the distance work compare
  does.
PLY: reading and writing the noisy mesh (binary little-endian, double coordinates).
* beltrami: seconds.read and seconds.write of `smooth --weights uniform --iterations 0 --report`
  (read includes building and validating the half-edge mesh).
* Open3D io.read_triangle_mesh / io.write_triangle_mesh(write_ascii=False).
* trimesh.load(process=False) / Trimesh.export(ply).
* numpy: harness.read_ply, a header parse and one frombuffer (a floor for reading)."""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import harness as H

BIN = os.environ["BELTRAMI"]


def timed(fn, reps=None):
    times, result = [], None
    for _ in range(reps or H.REPS):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return times, result


def main():
    name = sys.argv[1] if len(sys.argv) > 1 else "sphere8"
    noisy, clean = H.mesh_path(name), H.mesh_path(name, clean=True)
    V, F = H.load(name)
    nv, nf = len(V), len(F)
    size_mb = os.path.getsize(noisy) / 1e6

    # --- closest-point distances -------------------------------------------------
    times, out = timed(lambda: subprocess.run([BIN, "compare", noisy, clean, "--json"], check=True,
                                              capture_output=True, text=True).stdout)
    rms = json.loads(out)["rms"]
    H.record("beltrami", "compare NOISY CLEAN --json (whole process)", name, nv, times, 1,
             scheme="closest-point", weights="-", kind="distance", threads="all",
             check=f"rms={rms:.6e}", extra=dict(points=nv, triangles=nf))
    try:
        import open3d as o3d
    except ImportError as e:
        print(f"  open3d not available ({e}): distance and IO rows skipped", flush=True)
        o3d = None
    if o3d is not None:
        Vc, Fc = H.read_ply(clean)

        def scene_of(Vs, Fs):
            scene = o3d.t.geometry.RaycastingScene()
            scene.add_triangles(o3d.core.Tensor(Vs.astype(np.float32)),
                                o3d.core.Tensor(Fs.astype(np.uint32)))
            return scene

        def one_way():
            return scene_of(Vc, Fc).compute_distance(o3d.core.Tensor(V.astype(np.float32))).numpy()

        times, d = timed(one_way)
        H.record("open3d", "RaycastingScene(clean) + compute_distance(noisy vertices), float32",
                 name, nv, times, 1, scheme="closest-point", weights="-", kind="distance",
                 threads="all", check=f"rms={np.sqrt(np.mean(d.astype(np.float64) ** 2)):.6e}",
                 extra=dict(points=nv, triangles=nf))

        def both_ways():
            a = o3d.io.read_triangle_mesh(noisy)
            b = o3d.io.read_triangle_mesh(clean)
            Va, Fa = np.asarray(a.vertices), np.asarray(a.triangles)
            Vb, Fb = np.asarray(b.vertices), np.asarray(b.triangles)
            d1 = scene_of(Vb, Fb).compute_distance(o3d.core.Tensor(Va.astype(np.float32))).numpy()
            d2 = scene_of(Va, Fa).compute_distance(o3d.core.Tensor(Vb.astype(np.float32))).numpy()
            return d1, d2

        times, _ = timed(both_ways)
        H.record("open3d", "read both + both directions (the distance work of compare)", name, nv,
                 times, 1, scheme="closest-point", weights="-", kind="distance", threads="all",
                 extra=dict(points=nv, triangles=nf))

    # --- binary PLY read / write ---------------------------------------------------
    with tempfile.TemporaryDirectory() as tmp:
        reads, writes = [], []
        for _ in range(H.REPS):
            report = os.path.join(tmp, "r.json")
            subprocess.run([BIN, "smooth", noisy, os.path.join(tmp, "b.ply"), "--weights", "uniform",
                            "--iterations", "0", "--report", report], check=True,
                           stdout=subprocess.DEVNULL)
            sec = json.load(open(report))["seconds"]
            reads.append(sec["read"])
            writes.append(sec["write"])
        extra = dict(megabytes=size_mb)
        H.record("beltrami", "read PLY + build half-edge mesh (smooth --report seconds.read)", name, nv,
                 reads, 1, scheme="ply-read", weights="-", kind="io", extra=extra)
        H.record("beltrami", "write PLY (smooth --report seconds.write)", name, nv, writes, 1,
                 scheme="ply-write", weights="-", kind="io", extra=extra)
        times, _ = timed(lambda: H.read_ply(noisy))
        H.record("numpy", "header parse + frombuffer (harness.read_ply)", name, nv, times, 1,
                 scheme="ply-read", weights="-", kind="io", extra=extra)
        if o3d is not None:
            times, m = timed(lambda: o3d.io.read_triangle_mesh(noisy))
            H.record("open3d", "io.read_triangle_mesh", name, nv, times, 1, scheme="ply-read",
                     weights="-", kind="io", extra=extra)
            path = os.path.join(tmp, "o.ply")
            times, _ = timed(lambda: o3d.io.write_triangle_mesh(path, m, write_ascii=False))
            H.record("open3d", "io.write_triangle_mesh(write_ascii=False)", name, nv, times, 1,
                     scheme="ply-write", weights="-", kind="io", extra=extra)
        try:
            import trimesh
        except ImportError as e:
            print(f"  trimesh not available ({e}): its IO rows skipped", flush=True)
            return
        times, m = timed(lambda: trimesh.load(noisy, process=False))
        H.record("trimesh", "trimesh.load(process=False)", name, nv, times, 1, scheme="ply-read",
                 weights="-", kind="io", extra=extra)
        path = os.path.join(tmp, "t.ply")
        times, _ = timed(lambda: m.export(path))
        H.record("trimesh", "Trimesh.export(ply, binary)", name, nv, times, 1, scheme="ply-write",
                 weights="-", kind="io", extra=extra)


if __name__ == "__main__":
    main()
