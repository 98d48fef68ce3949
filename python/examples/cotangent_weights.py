"""The built-in cotangent scheme, written again in numpy and registered by name.

Run with `python python/examples/cotangent_weights.py` after `pip install ./python`.
The Python scheme is called once per weight refresh with per-halfedge arrays for the
whole mesh; the smoothed positions agree with the Rust scheme's to 1e-12.
"""

import numpy as np

import beltrami as bt


def cotangent(h):
    """w_ij = (cot(alpha) + cot(beta)) / 2: the two angles opposite the edge i-j."""
    return 0.5 * (h["opposite_cotangent"] + h["opposite_cotangent"][h["twin"]])


bt.register_weight("numpy-cotangent", cotangent, description="cotangent weights in numpy")

noisy = bt.generate("sphere", level=4, noise=0.2, seed=1)
rust, _ = bt.smooth(noisy, weights="cotangent", iterations=20)
python, report = bt.smooth(noisy, weights="numpy-cotangent", iterations=20)

difference = np.abs(python.vertices - rust.vertices).max()
print(f"{report['iterations']} iterations, largest coordinate difference {difference:.3e}")
assert difference <= 1e-12, difference
