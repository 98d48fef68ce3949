//! [`EditError`]: why an editing operation was refused.

use crate::ids::{EdgeId, FaceId, HalfedgeId, VertexId};

/// Why an operation on an [`EditMesh`](crate::EditMesh) was refused.
///
/// A refused operation leaves the mesh exactly as it was: every precondition is checked
/// before the first link is written. Each variant names the offending element by its
/// current id (ids change only in
/// [`garbage_collection`](crate::EditMesh::garbage_collection)).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EditError {
    /// A vertex id that is out of range or marked deleted.
    #[error("{vertex} does not exist (out of range or deleted)")]
    NoSuchVertex {
        /// The vertex.
        vertex: VertexId,
    },
    /// A halfedge id that is out of range or whose edge is marked deleted.
    #[error("{halfedge} does not exist (out of range or deleted)")]
    NoSuchHalfedge {
        /// The halfedge.
        halfedge: HalfedgeId,
    },
    /// An edge id that is out of range or marked deleted.
    #[error("{edge} does not exist (out of range or deleted)")]
    NoSuchEdge {
        /// The edge.
        edge: EdgeId,
    },
    /// A face id that is out of range or marked deleted.
    #[error("{face} does not exist (out of range or deleted)")]
    NoSuchFace {
        /// The face.
        face: FaceId,
    },
    /// A flip was asked of a boundary edge (a flip needs a triangle on each side).
    #[error("{edge} is a boundary edge; only an interior edge can be flipped")]
    FlipBoundaryEdge {
        /// The edge.
        edge: EdgeId,
    },
    /// Both triangles of the edge have the same opposite vertex, so the flipped edge
    /// would join a vertex to itself.
    #[error("both triangles of {edge} have {vertex} opposite; the flip would make a loop")]
    FlipSameOpposite {
        /// The edge.
        edge: EdgeId,
        /// The shared opposite vertex.
        vertex: VertexId,
    },
    /// The edge a flip would create is already in the mesh.
    #[error("flipping {edge} would duplicate the existing edge between {from} and {to}")]
    FlipEdgeExists {
        /// The edge asked to flip.
        edge: EdgeId,
        /// One end of the edge the flip would create.
        from: VertexId,
        /// The other end.
        to: VertexId,
    },
    /// An operation defined on triangles met a face with more vertices.
    #[error("{face} has {len} vertices; this operation needs triangles")]
    NotTriangle {
        /// The face.
        face: FaceId,
        /// Its number of vertices.
        len: usize,
    },
    /// A collapse would remove a triangle whose two other edges are boundary edges,
    /// leaving a dangling edge.
    #[error(
        "collapsing {halfedge} would leave a dangling edge: the triangle with {vertex} has both other edges on the boundary"
    )]
    CollapseDanglingTriangle {
        /// The halfedge asked to collapse.
        halfedge: HalfedgeId,
        /// The vertex opposite the halfedge in that triangle.
        vertex: VertexId,
    },
    /// Both triangles of the edge have the same opposite vertex.
    #[error("both triangles of {halfedge} have {vertex} opposite; the collapse would fold them")]
    CollapseSameOpposite {
        /// The halfedge asked to collapse.
        halfedge: HalfedgeId,
        /// The shared opposite vertex.
        vertex: VertexId,
    },
    /// The link condition fails: the two end points share a neighbour that is not
    /// opposite the edge, so the collapse would create a duplicate edge.
    #[error(
        "collapsing {halfedge} breaks the link condition: its end points share the neighbour {vertex}, which is not opposite the edge"
    )]
    CollapseLinkCondition {
        /// The halfedge asked to collapse.
        halfedge: HalfedgeId,
        /// The common neighbour.
        vertex: VertexId,
    },
    /// The end points are joined by more than one edge (possible after splits on a
    /// mesh that is not a simplicial complex, e.g. two triangles on the same three
    /// vertices); the collapse would turn the other edge into a loop.
    #[error(
        "the end points of {halfedge} are joined by more than one edge; the collapse would make a loop"
    )]
    CollapseDuplicateEdge {
        /// The halfedge asked to collapse.
        halfedge: HalfedgeId,
    },
    /// The edge lies on a boundary loop of three edges whose third vertex is also the
    /// vertex opposite the edge inside: the collapse would close the hole by merging
    /// two edges (possible only on meshes that join two vertices by more than one
    /// edge).
    #[error(
        "{halfedge} lies on a triangular hole; the collapse would close the hole by merging two edges"
    )]
    CollapseClosesHole {
        /// The halfedge asked to collapse.
        halfedge: HalfedgeId,
    },
    /// An interior edge joins two boundary vertices; collapsing it would pinch the
    /// surface into a non-manifold vertex.
    #[error(
        "{halfedge} is an interior edge between two boundary vertices; the collapse would pinch the surface"
    )]
    CollapseBoundaryPinch {
        /// The halfedge asked to collapse.
        halfedge: HalfedgeId,
    },
    /// A face needs at least three vertices.
    #[error("a face needs at least 3 vertices, {len} were given")]
    FaceTooSmall {
        /// The number of vertices given.
        len: usize,
    },
    /// A face lists a vertex more than once.
    #[error("the face lists {vertex} more than once")]
    RepeatedVertex {
        /// The repeated vertex.
        vertex: VertexId,
    },
    /// A new face would touch an interior vertex (one whose fan is closed): the vertex
    /// would become non-manifold.
    #[error("complex vertex: {vertex} is interior (its fan is closed), a new face cannot touch it")]
    ComplexVertex {
        /// The vertex.
        vertex: VertexId,
    },
    /// A new face would use an edge that already has a face on that side: either the
    /// edge would get a third face, or the new face is oriented against its neighbour.
    #[error(
        "complex edge: the halfedge from {from} to {to} already has a face (a third face on the edge, or the wrong orientation)"
    )]
    ComplexEdge {
        /// Start of the edge as the new face traverses it.
        from: VertexId,
        /// End of the edge.
        to: VertexId,
    },
    /// A new face joins two existing boundary edges at a vertex whose other faces leave
    /// no free gap to move them into.
    #[error(
        "the faces around {vertex} leave no boundary gap for the new face (patch re-linking fails)"
    )]
    NoBoundaryGap {
        /// The vertex where the two edges meet.
        vertex: VertexId,
    },
    /// A property of this name already exists on this kind of element.
    #[error("a {kind} property named {name:?} already exists")]
    PropertyExists {
        /// `"vertex"`, `"halfedge"`, `"edge"` or `"face"`.
        kind: &'static str,
        /// The name.
        name: String,
    },
}
