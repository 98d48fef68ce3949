#!/usr/bin/env python3
"""Loop subdivision, two steps, on one mesh: beltrami against OpenMesh and PyMeshLab.

    bench_subdivision.py MESH.ply [--reps N] [--beltrami BIN] [--openmesh BIN]

Times, in one run and on the same file:
  beltrami   `beltrami subdivide MESH OUT --steps 2 --json`: its "seconds" (the two
             steps, building and validating each refined mesh; not reading or
             writing), on every core and with RAYON_NUM_THREADS=1;
  OpenMesh   LoopT<TriMesh(double)>(mesh, 2), openmesh_subdivide.cpp (built here with
             g++ -O2 -DNDEBUG when --openmesh is not given; needs libopenmesh-dev);
  PyMeshLab  meshing_surface_subdivision_loop(loopweight='Loop', iterations=2,
             threshold=0 absolute, so that every edge is split), the filter call only.
Prints a Markdown table of medians and of each peer's median over beltrami's.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def beltrami(binary, mesh, reps, threads):
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    times, faces = [], None
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(reps):
            out = subprocess.run(
                [binary, "subdivide", mesh, os.path.join(tmp, "out.ply"), "--steps", "2",
                 "--json", "--force"],
                check=True, capture_output=True, env=env).stdout
            summary = json.loads(out)
            times.append(summary["seconds"])
            faces = summary["faces"]
    return times, faces


def openmesh(binary, mesh, reps):
    if binary is None:
        binary = os.path.join(tempfile.mkdtemp(), "openmesh_subdivide")
        subprocess.run(["g++", "-O2", "-DNDEBUG", "-std=c++17", "-o", binary,
                        os.path.join(HERE, "openmesh_subdivide.cpp"), "-lOpenMeshCore",
                        "-lOpenMeshTools"], check=True, capture_output=True)
    out = json.loads(subprocess.run([binary, mesh, "2", str(reps)], check=True,
                                    capture_output=True).stdout)
    return out["seconds"], out["faces"]


def pymeshlab_loop(mesh, reps):
    import pymeshlab
    times, faces = [], None
    for _ in range(reps):
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(mesh)
        t0 = time.perf_counter()
        ms.apply_filter("meshing_surface_subdivision_loop", loopweight="Loop", iterations=2,
                        threshold=pymeshlab.PureValue(0.0))
        times.append(time.perf_counter() - t0)
        faces = ms.current_mesh().face_number()
    return times, faces


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh")
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--beltrami", default=os.path.join(HERE, "../../target/release/beltrami"))
    ap.add_argument("--openmesh")
    args = ap.parse_args()

    rows = []
    base, faces = beltrami(args.beltrami, args.mesh, args.reps, None)
    rows.append(("beltrami (all cores)", base, faces))
    rows.append(("beltrami (1 thread)", *beltrami(args.beltrami, args.mesh, args.reps, 1)))
    for name, run in [("OpenMesh LoopT", lambda: openmesh(args.openmesh, args.mesh, args.reps)),
                      ("PyMeshLab loop", lambda: pymeshlab_loop(args.mesh, args.reps))]:
        try:
            rows.append((name, *run()))
        except Exception as e:  # a peer that is not installed is reported, not fatal
            print(f"skipped {name}: {e}", file=sys.stderr)
    ref = statistics.median(base)
    print(f"| tool | faces | median s | min s | ÷ beltrami (all cores) |")
    print(f"|---|---:|---:|---:|---:|")
    for name, times, n in rows:
        med = statistics.median(times)
        print(f"| {name} | {n} | {med:.4f} | {min(times):.4f} | {med / ref:.2f} |")


if __name__ == "__main__":
    main()
