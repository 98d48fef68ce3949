//! Cotangent weights (the paper's Eq. 5).

use std::cell::RefCell;

use beltrami_halfedge::{FaceId, HalfedgeId};
use rayon::prelude::*;

use crate::scheme::{WeightContext, WeightKernel, WeightScheme};

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

/// Per-face cotangent triples of [`Cotangent::fill_weights`], reused between calls.
type FaceCotangents = Vec<Option<[(HalfedgeId, f64); 3]>>;

thread_local! {
    static FACE_COTANGENTS: RefCell<FaceCotangents> = const { RefCell::new(Vec::new()) };
}

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

    fn kernel(&self) -> Option<WeightKernel> {
        Some(WeightKernel::Cotangent)
    }

    fn fill_weights(&self, ctx: &WeightContext<'_>, out: &mut [f64]) {
        // One degeneracy test per triangle, then one sum per edge; the same bits as
        // `weight` for every halfedge.
        // Faces are independent: computed in parallel, written back in face order, so
        // the result does not depend on the thread count.
        out.fill(0.0);
        let geometry = ctx.geometry();
        let n_faces = ctx.mesh().n_faces();
        // The per-face buffer is kept between calls on the same thread, so that a run
        // that refreshes the weights every iteration does not allocate (and fault in)
        // tens of megabytes each time.
        FACE_COTANGENTS.with_borrow_mut(|cots| {
            (0..n_faces)
                .into_par_iter()
                .map(|f| geometry.face_opposite_cotangents(FaceId::new(f as u32)))
                .collect_into_vec(cots);
            for &(h, cot) in cots.iter().flatten().flatten() {
                out[h.index()] = cot;
            }
        });
        out.par_chunks_mut(crate::PAR_CHUNK).for_each(|chunk| {
            for pair in chunk.chunks_exact_mut(2) {
                let w = 0.5 * (pair[0] + pair[1]);
                pair[0] = w;
                pair[1] = w;
            }
        });
    }
}
