//! What the smoother's internal numbering may change: [`sums_by_triangles`] names the
//! one configuration whose results follow it to rounding, [`max_difference`] measures
//! by how much.

use beltrami_smooth::{SmoothConfig, Summation};
use beltrami_weights::WeightScheme;

/// The largest difference [`max_difference`] allows between two runs of a
/// [`sums_by_triangles`] configuration that differ only in the internal numbering, for
/// the unit-sized test meshes and a handful of iterations: a few units in the last place
/// of each coordinate, accumulated over the iterations.
pub const ROUNDING: f64 = 1e-12;

/// Whether `config` smooths with `scheme`'s rows recomputed every iteration and summed
/// triangle by triangle inside the sweep (`Summation::Triangles` where it applies): the
/// built-in cotangent scheme (registry name `cotangent`), weight-sum normalisation,
/// negative weights kept, weights updated every iteration, plain explicit diffusion
/// without volume preservation (`SmoothConfig::triangle_summation_unmet`). Such a run
/// sums each row in the order of the triangles in the smoother's internal numbering, so
/// reordering the vertices (`Reorder`) changes its results in the last bits; every
/// other configuration gives the same bits either way.
#[must_use]
pub fn sums_by_triangles(scheme: &dyn WeightScheme, config: &SmoothConfig) -> bool {
    config.summation == Summation::Triangles && config.triangle_summation_unmet(scheme).is_none()
}

/// The largest coordinate difference between two lists of points given as bit patterns
/// (`f64::to_bits` of x, y, z); infinite when the lists differ in length or a pair
/// differs in a non-finite coordinate, 0 for bit-identical lists.
#[must_use]
pub fn max_difference(a: &[[u64; 3]], b: &[[u64; 3]]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let mut largest = 0.0_f64;
    for (p, q) in a.iter().zip(b) {
        for (&x, &y) in p.iter().zip(q) {
            if x == y {
                continue;
            }
            let d = (f64::from_bits(x) - f64::from_bits(y)).abs();
            largest = largest.max(if d.is_nan() { f64::INFINITY } else { d });
        }
    }
    largest
}
