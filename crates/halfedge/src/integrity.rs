//! `check_integrity`: every half-edge invariant, checked element by element.

use crate::error::TopologyError;
use crate::ids::ElementId;
use crate::mesh::{HalfedgeMesh, INVALID};

fn fail<I: ElementId>(id: I, invariant: &'static str) -> Result<(), TopologyError> {
    Err(TopologyError::Integrity {
        element: format!("{} {}", I::KIND, id.index()),
        invariant,
    })
}

impl HalfedgeMesh {
    /// Checks every invariant of the structure. A mesh built by this crate always
    /// passes; the check exists for tests and for code that extends the crate.
    ///
    /// Invariants: links are in range; `next` and `prev` are inverse; a halfedge and its
    /// successor share a face (or are both boundary) and meet at a vertex; twins run
    /// between the same two vertices in opposite directions and are never both boundary;
    /// every face's halfedge belongs to it and its cycle has at least 3 halfedges; every
    /// non-isolated vertex's outgoing halfedge starts at it, and is a boundary halfedge
    /// whenever the vertex has one; circulating a vertex visits all its outgoing halfedges.
    ///
    /// # Errors
    /// [`TopologyError::Integrity`] naming the first element that breaks an invariant.
    ///
    /// # Complexity
    /// O(H).
    pub fn check_integrity(&self) -> Result<(), TopologyError> {
        let nh = self.n_halfedges();
        let (nv, nf) = (self.n_vertices(), self.n_faces());
        if nh % 2 != 0 {
            return Err(TopologyError::Integrity {
                element: "mesh".into(),
                invariant: "the number of halfedges is even",
            });
        }
        for h in self.halfedges() {
            let i = h.index();
            if self.h_to[i] as usize >= nv
                || self.h_next[i] as usize >= nh
                || self.h_prev[i] as usize >= nh
                || (self.h_face[i] != INVALID && self.h_face[i] as usize >= nf)
            {
                return fail(h, "links are in range");
            }
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
        for f in self.faces() {
            let h = self.face_halfedge(f);
            if h.index() >= nh || self.face(h) != Some(f) {
                return fail(f, "the face's halfedge belongs to the face");
            }
            let len = self.halfedges_around_face(f).take(nh + 1).count();
            if !(3..=nh).contains(&len) {
                return fail(f, "a face has at least 3 halfedges");
            }
        }
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
                    if h.index() >= nh || self.from_vertex(h) != v {
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
}
