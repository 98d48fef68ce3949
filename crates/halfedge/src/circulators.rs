//! Navigation shared by [`HalfedgeMesh`] and [`EditMesh`](crate::EditMesh): the link
//! accessors, the status queries that follow from them, and the circulators — named
//! iterators around a vertex or a face, counter-clockwise.
//!
//! Both meshes store the same half-edge arrays, so the accessors are written once, in
//! the `navigation!` macro, and expanded as inherent methods of each mesh; the
//! circulators are generic over the mesh they walk ([`Links`]), the immutable mesh
//! being the default.
//!
//! Around a vertex, "counter-clockwise" is seen from the side the face normals point
//! to; the step is [`HalfedgeMesh::ccw_rotated`]. Each circulator starts at the
//! vertex's [`outgoing_halfedge`](HalfedgeMesh::outgoing_halfedge) — at a boundary
//! vertex, the outgoing boundary halfedge, so the first neighbour is the one across
//! the boundary edge that leaves the vertex and the fan is then visited in order.

use std::iter::FusedIterator;

use crate::ids::{FaceId, HalfedgeId, VertexId};
use crate::mesh::HalfedgeMesh;

/// The links a circulator follows: implemented by [`HalfedgeMesh`] and
/// [`EditMesh`](crate::EditMesh), with their inherent accessors of the same names.
pub trait Links {
    /// The vertex `h` points to.
    fn to_vertex(&self, h: HalfedgeId) -> VertexId;
    /// The next halfedge along the face (or boundary loop) of `h`.
    fn next(&self, h: HalfedgeId) -> HalfedgeId;
    /// The outgoing halfedge after `h` counter-clockwise around its start vertex.
    fn ccw_rotated(&self, h: HalfedgeId) -> HalfedgeId;
    /// The face `h` belongs to, `None` for a boundary halfedge.
    fn face(&self, h: HalfedgeId) -> Option<FaceId>;
}

/// Outgoing halfedges of a vertex, counter-clockwise. See
/// [`HalfedgeMesh::halfedges_around_vertex`].
#[derive(Clone, Debug)]
pub struct HalfedgesAroundVertex<'a, M = HalfedgeMesh> {
    mesh: &'a M,
    start: Option<HalfedgeId>,
    current: Option<HalfedgeId>,
}

impl<'a, M> HalfedgesAroundVertex<'a, M> {
    /// The circulator from `start` (`None`: an isolated vertex, nothing to visit).
    #[inline]
    pub(crate) fn new(mesh: &'a M, start: Option<HalfedgeId>) -> Self {
        Self {
            mesh,
            start,
            current: start,
        }
    }
}

impl<M: Links> Iterator for HalfedgesAroundVertex<'_, M> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        let n = self.mesh.ccw_rotated(h);
        self.current = (Some(n) != self.start).then_some(n);
        Some(h)
    }
}
impl<M: Links> FusedIterator for HalfedgesAroundVertex<'_, M> {}

/// Neighbouring vertices of a vertex (its one-ring), counter-clockwise. See
/// [`HalfedgeMesh::vertices_around_vertex`].
#[derive(Clone, Debug)]
pub struct VerticesAroundVertex<'a, M = HalfedgeMesh> {
    inner: HalfedgesAroundVertex<'a, M>,
}

impl<'a, M> VerticesAroundVertex<'a, M> {
    #[inline]
    pub(crate) fn new(inner: HalfedgesAroundVertex<'a, M>) -> Self {
        Self { inner }
    }
}

impl<M: Links> Iterator for VerticesAroundVertex<'_, M> {
    type Item = VertexId;
    #[inline]
    fn next(&mut self) -> Option<VertexId> {
        self.inner.next().map(|h| self.inner.mesh.to_vertex(h))
    }
}
impl<M: Links> FusedIterator for VerticesAroundVertex<'_, M> {}

/// Faces incident to a vertex, counter-clockwise. See
/// [`HalfedgeMesh::faces_around_vertex`].
#[derive(Clone, Debug)]
pub struct FacesAroundVertex<'a, M = HalfedgeMesh> {
    inner: HalfedgesAroundVertex<'a, M>,
}

impl<'a, M> FacesAroundVertex<'a, M> {
    #[inline]
    pub(crate) fn new(inner: HalfedgesAroundVertex<'a, M>) -> Self {
        Self { inner }
    }
}

