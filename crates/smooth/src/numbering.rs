//! The internal vertex numbering of a reordered run and the way back to the caller's.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::reorder::VertexPermutation;
use rayon::prelude::*;

use crate::error::SmoothError;

/// Vertices per parallel work unit. Fixed, so that per-chunk partial sums (and hence
/// the reported statistics) do not depend on the number of threads.
pub(crate) const CHUNK: usize = 4096;

/// `internal` back in the caller's numbering, into `out`, gathered in parallel.
pub(crate) fn restore_par(perm: &VertexPermutation, internal: &[DVec3], out: &mut [DVec3]) {
    out.par_chunks_mut(CHUNK)
        .zip(perm.old_to_new().par_chunks(CHUNK))
        .for_each(|(out, ids)| {
            for (x, &i) in out.iter_mut().zip(ids) {
                *x = internal[i as usize];
            }
        });
}

/// `positions` in the internal numbering of `perm`, gathered in parallel.
pub(crate) fn permute_par(perm: &VertexPermutation, positions: &[DVec3]) -> Vec<DVec3> {
    perm.new_to_old()
        .par_iter()
        .map(|&o| positions[o as usize])
        .collect()
}

/// `e` with the vertex indices of the internal numbering `perm` mapped back to the
/// caller's.
pub(crate) fn error_to_caller(e: SmoothError, perm: &VertexPermutation) -> SmoothError {
    let old = |v: u32| perm.new_to_old()[v as usize];
    match e {
        SmoothError::Weights(beltrami_weights::WeightError::NonFiniteWeight {
            scheme,
            from,
            to,
            value,
        }) => SmoothError::Weights(beltrami_weights::WeightError::NonFiniteWeight {
            scheme,
            from: old(from),
            to: old(to),
            value,
        }),
        e => e,
    }
}
