//! Errors of `beltrami-smooth`.

use beltrami_weights::WeightError;

/// Why a smoothing run could not start or had to stop.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SmoothError {
    /// λ outside its valid range.
    #[error("lambda must be {range}, got {lambda}")]
    InvalidLambda {
        /// The value given.
        lambda: f64,
        /// The valid range in words.
        range: &'static str,
    },
    /// A boundary mode that does not combine with the normalisation.
    #[error("boundary mode 'curve' needs weight-sum normalisation")]
    CurveNeedsWeightSum,
    /// A pinned vertex that does not exist.
    #[error("pinned vertex {vertex} does not exist (the mesh has {n_vertices} vertices)")]
    PinnedOutOfRange {
        /// The vertex.
        vertex: u32,
        /// The number of vertices.
        n_vertices: usize,
    },
    /// An input position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite input position")]
    NonFiniteInput {
        /// The vertex.
        vertex: u32,
    },
    /// A position became NaN or infinite (the step is too large for the operator).
    #[error(
        "vertex {vertex} became non-finite in iteration {iteration}; the step is too large for this operator"
    )]
    NonFinite {
        /// The vertex.
        vertex: u32,
        /// The iteration (1-based).
        iteration: usize,
    },
    /// The weights could not be computed.
    #[error(transparent)]
    Weights(#[from] WeightError),
}
