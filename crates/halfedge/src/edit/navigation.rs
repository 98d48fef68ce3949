//! Reading an [`EditMesh`]: links, status queries and counter-clockwise circulators,
//! named as on [`HalfedgeMesh`](crate::HalfedgeMesh).

use std::iter::FusedIterator;

use super::storage::{EditMesh, opt};
use crate::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::INVALID;

/// The live elements of one kind, in index order. See [`EditMesh::vertices`].
#[derive(Clone, Debug)]
pub struct LiveElements<'a, I> {
    deleted: &'a [bool],
    cursor: usize,
    _kind: std::marker::PhantomData<I>,
}

impl<I: ElementId> Iterator for LiveElements<'_, I> {
    type Item = I;
    fn next(&mut self) -> Option<I> {
        while self.cursor < self.deleted.len() {
            let i = self.cursor;
            self.cursor += 1;
            if !self.deleted[i] {
                return Some(I::from_index(i));
            }
        }
        None
    }
}
impl<I: ElementId> FusedIterator for LiveElements<'_, I> {}

/// Outgoing halfedges of a vertex, counter-clockwise. See
/// [`EditMesh::halfedges_around_vertex`].
#[derive(Clone, Debug)]
pub struct HalfedgesAroundVertex<'a> {
    mesh: &'a EditMesh,
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

/// Halfedges of a face or boundary loop, following `next`. See
/// [`EditMesh::halfedges_around_face`].
#[derive(Clone, Debug)]
pub struct HalfedgesAroundFace<'a> {
    mesh: &'a EditMesh,
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

