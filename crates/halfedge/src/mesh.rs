//! The half-edge connectivity structure and its element accessors.

use crate::ids::{EdgeId, FaceId, HalfedgeId, IdRange, VertexId};
use crate::map::{EdgeMap, FaceMap, HalfedgeMap, VertexMap};

/// Marks an absent link in the internal arrays; never visible in the public API.
pub(crate) const INVALID: u32 = u32::MAX;

/// Half-edge connectivity of a polygon mesh: topology only, no positions.
///
/// Positions live beside the mesh as a `&[DVec3]` indexed by [`VertexId::index`], so a
/// smoother can double-buffer them and a weight can be evaluated on any positions
/// without cloning the connectivity. See `docs/conventions.md` for a diagram.
///
/// Conventions:
/// - edge `e` owns halfedges `2e` and `2e + 1`; the twin of `h` is `h ^ 1`
///   ([`HalfedgeId::twin`]);
/// - a halfedge points *to* [`to_vertex`](Self::to_vertex); inner halfedges run
///   counter-clockwise around their face (seen from the side the normal points to);
/// - a boundary halfedge has no face; boundary halfedges form the
///   [`boundary_loops`](Self::boundary_loops);
/// - a boundary vertex's [`outgoing_halfedge`](Self::outgoing_halfedge) is a boundary
///   halfedge, so [`is_boundary_vertex`](Self::is_boundary_vertex) is O(1);
/// - a face's [`face_halfedge`](Self::face_halfedge) is the halfedge that ends at the
///   face's first vertex as given to the builder, so
///   [`vertices_around_face`](Self::vertices_around_face) lists the vertices in input
///   order (as OpenMesh does).
///
/// A `HalfedgeMesh` is always valid: it is only built through validating constructors
/// such as [`from_polygons`](Self::from_polygons) and cannot be edited afterwards.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HalfedgeMesh {
    /// Outgoing halfedge per vertex, `INVALID` for isolated vertices.
    pub(crate) v_out: Vec<u32>,
    /// Target vertex per halfedge.
    pub(crate) h_to: Vec<u32>,
    pub(crate) h_next: Vec<u32>,
    pub(crate) h_prev: Vec<u32>,
    /// Face per halfedge, `INVALID` on the boundary.
    pub(crate) h_face: Vec<u32>,
    /// One halfedge per face.
    pub(crate) f_he: Vec<u32>,
}

/// The link `raw`, `None` when it is [`INVALID`].
#[inline]
pub(crate) fn opt(raw: u32) -> Option<u32> {
    (raw != INVALID).then_some(raw)
}

crate::circulators::navigation!(
    HalfedgeMesh,
    outgoing: "An outgoing halfedge of `v`, `None` for an isolated vertex. For a boundary vertex \
               it is the outgoing boundary halfedge; for an interior vertex, the halfedge leaving \
               it in its last face in input order (as in OpenMesh).",
    face_halfedge: "The halfedge of face `f` that ends at the face's first vertex."
);

impl HalfedgeMesh {
    /// The number of vertices, isolated ones included.
    #[must_use]
    pub fn n_vertices(&self) -> usize {
        self.v_out.len()
    }

    /// The number of halfedges (twice the number of edges).
    #[must_use]
    pub fn n_halfedges(&self) -> usize {
        self.h_to.len()
    }

    /// The number of edges.
    #[must_use]
    pub fn n_edges(&self) -> usize {
        self.h_to.len() / 2
    }

    /// The number of faces.
    #[must_use]
    pub fn n_faces(&self) -> usize {
        self.f_he.len()
    }

    /// The number of isolated vertices (in no edge, so in no face).
    ///
    /// # Complexity
    /// O(V).
    #[must_use]
    pub fn n_isolated_vertices(&self) -> usize {
        self.v_out.iter().filter(|&&h| h == INVALID).count()
    }

    /// All vertex handles in index order.
    pub fn vertices(&self) -> IdRange<VertexId> {
        IdRange::new(self.n_vertices())
    }

    /// All halfedge handles in index order.
    pub fn halfedges(&self) -> IdRange<HalfedgeId> {
        IdRange::new(self.n_halfedges())
    }

    /// All edge handles in index order.
    pub fn edges(&self) -> IdRange<EdgeId> {
        IdRange::new(self.n_edges())
    }

    /// All face handles in index order.
    pub fn faces(&self) -> IdRange<FaceId> {
        IdRange::new(self.n_faces())
    }

    /// Whether face `f` has at least one boundary edge.
    #[must_use]
    pub fn is_boundary_face(&self, f: FaceId) -> bool {
        self.halfedges_around_face(f)
            .any(|h| self.is_boundary_halfedge(h.twin()))
    }

    /// Whether the mesh has no boundary halfedge (every edge has two faces). Isolated
    /// vertices do not make a mesh open. An empty mesh is closed.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.h_face.iter().all(|&f| f != INVALID)
    }

    /// Whether every face is a triangle.
    #[must_use]
    pub fn is_triangle_mesh(&self) -> bool {
        self.n_halfedges() - self.n_boundary_halfedges() == 3 * self.n_faces()
    }

    /// The number of boundary halfedges.
    #[must_use]
    pub fn n_boundary_halfedges(&self) -> usize {
        self.h_face.iter().filter(|&&f| f == INVALID).count()
    }

    /// The vertices of triangle `f` in input order, `[v0, v1, v2]`.
    ///
    /// # Panics
    /// In debug builds, if `f` is not a triangle.
    #[inline]
    #[must_use]
    pub fn triangle_vertices(&self, f: FaceId) -> [VertexId; 3] {
        let h0 = self.face_halfedge(f);
        let h1 = self.next(h0);
        let h2 = self.next(h1);
        debug_assert_eq!(self.next(h2), h0, "face {f:?} is not a triangle");
        [self.to_vertex(h0), self.to_vertex(h1), self.to_vertex(h2)]
    }

    /// The Euler characteristic `V − E + F` (isolated vertices included).
    #[must_use]
    pub fn euler_characteristic(&self) -> i64 {
        self.n_vertices() as i64 - self.n_edges() as i64 + self.n_faces() as i64
    }

    /// A per-vertex map filled with `value`.
    #[must_use]
    pub fn vertex_map<T: Clone>(&self, value: T) -> VertexMap<T> {
        VertexMap::filled(self.n_vertices(), value)
    }

    /// A per-halfedge map filled with `value`.
    #[must_use]
    pub fn halfedge_map<T: Clone>(&self, value: T) -> HalfedgeMap<T> {
        HalfedgeMap::filled(self.n_halfedges(), value)
    }

    /// A per-edge map filled with `value`.
    #[must_use]
    pub fn edge_map<T: Clone>(&self, value: T) -> EdgeMap<T> {
        EdgeMap::filled(self.n_edges(), value)
    }

    /// A per-face map filled with `value`.
    #[must_use]
    pub fn face_map<T: Clone>(&self, value: T) -> FaceMap<T> {
        FaceMap::filled(self.n_faces(), value)
    }

    /// The faces as vertex-index lists in input order (the inverse of
    /// [`from_polygons`](Self::from_polygons)).
    #[must_use]
    pub fn to_polygons(&self) -> crate::PolygonList {
        let mut list = crate::PolygonList::with_capacity(
            self.n_faces(),
            self.n_halfedges() - self.n_boundary_halfedges(),
        );
        let mut buf = Vec::new();
        for f in self.faces() {
            buf.clear();
            buf.extend(self.vertices_around_face(f).map(VertexId::raw));
            list.push(&buf);
        }
        list
    }
}
