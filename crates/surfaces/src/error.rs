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
    /// A negative or non-finite noise level.
    #[error("the noise level must be finite and not negative, got sigma = {sigma}")]
    InvalidNoise {
        /// The σ in length units.
        sigma: f64,
    },
    /// The positions do not match the mesh.
    #[error(transparent)]
    Topology(#[from] TopologyError),
}
