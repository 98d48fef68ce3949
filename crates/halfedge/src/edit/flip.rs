//! Edge flip: the diagonal of the quadrilateral of two triangles is exchanged.
//!
//! ```text
//!        a                 a
//!       /|\               / \
//!      / | \             /   \
//!    c   |   d   →     c ----- d
//!      \ | /             \   /
//!       \|/               \ /
//!        b                 b
//! ```

use super::error::EditError;
use super::storage::EditMesh;
use crate::ids::EdgeId;

impl EditMesh {
    /// Checks the preconditions of [`flip_edge`](Self::flip_edge): `e` is live and
    /// interior, both its faces are triangles, their opposite vertices differ and are not
    /// already joined by an edge (as OpenMesh's `TriConnectivity::is_flip_ok`).
    ///
    /// # Errors
    /// [`EditError::NoSuchEdge`], [`EditError::FlipBoundaryEdge`],
    /// [`EditError::NotTriangle`], [`EditError::FlipSameOpposite`],
    /// [`EditError::FlipEdgeExists`].
    ///
    /// # Complexity
    /// O(valence of the opposite vertex).
    pub fn check_flip(&self, e: EdgeId) -> Result<(), EditError> {
        self.live_edge(e)?;
        if self.is_boundary_edge(e) {
            return Err(EditError::FlipBoundaryEdge { edge: e });
        }
        let [h, t] = e.halfedges();
        self.triangle_or_boundary(h)?;
        self.triangle_or_boundary(t)?;
        let a = self.to_vertex(self.next(h));
        let b = self.to_vertex(self.next(t));
        if a == b {
            return Err(EditError::FlipSameOpposite { edge: e, vertex: a });
        }
        if self.find_halfedge(a, b).is_some() {
            return Err(EditError::FlipEdgeExists {
                edge: e,
                from: a,
                to: b,
            });
        }
        Ok(())
    }

    /// Whether [`flip_edge`](Self::flip_edge) would accept `e`.
    #[must_use]
    pub fn is_flip_ok(&self, e: EdgeId) -> bool {
        self.check_flip(e).is_ok()
    }

    /// Flips edge `e`: the two triangles `(v0, v1, a)` and `(v1, v0, b)` at it become
    /// `(a, b, v1)` and `(b, a, v0)`. Halfedge `2e` then runs from `b` to `a`.
    ///
    /// The edge, its two halfedges and the two faces keep their ids and their property
    /// values. V, E and F do not change.
    ///
    /// # Errors
    /// Those of [`check_flip`](Self::check_flip); the mesh is then unchanged.
    ///
    /// # Complexity
    /// O(valence of the opposite vertex), for the check.
    pub fn flip_edge(&mut self, e: EdgeId) -> Result<(), EditError> {
        self.check_flip(e)?;
        let [a0, b0] = e.halfedges();
        let a1 = self.next(a0);
        let a2 = self.next(a1);
        let b1 = self.next(b0);
        let b2 = self.next(b1);
        let va0 = self.to_vertex(a0);
        let va1 = self.to_vertex(a1);
        let vb0 = self.to_vertex(b0);
        let vb1 = self.to_vertex(b1);
        let fa = self.face(a0);
        let fb = self.face(b0);

        self.set_to(a0, va1);
        self.set_to(b0, vb1);
        self.link(a0, a2);
        self.link(a2, b1);
        self.link(b1, a0);
        self.link(b0, b2);
        self.link(b2, a1);
        self.link(a1, b0);
        self.set_face(a1, fb);
        self.set_face(b1, fa);
        if let (Some(fa), Some(fb)) = (fa, fb) {
            self.set_face_halfedge(fa, a0);
            self.set_face_halfedge(fb, b0);
        }
        // The end points lose one outgoing halfedge each (interior ones, so a boundary
        // end point keeps its boundary halfedge).
        if self.outgoing_halfedge(va0) == Some(b0) {
            self.set_outgoing(va0, Some(a1));
        }
        if self.outgoing_halfedge(vb0) == Some(a0) {
            self.set_outgoing(vb0, Some(b1));
        }
        Ok(())
    }
}
