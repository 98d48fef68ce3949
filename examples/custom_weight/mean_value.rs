//! Mean-value weights (Floater 2003), a scheme that beltrami does not build in.

use beltrami::halfedge::HalfedgeId;
use beltrami::weights::{DISTANCE_EPSILON, WeightContext, WeightScheme};

/// Mean-value weights: `w_ij = (tan(α/2) + tan(β/2)) / |x_j − x_i|`, with α and β the
/// angles at vertex i on either side of edge ij (0 on the boundary side). Always
/// positive for a valid triangulation, unlike cotangent weights.
///
/// Reference: M. S. Floater, "Mean value coordinates", CAGD 20(1), 2003.
pub(crate) struct MeanValue;

impl WeightScheme for MeanValue {
    fn name(&self) -> &str {
        "mean-value"
    }

    fn description(&self) -> &str {
        "w_ij = (tan(a/2) + tan(b/2)) / |x_j - x_i| (Floater 2003)"
    }

    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let (mesh, geometry) = (ctx.mesh(), ctx.geometry());
        // The corner at i in the face of h ends prev(h); in the face of the twin, the
        // twin itself ends at i. A boundary side has no face and contributes 0.
        let alpha = geometry.corner_angle(mesh.prev(h));
        let beta = geometry.corner_angle(h.twin());
        ((alpha / 2.0).tan() + (beta / 2.0).tan())
            / (ctx.edge_vector(h).length() + DISTANCE_EPSILON)
    }
}