impl EditMesh {
    /// The live vertices in index order.
    #[must_use]
    pub fn vertices(&self) -> LiveElements<'_, VertexId> {
        live(&self.v_deleted)
    }

    /// The live edges in index order.
    #[must_use]
    pub fn edges(&self) -> LiveElements<'_, EdgeId> {
        live(&self.e_deleted)
    }

    /// The live halfedges in index order.
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeId> + '_ {
        self.edges().flat_map(EdgeId::halfedges)
    }

    /// The live faces in index order.
    #[must_use]
    pub fn faces(&self) -> LiveElements<'_, FaceId> {
        live(&self.f_deleted)
    }

    /// The vertex `h` points to.
    ///
    /// All link accessors take a live element; on a deleted one they return what the
    /// slot last held, and they panic when the id is out of range.
    #[inline]
    #[must_use]
    pub fn to_vertex(&self, h: HalfedgeId) -> VertexId {
        VertexId::new(self.h_to[h.index()])
    }

    /// The vertex `h` starts from (the target of its twin).
    #[inline]
    #[must_use]
    pub fn from_vertex(&self, h: HalfedgeId) -> VertexId {
        VertexId::new(self.h_to[h.twin().index()])
    }

    /// The next halfedge along the face (or boundary loop) of `h`.
    #[inline]
    #[must_use]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId::new(self.h_next[h.index()])
    }

    /// The previous halfedge along the face (or boundary loop) of `h`.
    #[inline]
    #[must_use]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId::new(self.h_prev[h.index()])
    }

    /// The face `h` belongs to, `None` for a boundary halfedge.
    #[inline]
    #[must_use]
    pub fn face(&self, h: HalfedgeId) -> Option<FaceId> {
        opt(self.h_face[h.index()]).map(FaceId::new)
    }

    /// An outgoing halfedge of `v`, `None` for an isolated vertex; a boundary halfedge
    /// whenever `v` is on the boundary.
    #[inline]
    #[must_use]
    pub fn outgoing_halfedge(&self, v: VertexId) -> Option<HalfedgeId> {
        opt(self.v_out[v.index()]).map(HalfedgeId::new)
    }

    /// One halfedge of face `f`.
    #[inline]
    #[must_use]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        HalfedgeId::new(self.f_he[f.index()])
    }

    /// Rotates an outgoing halfedge counter-clockwise around its start vertex:
    /// `twin(prev(h))`.
    #[inline]
    #[must_use]
    pub fn ccw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.prev(h).twin()
    }

    /// Rotates an outgoing halfedge clockwise around its start vertex: `next(twin(h))`.
    #[inline]
    #[must_use]
    pub fn cw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.next(h.twin())
    }

    /// The two vertices of an edge, `[from, to]` of its halfedge `2e`.
    #[inline]
    #[must_use]
    pub fn edge_vertices(&self, e: EdgeId) -> [VertexId; 2] {
        let [h, t] = e.halfedges();
        [self.to_vertex(t), self.to_vertex(h)]
    }

    /// Whether `h` has no face.
    #[inline]
    #[must_use]
    pub fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        self.h_face[h.index()] == INVALID
    }

    /// Whether either halfedge of `e` has no face.
    #[inline]
    #[must_use]
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        let [a, b] = e.halfedges();
        self.is_boundary_halfedge(a) || self.is_boundary_halfedge(b)
    }

    /// Whether `v` lies on the boundary (isolated vertices count as boundary). O(1).
    #[inline]
    #[must_use]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.outgoing_halfedge(v)
            .is_none_or(|h| self.is_boundary_halfedge(h))
    }

    /// Whether `v` has no incident edge.
    #[inline]
    #[must_use]
    pub fn is_isolated(&self, v: VertexId) -> bool {
        self.v_out[v.index()] == INVALID
    }

    /// Whether the live mesh has no boundary halfedge.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.halfedges().all(|h| !self.is_boundary_halfedge(h))
    }

    /// The number of edges at `v`. O(valence).
    #[must_use]
    pub fn valence(&self, v: VertexId) -> usize {
        self.halfedges_around_vertex(v).count()
    }

    /// The number of vertices (= edges) of face `f`.
    #[must_use]
    pub fn face_valence(&self, f: FaceId) -> usize {
        self.halfedges_around_face(f).count()
    }

    /// The halfedge from `from` to `to`, if they are joined by an edge. O(valence).
    #[must_use]
    pub fn find_halfedge(&self, from: VertexId, to: VertexId) -> Option<HalfedgeId> {
        self.halfedges_around_vertex(from)
            .find(|&h| self.to_vertex(h) == to)
    }

    /// The outgoing halfedges of `v`, counter-clockwise from
    /// [`outgoing_halfedge`](Self::outgoing_halfedge). Empty for an isolated vertex.
    #[must_use]
    pub fn halfedges_around_vertex(&self, v: VertexId) -> HalfedgesAroundVertex<'_> {
        let start = self.outgoing_halfedge(v);
        HalfedgesAroundVertex {
            mesh: self,
            start,
            current: start,
        }
    }

    /// The neighbours of `v`, counter-clockwise.
    pub fn vertices_around_vertex(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        self.halfedges_around_vertex(v).map(|h| self.to_vertex(h))
    }

    /// The faces around `v`, counter-clockwise (boundary gaps skipped).
    pub fn faces_around_vertex(&self, v: VertexId) -> impl Iterator<Item = FaceId> + '_ {
        self.halfedges_around_vertex(v).filter_map(|h| self.face(h))
    }

    /// The halfedges of face `f`, counter-clockwise from
    /// [`face_halfedge`](Self::face_halfedge).
    #[must_use]
    pub fn halfedges_around_face(&self, f: FaceId) -> HalfedgesAroundFace<'_> {
        self.halfedges_around_cycle(self.face_halfedge(f))
    }

    /// The halfedges of the cycle (face or boundary loop) through `h`, from `h`.
    #[must_use]
    pub fn halfedges_around_cycle(&self, h: HalfedgeId) -> HalfedgesAroundFace<'_> {
        HalfedgesAroundFace {
            mesh: self,
            start: h,
            current: Some(h),
        }
    }

    /// The vertices of face `f`, counter-clockwise.
    pub fn vertices_around_face(&self, f: FaceId) -> impl Iterator<Item = VertexId> + '_ {
        self.halfedges_around_face(f).map(|h| self.to_vertex(h))
    }

    /// The vertex opposite halfedge `h` in its triangle, `to_vertex(next(h))`; `None`
    /// for a boundary halfedge.
    #[must_use]
    pub fn opposite_vertex(&self, h: HalfedgeId) -> Option<VertexId> {
        (!self.is_boundary_halfedge(h)).then(|| self.to_vertex(self.next(h)))
    }

    /// The live faces as vertex lists, counter-clockwise, in face index order.
    #[must_use]
    pub fn face_vertex_lists(&self) -> Vec<Vec<VertexId>> {
        self.faces()
            .map(|f| self.vertices_around_face(f).collect())
            .collect()
    }
}

fn live<I>(deleted: &[bool]) -> LiveElements<'_, I> {
    LiveElements {
        deleted,
        cursor: 0,
        _kind: std::marker::PhantomData,
    }
}
