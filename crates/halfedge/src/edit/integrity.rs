//! `check_integrity` for an [`EditMesh`]: the invariants of
//! [`HalfedgeMesh::check_integrity`](crate::HalfedgeMesh::check_integrity) on the live
//! elements, and no live element pointing at a deleted one.

use super::storage::EditMesh;
use crate::error::TopologyError;
use crate::ids::{ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::INVALID;

fn fail<I: ElementId>(id: I, invariant: &'static str) -> Result<(), TopologyError> {
    Err(TopologyError::Integrity {
        element: format!("{} {}", I::KIND, id.index()),
        invariant,
    })
}

impl EditMesh {
    /// Checks every half-edge invariant on the live elements: links are in range and
    /// lead to live elements; `next` and `prev` are inverse; a halfedge and its successor
    /// share a face (or are both boundary) and meet at a vertex; an edge has at least one
    /// face and joins two different vertices; a face's cycle has at least 3 halfedges and
    /// all of them point to it; a vertex's outgoing halfedge starts at it, is a boundary
    /// halfedge whenever the vertex has one, and circulating from it visits every
    /// outgoing halfedge once; the deletion counters match the marks. Every operator
    /// keeps these; the check exists for tests and for code that extends the crate.
    ///
    /// # Errors
    /// [`TopologyError::Integrity`] naming the first element that breaks an invariant.
    ///
    /// # Complexity
    /// O(V + H + F).
    pub fn check_integrity(&self) -> Result<(), TopologyError> {
        self.check_counts()?;
        self.check_links()?;
        self.check_halfedges()?;
        self.check_faces()?;
        self.check_vertices()
    }

    /// The arrays' lengths and the deletion counters agree with the marks.
    fn check_counts(&self) -> Result<(), TopologyError> {
        let nv = self.vertex_capacity();
        let nh = 2 * self.edge_capacity();
        let counted = |d: &[bool]| d.iter().filter(|&&x| x).count();
        if counted(&self.v_deleted) != self.deleted_vertices
            || counted(&self.e_deleted) != self.deleted_edges
            || counted(&self.f_deleted) != self.deleted_faces
            || self.h_to.len() != nh
            || self.h_next.len() != nh
            || self.h_prev.len() != nh
            || self.h_face.len() != nh
            || self.v_pos.len() != nv
        {
            return Err(TopologyError::Integrity {
                element: "mesh".into(),
                invariant: "array lengths and deletion counts agree",
            });
        }
        Ok(())
    }

    /// Every link of a live element is in range and leads to a live element.
    fn check_links(&self) -> Result<(), TopologyError> {
        let nv = self.vertex_capacity();
        let nh = 2 * self.edge_capacity();
        let nf = self.face_capacity();
        let live_h = |raw: u32| (raw as usize) < nh && self.is_live_halfedge(HalfedgeId::new(raw));
        for h in self.halfedges() {
            let i = h.index();
            let face_ok = self.h_face[i] == INVALID
                || ((self.h_face[i] as usize) < nf
                    && self.is_live_face(FaceId::new(self.h_face[i])));
            if (self.h_to[i] as usize) >= nv
                || !self.is_live_vertex(self.to_vertex(h))
                || !live_h(self.h_next[i])
                || !live_h(self.h_prev[i])
                || !face_ok
            {
                return fail(h, "links are in range and lead to live elements");
            }
        }
        for f in self.faces() {
            if !live_h(self.f_he[f.index()]) {
                return fail(f, "links are in range and lead to live elements");
            }
        }
        for v in self.vertices() {
            let h = self.v_out[v.index()];
            if h != INVALID && !live_h(h) {
                return fail(v, "links are in range and lead to live elements");
            }
        }
        Ok(())
    }

    /// Per live halfedge: `next` and `prev` are inverse, a halfedge and its successor
    /// meet at a vertex and share a face, an edge has a face and two different vertices.
    fn check_halfedges(&self) -> Result<(), TopologyError> {
        for h in self.halfedges() {
            if self.prev(self.next(h)) != h {
                return fail(h, "prev(next(h)) == h");
            }
            if self.from_vertex(self.next(h)) != self.to_vertex(h) {
                return fail(h, "next(h) starts where h ends");
            }
            if self.face(self.next(h)) != self.face(h) {
                return fail(h, "next(h) lies in the face of h");
            }
            if self.to_vertex(h) == self.from_vertex(h) {
                return fail(h, "a halfedge joins two different vertices");
            }
            if self.is_boundary_halfedge(h) && self.is_boundary_halfedge(h.twin()) {
                return fail(h, "an edge has at least one face");
            }
        }
        Ok(())
    }

    /// Per live face: its halfedge belongs to it, and its cycle has at least 3
    /// halfedges, all that point to it.
    fn check_faces(&self) -> Result<(), TopologyError> {
        let nh = 2 * self.edge_capacity();
        let nf = self.face_capacity();
        let mut face_len = vec![0usize; nf];
        for h in self.halfedges() {
            if let Some(f) = self.face(h) {
                face_len[f.index()] += 1;
            }
        }
        for f in self.faces() {
            let h = self.face_halfedge(f);
            if self.face(h) != Some(f) {
                return fail(f, "the face's halfedge belongs to the face");
            }
            let len = self.halfedges_around_face(f).take(nh + 1).count();
            if len < 3 || len != face_len[f.index()] {
                return fail(f, "a face is one cycle of at least 3 halfedges");
            }
        }
        Ok(())
    }

    /// Per live vertex: its outgoing halfedge starts at it, is a boundary halfedge
    /// whenever the vertex has one, and circulating from it visits every outgoing
    /// halfedge once.
    fn check_vertices(&self) -> Result<(), TopologyError> {
        let nv = self.vertex_capacity();
        let mut degree = vec![0usize; nv];
        let mut has_boundary_out = vec![false; nv];
        for h in self.halfedges() {
            let v = self.from_vertex(h).index();
            degree[v] += 1;
            has_boundary_out[v] |= self.is_boundary_halfedge(h);
        }
        for v in self.vertices() {
            match self.outgoing_halfedge(v) {
                None if degree[v.index()] == 0 => {}
                None => return fail(v, "a vertex with edges has an outgoing halfedge"),
                Some(h) => {
                    if self.from_vertex(h) != v {
                        return fail(v, "the outgoing halfedge starts at the vertex");
                    }
                    if has_boundary_out[v.index()] && !self.is_boundary_halfedge(h) {
                        return fail(v, "a boundary vertex's outgoing halfedge is a boundary one");
                    }
                    let d = degree[v.index()];
                    if self.halfedges_around_vertex(v).take(d + 1).count() != d {
                        return fail(v, "circulation visits every outgoing halfedge once");
                    }
                }
            }
        }
        Ok(())
    }

    /// The number of fans around `v` that end at the boundary: 0 for an interior or
    /// isolated vertex, 1 for a manifold boundary vertex, more for a pinch.
    #[must_use]
    pub fn boundary_fans(&self, v: VertexId) -> usize {
        self.halfedges_around_vertex(v)
            .filter(|&h| self.is_boundary_halfedge(h))
            .count()
    }
}
