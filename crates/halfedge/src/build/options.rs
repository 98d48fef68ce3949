//! What the builder may repair ([`BuildOptions`]) and what it did ([`BuildReport`]).

use crate::ids::VertexId;

/// Opt-in repairs applied while building. All are off by default: without them every
/// problem is an error. Each repair that acts is recorded in the [`BuildReport`].
///
/// # Examples
/// ```
/// use beltrami_halfedge::{BuildOptions, HalfedgeMesh};
/// // Face 1 is wound the other way round.
/// let faces = [[0u32, 1, 2], [0, 1, 3]];
/// assert!(HalfedgeMesh::from_polygons(4, &faces).is_err());
/// let (mesh, report) =
///     HalfedgeMesh::build(4, &faces, &BuildOptions::new().reorient(true)).unwrap();
/// assert_eq!(report.flipped_faces, [1]);
/// assert_eq!(mesh.n_faces(), 2);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildOptions {
    drop_degenerate_faces: bool,
    reorient: bool,
    split_nonmanifold_vertices: bool,
}

impl BuildOptions {
    /// No repairs: every problem is an error.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Every repair enabled.
    #[must_use]
    pub fn repair_all() -> Self {
        Self {
            drop_degenerate_faces: true,
            reorient: true,
            split_nonmanifold_vertices: true,
        }
    }

    /// Drop faces with fewer than three vertices or with a repeated vertex instead of
    /// failing. Out-of-range indices are still an error (the file is broken, not
    /// degenerate).
    #[must_use]
    pub fn drop_degenerate_faces(mut self, yes: bool) -> Self {
        self.drop_degenerate_faces = yes;
        self
    }

    /// Re-orient faces so that each connected component is consistently oriented. The
    /// lowest-numbered face of a component keeps its orientation; a flipped face keeps
    /// its first vertex and reverses the rest. Fails with
    /// [`TopologyError::NonOrientable`](crate::TopologyError::NonOrientable) when no consistent orientation exists.
    #[must_use]
    pub fn reorient(mut self, yes: bool) -> Self {
        self.reorient = yes;
        self
    }

    /// Give every extra fan of faces around a pinched vertex its own copy of the vertex.
    /// New vertices are numbered after the input vertices; the caller appends their
    /// positions (copies of the originals) in the order of
    /// [`BuildReport::split_vertices`].
    #[must_use]
    pub fn split_nonmanifold_vertices(mut self, yes: bool) -> Self {
        self.split_nonmanifold_vertices = yes;
        self
    }

    /// Whether degenerate faces are dropped.
    #[must_use]
    pub fn drops_degenerate_faces(&self) -> bool {
        self.drop_degenerate_faces
    }

    /// Whether faces are re-oriented.
    #[must_use]
    pub fn reorients(&self) -> bool {
        self.reorient
    }

    /// Whether non-manifold vertices are split.
    #[must_use]
    pub fn splits_nonmanifold_vertices(&self) -> bool {
        self.split_nonmanifold_vertices
    }
}

/// A vertex added by splitting a non-manifold vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexSplit {
    /// The new vertex (numbered after all input vertices).
    pub vertex: VertexId,
    /// The input vertex it copies.
    pub original: VertexId,
}

/// What the opt-in repairs of [`HalfedgeMesh::build`](crate::HalfedgeMesh::build) changed. Empty when the input
/// needed no repair.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct BuildReport {
    /// Input indices of faces dropped as degenerate, ascending.
    pub dropped_faces: Vec<usize>,
    /// Input indices of faces whose orientation was reversed, ascending.
    pub flipped_faces: Vec<usize>,
    /// Vertices added by splitting non-manifold vertices, in the order of their ids.
    pub split_vertices: Vec<VertexSplit>,
    /// For each face of the built mesh, its input index. Empty when no face was dropped
    /// (then face `f` is input face `f`).
    pub face_origin: Vec<usize>,
}

impl BuildReport {
    /// Whether no repair acted.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.dropped_faces.is_empty()
            && self.flipped_faces.is_empty()
            && self.split_vertices.is_empty()
    }
}
