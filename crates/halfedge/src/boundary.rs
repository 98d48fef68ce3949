//! Boundary loops.

use crate::ids::HalfedgeId;
use crate::mesh::HalfedgeMesh;

/// The boundary loops of a mesh, each as its halfedges in `next` order. See
/// [`HalfedgeMesh::boundary_loops`].
#[derive(Clone, Debug)]
pub struct BoundaryLoops<'a> {
    mesh: &'a HalfedgeMesh,
    visited: Vec<bool>,
    cursor: usize,
}

impl Iterator for BoundaryLoops<'_> {
    type Item = Vec<HalfedgeId>;

    fn next(&mut self) -> Option<Vec<HalfedgeId>> {
        let mesh = self.mesh;
        while self.cursor < mesh.n_halfedges() {
            let h = HalfedgeId::new(self.cursor as u32);
            self.cursor += 1;
            if mesh.is_boundary_halfedge(h) && !self.visited[h.index()] {
                let cycle: Vec<HalfedgeId> = mesh.halfedges_around_cycle(h).collect();
                for c in &cycle {
                    self.visited[c.index()] = true;
                }
                return Some(cycle);
            }
        }
        None
    }
}

impl std::iter::FusedIterator for BoundaryLoops<'_> {}

impl HalfedgeMesh {
    /// The boundary loops, ordered by their lowest halfedge id; each loop lists its
    /// boundary halfedges in `next` order starting at that lowest halfedge.
    ///
    /// Boundary halfedges run opposite to the faces beside them: seen from the side the
    /// normals point to, a loop goes clockwise around a hole (and around the outer rim of
    /// a disc). The vertices of loop `l` are `l.iter().map(|&h| mesh.to_vertex(h))`.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::HalfedgeMesh;
    /// let quad = HalfedgeMesh::from_polygons(4, &[[0u32, 1, 2], [0, 2, 3]]).unwrap();
    /// let loops: Vec<usize> = quad.boundary_loops().map(|l| l.len()).collect();
    /// assert_eq!(loops, [4]);
    /// ```
    ///
    /// # Complexity
    /// O(H) over all loops, with one bit of scratch per halfedge.
    pub fn boundary_loops(&self) -> BoundaryLoops<'_> {
        BoundaryLoops {
            mesh: self,
            visited: vec![false; self.n_halfedges()],
            cursor: 0,
        }
    }
}
