//! Cotangent weights (the paper's Eq. 5).

use beltrami_halfedge::HalfedgeId;
use rayon::prelude::*;

use crate::scheme::{WeightContext, WeightScheme};

/// Cotangent weights, `w_ij = ½ (cot α_ij + cot β_ij)`, with α and β the angles opposite
/// edge ij in its two triangles (one term on a boundary edge). Each cotangent is
/// `(u·v)/|u×v|` at the opposite corner; a degenerate triangle contributes 0 (see
/// [`WeightContext::opposite_cotangent`]). Symmetric; negative when α + β > π — the
/// Laplacian's [`NegativeWeights`](crate::NegativeWeights) policy decides what happens
/// then.
///
/// With area normalisation this is the discretisation of Pinkall & Polthier (1993) and
/// Meyer et al. (2003): `1/(2A_i) Σ (cot α + cot β)(x_j − x_i)` approximates the mean
/// curvature normal `−2H n`.
///
/// # References
/// - U. Pinkall, K. Polthier, "Computing discrete minimal surfaces and their conjugates",
///   Experimental Mathematics 2(1), 1993.
/// - M. Meyer, M. Desbrun, P. Schröder, A. Barr, "Discrete differential-geometry
///   operators for triangulated 2-manifolds", VisMath 2002 (2003).
#[derive(Clone, Copy, Debug, Default)]
pub struct Cotangent;

impl WeightScheme for Cotangent {
    fn name(&self) -> &str {
        "cotangent"
    }

    fn description(&self) -> &str {
        "w_ij = (cot a_ij + cot b_ij) / 2 (paper Eq. 5)"
    }

    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        0.5 * (ctx.opposite_cotangent(h) + ctx.opposite_cotangent(h.twin()))
    }

    fn fill_weights(&self, ctx: &WeightContext<'_>, out: &mut [f64]) {
        // One weight per edge, written to both halfedges (the sum is symmetric, so the
        // bits are `weight`'s for both); edges in parallel, fixed chunks. The operator
        // computes cotangents once per triangle instead (a built-in kernel).
        out.par_chunks_mut(crate::PAR_CHUNK)
            .enumerate()
            .for_each(|(c, chunk)| {
                for (k, pair) in chunk.chunks_exact_mut(2).enumerate() {
                    let h = HalfedgeId::new((c * crate::PAR_CHUNK + 2 * k) as u32);
                    let w = self.weight(ctx, h);
                    pair[0] = w;
                    pair[1] = w;
                }
            });
    }
}
