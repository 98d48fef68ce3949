//! Errors of `beltrami-metrics`.

use beltrami_halfedge::TopologyError;

/// Why a metric could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MetricsError {
    /// A mesh (or point set) without the elements the metric needs.
    #[error("the {what} is empty")]
    Empty {
        /// What is empty, e.g. `"reference mesh"`.
        what: &'static str,
    },
    /// Two meshes that must share their topology (same vertices and faces) do not.
    #[error("the meshes do not share their topology: {detail}")]
    TopologyMismatch {
        /// What differs, e.g. `"642 vertices vs 640"`.
        detail: String,
    },
    /// Too few points (or too little spread) to determine a fit.
    #[error("{shape} fit needs at least {needed} points in general position, got {got}")]
    TooFewPoints {
        /// `"sphere"`, `"circle"` or `"cylinder"`.
        shape: &'static str,
        /// The minimum.
        needed: usize,
        /// How many were given.
        got: usize,
    },
    /// The points are degenerate for this fit (collinear, coplanar where a sphere is asked…).
    #[error("{shape} fit is undetermined: {reason}")]
    Degenerate {
        /// The shape.
        shape: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// An iterative fit did not converge.
    #[error("{shape} fit did not converge in {iterations} iterations")]
    NoConvergence {
        /// The shape.
        shape: &'static str,
        /// Iterations done.
        iterations: usize,
    },
    /// A per-vertex field whose length does not match the mesh.
    #[error("{what} has {got} values for a mesh of {expected} vertices")]
    FieldLength {
        /// The field, e.g. `"residual"`.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The vertex count.
        expected: usize,
    },
    /// A non-finite input value.
    #[error("{what} {index} is not finite")]
    NonFinite {
        /// `"position"`, `"residual value"` …
        what: &'static str,
        /// Its index.
        index: usize,
    },
    /// A coordinate too large for the arithmetic of the metric (its squares or
    /// products would overflow): the mesh is in a unit far too small for its size.
    #[error(
        "{what} {index} has the coordinate {value:e}, beyond the {limit:e} this computation supports; express the mesh in a larger unit"
    )]
    CoordinateTooLarge {
        /// `"vertex"`, `"query point"`, ….
        what: &'static str,
        /// The index of the first offending point.
        index: usize,
        /// The offending coordinate.
        value: f64,
        /// The largest supported magnitude.
        limit: f64,
    },
    /// An invalid parameter (a zero plane normal, a negative threshold…).
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// A surface that folds back over its best-fit plane, where a height field over the
    /// plane is needed (a closed surface, or a strongly curved one).
    #[error(
        "the surface is not a height field over its mean plane: {folded_percent:.1} % of its projected area faces away from the plane"
    )]
    NotAHeightField {
        /// The share of the projected area that faces away from the plane's normal, in
        /// percent.
        folded_percent: f64,
    },
    /// A topological requirement failed (open mesh for a volume, positions count …).
    #[error(transparent)]
    Topology(#[from] TopologyError),
}
