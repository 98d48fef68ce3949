//! Errors of `beltrami-weights`.

use beltrami_halfedge::TopologyError;

/// Why a scheme could not be found or a Laplacian could not be assembled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum WeightError {
    /// No registered scheme has this name.
    #[error("unknown weight scheme {name:?} (known: {known})")]
    UnknownScheme {
        /// The name asked for.
        name: String,
        /// The registered names, comma-separated.
        known: String,
    },
    /// A scheme with this name is already registered.
    #[error("a weight scheme named {name:?} is already registered")]
    DuplicateScheme {
        /// The name.
        name: String,
    },
    /// A scheme name that cannot be typed on a command line.
    #[error("invalid weight scheme name {name:?}: use lowercase letters, digits, '-' and '_'")]
    InvalidSchemeName {
        /// The name.
        name: String,
    },
    /// A scheme returned NaN or an infinity.
    #[error(
        "weight scheme {scheme:?} gave a non-finite weight ({value}) on the edge from vertex {from} to vertex {to}"
    )]
    NonFiniteWeight {
        /// The scheme's name.
        scheme: String,
        /// Start vertex of the halfedge.
        from: u32,
        /// End vertex of the halfedge.
        to: u32,
        /// The value it gave.
        value: f64,
    },
    /// The mesh and positions do not fit together, or the operation needs triangles.
    #[error(transparent)]
    Topology(#[from] TopologyError),
}
