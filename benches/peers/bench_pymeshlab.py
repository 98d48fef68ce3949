"""PyMeshLab apply_coord_laplacian_smoothing(stepsmoothnum=100, cotangentweight=...,
boundary=True) (MeshLab's vcg VertexCoordLaplacian). Only the filter call is timed.

MeshLab has no lambda: x <- (x + sum_e w_e x_j) / (1 + sum_e w_e), summed over face
edges, so an interior edge counts twice. Uniform: step 2n/(2n+1) (about 0.92).
Cotangent: w = cot a + cot b (twice the usual weight), recomputed every step in
float32, step W_i/(1+W_i). Boundary vertices are averaged with boundary neighbours.
Also timed: the whole script (load_new_mesh, the filter, save_current_mesh)."""
from importlib.metadata import version

import numpy as np
import pymeshlab

import harness as H


def main():
    print(f"pymeshlab {version('pymeshlab')}", flush=True)
    for name in H.meshes_from_argv():
        V, F = H.load(name)

        def setup():
            ms = pymeshlab.MeshSet()
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F.astype(np.int32)))
            return ms

        for cot, scheme in ((False, "uniform"), (True, "cotangent")):
            def run(ms):
                ms.apply_coord_laplacian_smoothing(stepsmoothnum=H.ITERATIONS, boundary=True,
                                                   cotangentweight=cot)
                return ms

            def read(path):
                ms = pymeshlab.MeshSet()
                ms.load_new_mesh(path)
                return ms

            H.whole_process(
                "pymeshlab", f"load_new_mesh + apply_coord_laplacian_smoothing({H.ITERATIONS}, "
                f"cotangentweight={cot}) + save_current_mesh", name, len(V), read, run,
                lambda ms, path: ms.save_current_mesh(path), scheme=scheme, weights="every")
            times, ratio, _ = H.repeat(run, setup=setup)
            H.record("pymeshlab", f"apply_coord_laplacian_smoothing({H.ITERATIONS}, cotangentweight={cot})",
                     name, len(V), times, H.ITERATIONS, scheme=scheme, weights="every",
                     cpu_wall=ratio,
                     semantics=("no lambda: step 2n/(2n+1)" if not cot else
                                "no lambda: weights 2x, step W/(1+W), float32 weights"))


if __name__ == "__main__":
    main()
