//! What the smoother's internal numbering may change: [`sums_by_scatter`] names the
//! one configuration whose results follow it to rounding, [`max_difference`] measures
//! by how much.

use beltrami_halfedge::DVec3;
use beltrami_smooth::{SmoothConfig, Summation};

use crate::Deviation;
use beltrami_weights::WeightScheme;

/// The largest difference [`max_difference`] allows between two runs of a
/// [`sums_by_scatter`] configuration that differ only in the internal numbering, for
/// the unit-sized test meshes and a handful of iterations: a few units in the last place
/// of each coordinate, accumulated over the iterations.
pub const ROUNDING: f64 = 1e-12;

/// Whether `config` smooths with `scheme`'s rows recomputed every iteration and summed
/// element by element inside the sweep (`Summation::Scatter` where it applies): the
/// built-in cotangent scheme (registry name `cotangent`, negative weights kept) or
/// inverse-distance scheme (`distance`), weight-sum normalisation, weights updated
/// every iteration, plain explicit diffusion without volume preservation
/// (`SmoothConfig::scatter_unmet`). Such a run sums each row in the order of the
/// triangles or edges in the smoother's internal numbering, so reordering the vertices
/// (`Reorder`) changes its results in the last bits; every other configuration gives
/// the same bits either way.
#[must_use]
pub fn sums_by_scatter(scheme: &dyn WeightScheme, config: &SmoothConfig) -> bool {
    config.summation == Summation::Scatter && config.scatter_unmet(scheme).is_none()
}

/// The largest distance between corresponding points of two lists given as bit
/// patterns (`f64::to_bits` of x, y, z), as [`Deviation::between`] measures it;
/// infinite when the lists differ in length or a distance is not a number, 0 for
/// bit-identical lists.
#[must_use]
pub fn max_difference(a: &[[u64; 3]], b: &[[u64; 3]]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let points = |p: &[[u64; 3]]| -> Vec<DVec3> {
        p.iter()
            .map(|c| DVec3::from_array(c.map(f64::from_bits)))
            .collect()
    };
    let d = Deviation::between(&points(a), &points(b), 1.0);
    if d.identical {
        0.0
    } else if d.max.is_nan() {
        f64::INFINITY
    } else {
        d.max
    }
}