impl<M: Links> Iterator for FacesAroundVertex<'_, M> {
    type Item = FaceId;
    #[inline]
    fn next(&mut self) -> Option<FaceId> {
        loop {
            let h = self.inner.next()?;
            if let Some(f) = self.inner.mesh.face(h) {
                return Some(f);
            }
        }
    }
}
impl<M: Links> FusedIterator for FacesAroundVertex<'_, M> {}

/// Halfedges of a face (or of a boundary loop), following `next`. See
/// [`HalfedgeMesh::halfedges_around_face`].
#[derive(Clone, Debug)]
pub struct HalfedgesAroundFace<'a, M = HalfedgeMesh> {
    mesh: &'a M,
    start: HalfedgeId,
    current: Option<HalfedgeId>,
}

impl<'a, M> HalfedgesAroundFace<'a, M> {
    /// The circulator of the cycle through `start`, from `start`.
    #[inline]
    pub(crate) fn new(mesh: &'a M, start: HalfedgeId) -> Self {
        Self {
            mesh,
            start,
            current: Some(start),
        }
    }
}

impl<M: Links> Iterator for HalfedgesAroundFace<'_, M> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        let n = self.mesh.next(h);
        self.current = (n != self.start).then_some(n);
        Some(h)
    }
}
impl<M: Links> FusedIterator for HalfedgesAroundFace<'_, M> {}

/// Vertices of a face in input order. See [`HalfedgeMesh::vertices_around_face`].
#[derive(Clone, Debug)]
pub struct VerticesAroundFace<'a, M = HalfedgeMesh> {
    inner: HalfedgesAroundFace<'a, M>,
}

impl<'a, M> VerticesAroundFace<'a, M> {
    #[inline]
    pub(crate) fn new(inner: HalfedgesAroundFace<'a, M>) -> Self {
        Self { inner }
    }
}

impl<M: Links> Iterator for VerticesAroundFace<'_, M> {
    type Item = VertexId;
    #[inline]
    fn next(&mut self) -> Option<VertexId> {
        self.inner.next().map(|h| self.inner.mesh.to_vertex(h))
    }
}
impl<M: Links> FusedIterator for VerticesAroundFace<'_, M> {}

/// Faces that share an edge with a face, in the order of the face's halfedges. See
/// [`HalfedgeMesh::faces_around_face`].
#[derive(Clone, Debug)]
pub struct FacesAroundFace<'a, M = HalfedgeMesh> {
    inner: HalfedgesAroundFace<'a, M>,
}

impl<'a, M> FacesAroundFace<'a, M> {
    #[inline]
    pub(crate) fn new(inner: HalfedgesAroundFace<'a, M>) -> Self {
        Self { inner }
    }
}

impl<M: Links> Iterator for FacesAroundFace<'_, M> {
    type Item = FaceId;
    #[inline]
    fn next(&mut self) -> Option<FaceId> {
        loop {
            let h = self.inner.next()?;
            if let Some(f) = self.inner.mesh.face(h.twin()) {
                return Some(f);
            }
        }
    }
}
impl<M: Links> FusedIterator for FacesAroundFace<'_, M> {}

