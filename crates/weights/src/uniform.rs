//! Uniform (graph) weights.

use beltrami_halfedge::HalfedgeId;

use crate::scheme::{WeightContext, WeightScheme};

/// Uniform weights, `w_ij = 1`: with weight-sum normalisation the Laplacian moves a
/// vertex towards the plain average of its neighbours (the paper's Eq. 3, the "umbrella"
/// operator). Cheap and independent of the geometry, but it also moves vertices
/// tangentially on irregular meshes and shrinks the most.
#[derive(Clone, Copy, Debug, Default)]
pub struct Uniform;

impl WeightScheme for Uniform {
    fn name(&self) -> &str {
        "uniform"
    }

    fn description(&self) -> &str {
        "w_ij = 1 (graph Laplacian, paper Eq. 3)"
    }

    fn weight(&self, _ctx: &WeightContext<'_>, _h: HalfedgeId) -> f64 {
        1.0
    }

    fn fill_weights(&self, _ctx: &WeightContext<'_>, out: &mut [f64]) {
        out.fill(1.0);
    }

    fn depends_on_positions(&self) -> bool {
        false
    }

    fn curve_weight(&self, _ctx: &WeightContext<'_>, _h: HalfedgeId) -> f64 {
        1.0
    }
}
