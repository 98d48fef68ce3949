"""Open3D TriangleMesh smoothing filters. Only the filter call is timed; the mesh and
its adjacency list (Open3D builds it on first use) are made before.

* filter_smooth_laplacian(n, lambda): inverse-distance weights 1/(|d| + 1e-12)
  recomputed every iteration, Jacobi, free boundary: beltrami's distance/every.
* filter_smooth_simple(n): x <- (x + sum_j x_j) / (n_i + 1), i.e. uniform weights
  with a per-vertex step n_i / (n_i + 1) (about 0.857), no lambda parameter.
The whole process of the first (read_triangle_mesh, the filter, write_triangle_mesh) is
timed as well, for the comparison with beltrami's whole process."""
import numpy as np
import open3d as o3d

import harness as H


def make(V, F):
    m = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(V),
                                  o3d.utility.Vector3iVector(F.astype(np.int32)))
    m.compute_adjacency_list()
    return m


def main():
    print(f"open3d {o3d.__version__}", flush=True)
    for name in H.meshes_from_argv():
        V, F = H.load(name)
        n = H.ITERATIONS
        times, ratio, out = H.repeat(
            lambda m: m.filter_smooth_laplacian(number_of_iterations=n, lambda_filter=H.LAMBDA),
            setup=lambda: make(V, F))
        H.record("open3d", f"filter_smooth_laplacian({n}, lambda_filter=0.8)", name, len(V), times, n,
                 scheme="distance", weights="every", cpu_wall=ratio, threads="all",
                 check=H.agreement(np.asarray(out.vertices), name, "distance", "every", V, F),
                 semantics="same as beltrami distance/every (eps 1e-12, free boundary)")
        H.whole_process(
            "open3d", f"read_triangle_mesh + filter_smooth_laplacian({n}) + write_triangle_mesh",
            name, len(V), o3d.io.read_triangle_mesh,
            lambda m: m.filter_smooth_laplacian(number_of_iterations=n, lambda_filter=H.LAMBDA),
            lambda m, path: o3d.io.write_triangle_mesh(path, m),
            scheme="distance", weights="every")
        times, ratio, out = H.repeat(
            lambda m: m.filter_smooth_simple(number_of_iterations=n), setup=lambda: make(V, F))
        H.record("open3d", f"filter_smooth_simple({n})", name, len(V), times, n,
                 scheme="uniform", weights="every", cpu_wall=ratio, threads="all",
                 semantics="uniform with step n_i/(n_i+1) instead of 0.8")


if __name__ == "__main__":
    main()
