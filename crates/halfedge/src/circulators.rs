//! Circulators: named iterators around a vertex or a face, counter-clockwise.
//!
//! Around a vertex, "counter-clockwise" is seen from the side the face normals point
//! to; the step is [`HalfedgeMesh::ccw_rotated`]. Each circulator starts at the
//! vertex's [`outgoing_halfedge`](HalfedgeMesh::outgoing_halfedge) — at a boundary
//! vertex, the outgoing boundary halfedge, so the first neighbour is the one across
//! the boundary edge that leaves the vertex and the fan is then visited in order.

use std::iter::FusedIterator;

use crate::ids::{FaceId, HalfedgeId, VertexId};
use crate::mesh::HalfedgeMesh;

/// Outgoing halfedges of a vertex, counter-clockwise. See
/// [`HalfedgeMesh::halfedges_around_vertex`].
#[derive(Clone, Debug)]
pub struct HalfedgesAroundVertex<'a> {
    mesh: &'a HalfedgeMesh,
    start: Option<HalfedgeId>,
    current: Option<HalfedgeId>,
}

impl Iterator for HalfedgesAroundVertex<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        let n = self.mesh.ccw_rotated(h);
        self.current = (Some(n) != self.start).then_some(n);
        Some(h)
    }
}
impl FusedIterator for HalfedgesAroundVertex<'_> {}

/// Neighbouring vertices of a vertex (its one-ring), counter-clockwise. See
/// [`HalfedgeMesh::vertices_around_vertex`].
#[derive(Clone, Debug)]
pub struct VerticesAroundVertex<'a> {
    inner: HalfedgesAroundVertex<'a>,
}

impl Iterator for VerticesAroundVertex<'_> {
    type Item = VertexId;
    #[inline]
    fn next(&mut self) -> Option<VertexId> {
        self.inner.next().map(|h| self.inner.mesh.to_vertex(h))
    }
}
impl FusedIterator for VerticesAroundVertex<'_> {}

/// Faces incident to a vertex, counter-clockwise. See
/// [`HalfedgeMesh::faces_around_vertex`].
#[derive(Clone, Debug)]
pub struct FacesAroundVertex<'a> {
    inner: HalfedgesAroundVertex<'a>,
}

impl Iterator for FacesAroundVertex<'_> {
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
impl FusedIterator for FacesAroundVertex<'_> {}

/// Halfedges of a face (or of a boundary loop), following `next`. See
/// [`HalfedgeMesh::halfedges_around_face`].
#[derive(Clone, Debug)]
pub struct HalfedgesAroundFace<'a> {
    mesh: &'a HalfedgeMesh,
    start: HalfedgeId,
    current: Option<HalfedgeId>,
}

impl Iterator for HalfedgesAroundFace<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        let n = self.mesh.next(h);
        self.current = (n != self.start).then_some(n);
        Some(h)
    }
}
impl FusedIterator for HalfedgesAroundFace<'_> {}

/// Vertices of a face in input order. See [`HalfedgeMesh::vertices_around_face`].
#[derive(Clone, Debug)]
pub struct VerticesAroundFace<'a> {
    inner: HalfedgesAroundFace<'a>,
}

impl Iterator for VerticesAroundFace<'_> {
    type Item = VertexId;
    #[inline]
    fn next(&mut self) -> Option<VertexId> {
        self.inner.next().map(|h| self.inner.mesh.to_vertex(h))
    }
}
impl FusedIterator for VerticesAroundFace<'_> {}

/// Faces that share an edge with a face, in the order of the face's halfedges. See
/// [`HalfedgeMesh::faces_around_face`].
#[derive(Clone, Debug)]
pub struct FacesAroundFace<'a> {
    inner: HalfedgesAroundFace<'a>,
}

impl Iterator for FacesAroundFace<'_> {
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
impl FusedIterator for FacesAroundFace<'_> {}

impl HalfedgeMesh {
    /// The outgoing halfedges of `v`, counter-clockwise, starting at
    /// [`outgoing_halfedge`](Self::outgoing_halfedge). Empty for an isolated vertex.
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
    pub fn halfedges_around_vertex(&self, v: VertexId) -> HalfedgesAroundVertex<'_> {
        let start = self.outgoing_halfedge(v);
        HalfedgesAroundVertex {
            mesh: self,
            start,
            current: start,
        }
    }

    /// The neighbours of `v` (its one-ring), counter-clockwise. Each neighbour appears once.
    #[must_use]
    pub fn vertices_around_vertex(&self, v: VertexId) -> VerticesAroundVertex<'_> {
        VerticesAroundVertex {
            inner: self.halfedges_around_vertex(v),
        }
    }

    /// The faces around `v`, counter-clockwise (boundary gaps skipped).
    #[must_use]
    pub fn faces_around_vertex(&self, v: VertexId) -> FacesAroundVertex<'_> {
        FacesAroundVertex {
            inner: self.halfedges_around_vertex(v),
        }
    }

    /// The halfedges of face `f`, counter-clockwise, starting at
    /// [`face_halfedge`](Self::face_halfedge).
    #[must_use]
    pub fn halfedges_around_face(&self, f: FaceId) -> HalfedgesAroundFace<'_> {
        self.halfedges_around_cycle(self.face_halfedge(f))
    }

    /// The halfedges of the cycle (face or boundary loop) that contains `h`, starting at
    /// `h` and following [`next`](Self::next).
    #[must_use]
    pub fn halfedges_around_cycle(&self, h: HalfedgeId) -> HalfedgesAroundFace<'_> {
        HalfedgesAroundFace {
            mesh: self,
            start: h,
            current: Some(h),
        }
    }

    /// The vertices of face `f`, counter-clockwise, in the order given to the builder.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{FaceId, HalfedgeMesh};
    /// let mesh = HalfedgeMesh::from_polygons(4, &[[2u32, 0, 1], [0, 2, 3]]).unwrap();
    /// let f1: Vec<u32> = mesh.vertices_around_face(FaceId::new(1)).map(|v| v.raw()).collect();
    /// assert_eq!(f1, [0, 2, 3]);
    /// ```
    #[must_use]
    pub fn vertices_around_face(&self, f: FaceId) -> VerticesAroundFace<'_> {
        VerticesAroundFace {
            inner: self.halfedges_around_face(f),
        }
    }

    /// The faces across the edges of `f` (boundary edges skipped).
    #[must_use]
    pub fn faces_around_face(&self, f: FaceId) -> FacesAroundFace<'_> {
        FacesAroundFace {
            inner: self.halfedges_around_face(f),
        }
    }
}
