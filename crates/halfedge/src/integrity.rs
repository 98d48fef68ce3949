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
        // Ranges first, so that the structural checks below never index out of bounds.
        for h in self.halfedges() {
            let i = h.index();
            if self.h_to[i] as usize >= nv
                || self.h_next[i] as usize >= nh
                || self.h_prev[i] as usize >= nh
                || (self.h_face[i] != INVALID && self.h_face[i] as usize >= nf)
            {
                return fail(h, "links are in range");
            }
        }
        for f in self.faces() {
            if self.f_he[f.index()] as usize >= nh {
                return fail(f, "links are in range");
            }
        }
        for v in self.vertices() {
            let h = self.v_out[v.index()];
            if h != INVALID && h as usize >= nh {
                return fail(v, "links are in range");
            }
        }
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
        for f in self.faces() {
            let h = self.face_halfedge(f);
            if self.face(h) != Some(f) {
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
}

#[cfg(test)]
mod tests {
    use crate::HalfedgeMesh;
    use crate::error::TopologyError;

    fn quad() -> HalfedgeMesh {
        HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]]).unwrap()
    }

    fn message(mesh: &HalfedgeMesh) -> String {
        match mesh.check_integrity() {
            Err(e @ TopologyError::Integrity { .. }) => e.to_string(),
            other => panic!("expected an integrity error, got {other:?}"),
        }
    }

    #[test]
    fn a_valid_mesh_passes() {
        quad().check_integrity().unwrap();
    }

    #[test]
    fn broken_next_is_found() {
        let mut m = quad();
        m.h_next.swap(0, 2);
        assert_eq!(
            message(&m),
            "integrity violated at halfedge 0: prev(next(h)) == h"
        );
    }

    #[test]
    fn interior_outgoing_at_a_boundary_vertex_is_found() {
        let mut m = quad();
        // Vertex 0 is on the boundary; point it at its interior outgoing halfedge 0 -> 1.
        m.v_out[0] = 0;
        assert_eq!(
            message(&m),
            "integrity violated at vertex 0: a boundary vertex's outgoing halfedge is a boundary one"
        );
    }

    #[test]
    fn wrong_face_halfedge_is_found() {
        let mut m = quad();
        m.f_he[0] = m.f_he[1];
        assert_eq!(
            message(&m),
            "integrity violated at face 0: the face's halfedge belongs to the face"
        );
    }

    #[test]
    fn out_of_range_links_are_found_without_panicking() {
        let mut m = quad();
        m.h_to[3] = 99;
        assert_eq!(
            message(&m),
            "integrity violated at halfedge 3: links are in range"
        );
        let mut m = quad();
        m.h_next[5] = 1000;
        assert_eq!(
            message(&m),
            "integrity violated at halfedge 5: links are in range"
        );
        let mut m = quad();
        m.v_out[2] = 1000;
        assert_eq!(
            message(&m),
            "integrity violated at vertex 2: links are in range"
        );
    }
}
