//! Errors of `beltrami-surfaces`.

use beltrami_halfedge::TopologyError;

/// Why a surface or noise could not be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SurfaceError {
    /// A surface name that is not built in.
    #[error("unknown surface {name:?} (known: flens, sphere, block, golfball)")]
    UnknownSurface {
        /// The name asked for.
        name: String,
    },
    /// A negative or non-finite noise level, or one that moves a position beyond the
    /// largest number.
    #[error(
        "the noise level must be finite, not negative and leave every position finite, got sigma = {sigma}"
    )]
    InvalidNoise {
        /// The σ in length units.
        sigma: f64,
    },
    /// Holes that cannot be cut as asked (a bad radius, or not enough room).
    #[error("{reason}")]
    InvalidHoles {
        /// What is wrong, in one sentence.
        reason: String,
    },
    /// The positions do not match the mesh.
    #[error(transparent)]
    Topology(#[from] TopologyError),
}
