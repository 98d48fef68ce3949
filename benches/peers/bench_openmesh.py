"""OpenMesh 9 JacobiLaplaceSmootherT (C++, built by run.sh from openmesh_smooth.cpp):
uniform weights and cotangent weights computed once, step fixed at 0.5, boundary
fixed, one thread. smooth(100) is timed; initialize() (the weights) is recorded beside
it. Its output is checked against beltrami run with the same setting (lambda 0.5,
--update once, --boundary fixed). The C++ program also times the whole program a user
would write (read, smooth, write a binary PLY), recorded as kind "whole"."""
import json
import os
import subprocess

import numpy as np

import harness as H

BIN = os.path.join(H.OUT, "bin", "openmesh_smooth")


def main():
    for name in H.meshes_from_argv():
        V, F = H.load(name)
        prefix = os.path.join(H.OUT, "openmesh", name)
        os.makedirs(os.path.dirname(prefix), exist_ok=True)
        out = subprocess.run([BIN, H.mesh_path(name), str(H.ITERATIONS), str(H.REPS), prefix],
                             check=True, capture_output=True, text=True).stdout
        for line in out.splitlines():
            r = json.loads(line)
            if r["vertices"] != len(V):
                raise SystemExit(f"error: OpenMesh read {r['vertices']} vertices of {name}, expected {len(V)}")
            X = np.fromfile(f"{prefix}_{r['scheme']}.xyz", dtype="<f8").reshape(-1, 3)
            med = int(np.argsort(r["smooth"])[(len(r["smooth"]) - 1) // 2])
            H.record("openmesh", f"JacobiLaplaceSmootherT C0 smooth({H.ITERATIONS})", name, len(V),
                     r["smooth"], H.ITERATIONS, scheme=r["scheme"], weights="once",
                     cpu_wall=r["cpu_wall"][med],
                     check=H.agreement(X, name, r["scheme"], "once", V, F, variant="_om"),
                     semantics="step 0.5 (fixed), fixed boundary",
                     extra=dict(setup_seconds=float(np.median(r["initialize"]))))
            H.record("openmesh", f"read_mesh + JacobiLaplaceSmootherT C0 smooth({H.ITERATIONS}) + write_mesh",
                     name, len(V), r["whole"], H.ITERATIONS, scheme=r["scheme"], weights="once",
                     kind="whole", semantics="step 0.5 (fixed), fixed boundary")


if __name__ == "__main__":
    main()
