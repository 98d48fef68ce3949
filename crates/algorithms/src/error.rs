//! Errors of `beltrami-algorithms`.

use beltrami_halfedge::TopologyError;

/// Why a mesh could not be subdivided. Every variant names the offending element or
/// count.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SubdivisionError {
    /// A face is not a triangle; both schemes subdivide triangle meshes only.
    #[error("face {face} has {len} vertices; subdivision needs a triangle mesh")]
    NotTriangle {
        /// The face index (0-based, in mesh order).
        face: usize,
        /// The number of vertices it has.
        len: usize,
    },
    /// The positions slice does not have one position per vertex.
    #[error("{positions} positions were given for a mesh of {vertices} vertices")]
    PositionCount {
        /// The length of the positions slice.
        positions: usize,
        /// The number of vertices of the mesh.
        vertices: usize,
    },
    /// The result would have more elements than a mesh can hold.
    #[error(
        "{steps} steps of {scheme} subdivision would make {count} {kind}; a mesh holds at most {max}"
    )]
    TooLarge {
        /// The scheme's name (`"loop"` or `"sqrt3"`).
        scheme: &'static str,
        /// The number of steps asked for.
        steps: usize,
        /// `"vertices"`, `"halfedges"` or `"faces"`.
        kind: &'static str,
        /// How many there would be (saturated at `u64::MAX`).
        count: u64,
        /// The largest supported count.
        max: usize,
    },
    /// The subdivided faces did not build into a mesh. Subdividing a valid mesh always
    /// gives a valid one, so this is a defect of this crate, reported rather than
    /// panicking.
    #[error("the subdivided mesh did not build: {0}")]
    Topology(#[from] TopologyError),
}

/// Why [`delaunay_flip`](crate::delaunay_flip) could not run. Every variant names the
/// offending element or value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DelaunayError {
    /// A face is not a triangle; flips need a triangle mesh.
    #[error("face {face} has {len} vertices; Delaunay flipping needs a triangle mesh")]
    NotTriangle {
        /// The face index (0-based, in mesh order).
        face: usize,
        /// The number of vertices it has.
        len: usize,
    },
    /// The positions slice does not have one position per vertex.
    #[error("{positions} positions were given for a mesh of {vertices} vertices")]
    PositionCount {
        /// The length of the positions slice.
        positions: usize,
        /// The number of vertices of the mesh.
        vertices: usize,
    },
    /// A position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite position")]
    NonFinite {
        /// The vertex index.
        vertex: usize,
    },
    /// An option is out of its range.
    #[error("invalid option: {reason}")]
    Options {
        /// The problem in words.
        reason: String,
    },
    /// A flip the checks allowed was refused, or the result did not convert back to a
    /// mesh: a defect of this crate, reported rather than panicking.
    #[error("the flipped mesh is not valid: {0}")]
    Edit(#[from] beltrami_halfedge::EditError),
    /// The input or the result did not convert between the frozen and the editable
    /// mesh.
    #[error("{0}")]
    Topology(#[from] TopologyError),
    /// Measuring the change of the surface failed (a defect: the positions are finite).
    #[error("measuring the deviation: {0}")]
    Metrics(#[from] beltrami_metrics::MetricsError),
}
