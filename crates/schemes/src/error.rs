//! Errors of `beltrami-schemes`.

use beltrami_halfedge::TopologyError;
use beltrami_metrics::MetricsError;
use beltrami_smooth::SmoothError;
use beltrami_weights::WeightError;

/// Why a scheme could not be built or a measurement could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SchemesError {
    /// A parameter outside its valid range.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// The parameter, e.g. `"sigma"`.
        name: &'static str,
        /// Why it is invalid, with the value given.
        reason: String,
    },
    /// The mesh has no vertex the flat-region measure can use (no vertex whose faces,
    /// and its neighbours' faces, are coplanar on the clean surface).
    #[error("the clean surface has no flat-region vertex to measure smoothness on")]
    NoFlatRegion,
    /// The mesh and a positions slice do not fit together.
    #[error(transparent)]
    Topology(#[from] TopologyError),
    /// A scheme could not be registered.
    #[error(transparent)]
    Weights(#[from] WeightError),
    /// Smoothing with the named scheme failed.
    #[error("smoothing with {scheme:?} failed: {source}")]
    Smooth {
        /// The scheme's name.
        scheme: String,
        /// What went wrong.
        source: SmoothError,
    },
    /// A metric could not be computed.
    #[error(transparent)]
    Metrics(#[from] MetricsError),
}
