"""trimesh.smoothing.filter_laplacian(lamb=0.8, iterations=100, volume_constraint=False).

trimesh builds a row-normalised sparse operator P once and iterates x += lamb (P x - x);
the operator is never updated, so both of its weightings are 'weights once':
* laplacian_calculation(equal_weight=True), the default: uniform weights over the
  directed face halfedges (on an open mesh a boundary vertex misses one neighbour);
* equal_weight=False: inverse distance 1/max(|d|, 1e-6) from the input positions.
The operator is built outside the timed call (its build time is recorded beside it);
the default volume_constraint=True would also rescale the mesh every iteration.
Also timed: the whole script (trimesh.load, the operator, the filter, export)."""
import time

import numpy as np
import trimesh
from trimesh.smoothing import filter_laplacian, laplacian_calculation

import harness as H


def main():
    print(f"trimesh {trimesh.__version__}", flush=True)
    for name in H.meshes_from_argv():
        V, F = H.load(name)
        closed = H.is_closed(F)
        for equal, scheme in ((True, "uniform"), (False, "distance")):
            t0 = time.perf_counter()
            op = laplacian_calculation(trimesh.Trimesh(V, F, process=False), equal_weight=equal)
            build = time.perf_counter() - t0
            times, ratio, out = H.repeat(
                lambda m: filter_laplacian(m, lamb=H.LAMBDA, iterations=H.ITERATIONS,
                                           volume_constraint=False, laplacian_operator=op),
                setup=lambda: trimesh.Trimesh(V.copy(), F, process=False))
            semantics = ("same as beltrami uniform (closed mesh)" if equal and closed else
                         "uniform, boundary vertices miss one neighbour" if equal else
                         "inverse distance, eps 1e-6 instead of 1e-12, weights once")
            H.whole_process(
                "trimesh", f"trimesh.load + filter_laplacian(lamb=0.8, equal_weight={equal}) + export",
                name, len(V), lambda path: trimesh.load(path, process=False),
                lambda m: filter_laplacian(
                    m, lamb=H.LAMBDA, iterations=H.ITERATIONS, volume_constraint=False,
                    laplacian_operator=laplacian_calculation(m, equal_weight=equal)),
                lambda m, path: m.export(path), scheme=scheme, weights="once")
            H.record("trimesh", f"filter_laplacian(lamb=0.8, equal_weight={equal}), operator prebuilt",
                     name, len(V), times, H.ITERATIONS, scheme=scheme, weights="once",
                     cpu_wall=ratio, check=H.agreement(out.vertices, name, scheme, "once", V, F),
                     semantics=semantics, extra=dict(setup_seconds=build))


if __name__ == "__main__":
    main()
