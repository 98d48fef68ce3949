"""libigl (Python bindings): igl.cotmatrix gives L with L_ij = 1/2 (cot a + cot b) and
L_ii = -sum_j L_ij. The explicit step x += 0.8 (L x) / (-L_ii) is written here with
scipy, so the semantics are beltrami's cotangent scheme (free boundary):
* every: cotmatrix rebuilt from the current positions each iteration;
* once: built from the input, then row-scaled once and reused.
Also timed: the whole script (igl.read_triangle_mesh, the steps, igl.write_triangle_mesh)."""
from importlib.metadata import version

import numpy as np
import scipy.sparse as sp
import igl

import harness as H


def explicit(V, F, every):
    X = V.copy()
    if every:
        for _ in range(H.ITERATIONS):
            L = igl.cotmatrix(X, F)
            X += H.LAMBDA * (L @ X) / (-L.diagonal())[:, None]
        return X
    L = igl.cotmatrix(X, F).tocsr()
    P = sp.csr_matrix(sp.diags(-1.0 / L.diagonal()) @ L)
    for _ in range(H.ITERATIONS):
        X += H.LAMBDA * (P @ X)
    return X


def main():
    print(f"libigl {version('libigl')}", flush=True)
    for name in H.meshes_from_argv():
        V, F = H.load(name)
        for every, policy in ((True, "every"), (False, "once")):
            H.whole_process(
                "libigl", f"igl.read_triangle_mesh + cotmatrix {'every iteration' if every else 'once'}"
                " + scipy step + igl.write_triangle_mesh", name, len(V), igl.read_triangle_mesh,
                lambda vf: (explicit(vf[0].astype(np.float64), vf[1], every), vf[1]),
                lambda xf, path: igl.write_triangle_mesh(path, xf[0], xf[1]),
                scheme="cotangent", weights=policy)
            times, ratio, X = H.repeat(lambda _: explicit(V, F, every))
            H.record("libigl", f"igl.cotmatrix {'every iteration' if every else 'once'} + scipy step",
                     name, len(V), times, H.ITERATIONS, scheme="cotangent", weights=policy,
                     cpu_wall=ratio, check=H.agreement(X, name, "cotangent", policy, V, F),
                     semantics="same as beltrami cotangent (sparse matrix rebuilt per refresh)")


if __name__ == "__main__":
    main()