/// Expands the navigation of a half-edge mesh as inherent methods of `$mesh` (a type
/// with the half-edge arrays `v_out`, `h_to`, `h_next`, `h_prev`, `h_face`, `f_he` of
/// [`HalfedgeMesh`], absent links stored as [`INVALID`](crate::mesh::INVALID)) and
/// implements [`Links`] for it. `$outgoing` and `$face_halfedge` document which
/// halfedge [`outgoing_halfedge`](HalfedgeMesh::outgoing_halfedge) and
/// [`face_halfedge`](HalfedgeMesh::face_halfedge) return, which differs between the
/// meshes.
macro_rules! navigation {
    ($mesh:ident, outgoing: $outgoing:literal, face_halfedge: $face_halfedge:literal) => {
        impl $crate::circulators::Links for $mesh {
            #[inline]
            fn to_vertex(&self, h: $crate::HalfedgeId) -> $crate::VertexId {
                $mesh::to_vertex(self, h)
            }
            #[inline]
            fn next(&self, h: $crate::HalfedgeId) -> $crate::HalfedgeId {
                $mesh::next(self, h)
            }
            #[inline]
            fn ccw_rotated(&self, h: $crate::HalfedgeId) -> $crate::HalfedgeId {
                $mesh::ccw_rotated(self, h)
            }
            #[inline]
            fn face(&self, h: $crate::HalfedgeId) -> Option<$crate::FaceId> {
                $mesh::face(self, h)
            }
        }

        impl $mesh {
            /// The vertex `h` points to.
            #[inline]
            #[must_use]
            pub fn to_vertex(&self, h: $crate::HalfedgeId) -> $crate::VertexId {
                $crate::VertexId::new(self.h_to[h.index()])
            }

            /// The vertex `h` starts from (the target of its twin).
            #[inline]
            #[must_use]
            pub fn from_vertex(&self, h: $crate::HalfedgeId) -> $crate::VertexId {
                $crate::VertexId::new(self.h_to[h.twin().index()])
            }

            /// The next halfedge along the face (or boundary loop) of `h`.
            #[inline]
            #[must_use]
            pub fn next(&self, h: $crate::HalfedgeId) -> $crate::HalfedgeId {
                $crate::HalfedgeId::new(self.h_next[h.index()])
            }

            /// The previous halfedge along the face (or boundary loop) of `h`.
            #[inline]
            #[must_use]
            pub fn prev(&self, h: $crate::HalfedgeId) -> $crate::HalfedgeId {
                $crate::HalfedgeId::new(self.h_prev[h.index()])
            }

            /// The face `h` belongs to, `None` for a boundary halfedge.
            #[inline]
            #[must_use]
            pub fn face(&self, h: $crate::HalfedgeId) -> Option<$crate::FaceId> {
                $crate::mesh::opt(self.h_face[h.index()]).map($crate::FaceId::new)
            }

            #[doc = $outgoing]
            #[inline]
            #[must_use]
            pub fn outgoing_halfedge(&self, v: $crate::VertexId) -> Option<$crate::HalfedgeId> {
                $crate::mesh::opt(self.v_out[v.index()]).map($crate::HalfedgeId::new)
            }

            #[doc = $face_halfedge]
            #[inline]
            #[must_use]
            pub fn face_halfedge(&self, f: $crate::FaceId) -> $crate::HalfedgeId {
                $crate::HalfedgeId::new(self.f_he[f.index()])
            }

            /// Rotates an outgoing halfedge counter-clockwise around its start vertex:
            /// `twin(prev(h))`.
            #[inline]
            #[must_use]
            pub fn ccw_rotated(&self, h: $crate::HalfedgeId) -> $crate::HalfedgeId {
                self.prev(h).twin()
            }

            /// Rotates an outgoing halfedge clockwise around its start vertex:
            /// `next(twin(h))`.
            #[inline]
            #[must_use]
            pub fn cw_rotated(&self, h: $crate::HalfedgeId) -> $crate::HalfedgeId {
                self.next(h.twin())
            }

            /// The two vertices of an edge, `[from, to]` of its halfedge `2e`.
            #[inline]
            #[must_use]
            pub fn edge_vertices(&self, e: $crate::EdgeId) -> [$crate::VertexId; 2] {
                let [h, t] = e.halfedges();
                [self.to_vertex(t), self.to_vertex(h)]
            }

            /// Whether `h` is a boundary halfedge (has no face).
            #[inline]
            #[must_use]
            pub fn is_boundary_halfedge(&self, h: $crate::HalfedgeId) -> bool {
                self.h_face[h.index()] == $crate::mesh::INVALID
            }

            /// Whether either halfedge of `e` is a boundary halfedge.
            #[inline]
            #[must_use]
            pub fn is_boundary_edge(&self, e: $crate::EdgeId) -> bool {
                let [a, b] = e.halfedges();
                self.is_boundary_halfedge(a) || self.is_boundary_halfedge(b)
            }

            /// Whether `v` lies on the boundary. O(1). An isolated vertex counts as
            /// boundary (it has no closed fan around it), as in OpenMesh.
            #[inline]
            #[must_use]
            pub fn is_boundary_vertex(&self, v: $crate::VertexId) -> bool {
                match self.outgoing_halfedge(v) {
                    None => true,
                    Some(h) => self.is_boundary_halfedge(h),
                }
            }

            /// Whether `v` has no incident edge.
            #[inline]
            #[must_use]
            pub fn is_isolated(&self, v: $crate::VertexId) -> bool {
                self.v_out[v.index()] == $crate::mesh::INVALID
            }

            /// The number of edges at `v` (its vertex degree). 0 for an isolated vertex.
            ///
            /// # Complexity
            /// O(valence).
            #[must_use]
            pub fn valence(&self, v: $crate::VertexId) -> usize {
                self.halfedges_around_vertex(v).count()
            }

            /// The number of vertices (= edges) of face `f`.
            #[must_use]
            pub fn face_valence(&self, f: $crate::FaceId) -> usize {
                self.halfedges_around_face(f).count()
            }

            /// The halfedge from `from` to `to`, if they are joined by an edge.
            ///
            /// # Complexity
            /// O(valence of `from`).
            #[must_use]
            pub fn find_halfedge(
                &self,
                from: $crate::VertexId,
                to: $crate::VertexId,
            ) -> Option<$crate::HalfedgeId> {
                self.halfedges_around_vertex(from)
                    .find(|&h| self.to_vertex(h) == to)
            }

            /// The vertex opposite halfedge `h` in its triangle: `to_vertex(next(h))`.
            /// `None` for a boundary halfedge. Meaningful for triangles only.
            #[inline]
            #[must_use]
            pub fn opposite_vertex(&self, h: $crate::HalfedgeId) -> Option<$crate::VertexId> {
                (!self.is_boundary_halfedge(h)).then(|| self.to_vertex(self.next(h)))
            }

            /// The outgoing halfedges of `v`, counter-clockwise, starting at
            /// [`outgoing_halfedge`](Self::outgoing_halfedge). Empty for an isolated
            /// vertex.
            ///
            /// # Examples
            /// ```
            /// use beltrami_halfedge::{HalfedgeMesh, VertexId};
            /// // A fan of three triangles around vertex 0.
            /// let mesh = HalfedgeMesh::from_polygons(5, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4]]).unwrap();
            /// let ring: Vec<u32> = mesh.vertices_around_vertex(VertexId::new(0)).map(|v| v.raw()).collect();
            /// assert_eq!(ring, [4, 1, 2, 3]); // boundary neighbour first, then counter-clockwise
            /// ```
            #[must_use]
            pub fn halfedges_around_vertex(
                &self,
                v: $crate::VertexId,
            ) -> $crate::circulators::HalfedgesAroundVertex<'_, Self> {
                $crate::circulators::HalfedgesAroundVertex::new(self, self.outgoing_halfedge(v))
            }

            /// The neighbours of `v` (its one-ring), counter-clockwise. Each neighbour
            /// appears once.
            #[must_use]
            pub fn vertices_around_vertex(
                &self,
                v: $crate::VertexId,
            ) -> $crate::circulators::VerticesAroundVertex<'_, Self> {
                $crate::circulators::VerticesAroundVertex::new(self.halfedges_around_vertex(v))
            }

            /// The faces around `v`, counter-clockwise (boundary gaps skipped).
            #[must_use]
            pub fn faces_around_vertex(
                &self,
                v: $crate::VertexId,
            ) -> $crate::circulators::FacesAroundVertex<'_, Self> {
                $crate::circulators::FacesAroundVertex::new(self.halfedges_around_vertex(v))
            }

            /// The halfedges of face `f`, counter-clockwise, starting at
            /// [`face_halfedge`](Self::face_halfedge).
            #[must_use]
            pub fn halfedges_around_face(
                &self,
                f: $crate::FaceId,
            ) -> $crate::circulators::HalfedgesAroundFace<'_, Self> {
                self.halfedges_around_cycle(self.face_halfedge(f))
            }

            /// The halfedges of the cycle (face or boundary loop) that contains `h`,
            /// starting at `h` and following [`next`](Self::next).
            #[must_use]
            pub fn halfedges_around_cycle(
                &self,
                h: $crate::HalfedgeId,
            ) -> $crate::circulators::HalfedgesAroundFace<'_, Self> {
                $crate::circulators::HalfedgesAroundFace::new(self, h)
            }

            /// The vertices of face `f`, counter-clockwise, starting at the target of
            /// [`face_halfedge`](Self::face_halfedge).
            ///
            /// # Examples
            /// ```
            /// use beltrami_halfedge::{FaceId, HalfedgeMesh};
            /// let mesh = HalfedgeMesh::from_polygons(4, &[[2u32, 0, 1], [0, 2, 3]]).unwrap();
            /// let f1: Vec<u32> = mesh.vertices_around_face(FaceId::new(1)).map(|v| v.raw()).collect();
            /// assert_eq!(f1, [0, 2, 3]);
            /// ```
            #[must_use]
            pub fn vertices_around_face(
                &self,
                f: $crate::FaceId,
            ) -> $crate::circulators::VerticesAroundFace<'_, Self> {
                $crate::circulators::VerticesAroundFace::new(self.halfedges_around_face(f))
            }

            /// The faces across the edges of `f` (boundary edges skipped).
            #[must_use]
            pub fn faces_around_face(
                &self,
                f: $crate::FaceId,
            ) -> $crate::circulators::FacesAroundFace<'_, Self> {
                $crate::circulators::FacesAroundFace::new(self.halfedges_around_face(f))
            }
        }
    };
}
pub(crate) use navigation;
