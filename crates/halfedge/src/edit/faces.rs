//! Adding and deleting vertices and faces: `add_vertex`, the incremental `add_face` with
//! OpenMesh's manifold checks, `delete_face`, `delete_vertex`.

use glam::DVec3;

use super::error::EditError;
use super::storage::EditMesh;
use crate::ids::{EdgeId, FaceId, HalfedgeId, VertexId};

impl EditMesh {
    /// Adds an isolated vertex at `p`; its properties get their defaults. V grows by 1.
    ///
    /// # Complexity
    /// O(number of vertex properties).
    pub fn add_vertex(&mut self, p: DVec3) -> VertexId {
        self.new_vertex(p)
    }

    /// Checks the preconditions of [`add_face`](Self::add_face) — the cases OpenMesh's
    /// `PolyConnectivity::add_face` rejects, plus the degenerate inputs it asserts on.
    ///
    /// # Errors
    /// [`EditError::FaceTooSmall`] (fewer than 3 vertices), [`EditError::NoSuchVertex`],
    /// [`EditError::RepeatedVertex`], [`EditError::ComplexVertex`] (a vertex whose fan is
    /// closed), [`EditError::ComplexEdge`] (an existing halfedge of the face already has
    /// a face: a third face on an edge, or the wrong orientation),
    /// [`EditError::NoBoundaryGap`] (two existing boundary edges meet at a vertex whose
    /// faces cannot be re-linked around the new face).
    pub fn check_add_face(&self, vertices: &[VertexId]) -> Result<(), EditError> {
        self.plan_face(vertices).map(|_| ())
    }

    /// Whether [`add_face`](Self::add_face) would accept `vertices`.
    #[must_use]
    pub fn is_add_face_ok(&self, vertices: &[VertexId]) -> bool {
        self.plan_face(vertices).is_ok()
    }

    /// The existing halfedge along each side of the new face (`None` for a new edge),
    /// and the `next` re-links that make room for it; nothing is written.
    fn plan_face(&self, vs: &[VertexId]) -> Result<Plan, EditError> {
        let n = vs.len();
        if n < 3 {
            return Err(EditError::FaceTooSmall { len: n });
        }
        for (i, &v) in vs.iter().enumerate() {
            self.live_vertex(v)?;
            if vs[..i].contains(&v) {
                return Err(EditError::RepeatedVertex { vertex: v });
            }
        }
        let mut sides = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (vs[i], vs[(i + 1) % n]);
            if !self.is_boundary_vertex(a) {
                return Err(EditError::ComplexVertex { vertex: a });
            }
            let h = self.find_halfedge(a, b);
            if let Some(h) = h
                && !self.is_boundary_halfedge(h)
            {
                return Err(EditError::ComplexEdge { from: a, to: b });
            }
            sides.push(h);
        }
        let mut relinks = Vec::new();
        for i in 0..n {
            let ii = (i + 1) % n;
            let (Some(inner_prev), Some(inner_next)) = (sides[i], sides[ii]) else {
                continue;
            };
            if self.next(inner_prev) == inner_next {
                continue;
            }
            // The two boundary edges meet at vs[ii] but not consecutively: move the
            // faces between them into another boundary gap of vs[ii].
            let outer_prev = inner_next.twin();
            let mut boundary_prev = outer_prev;
            loop {
                boundary_prev = self.next(boundary_prev).twin();
                if self.is_boundary_halfedge(boundary_prev) {
                    break;
                }
            }
            if boundary_prev == inner_prev {
                return Err(EditError::NoBoundaryGap { vertex: vs[ii] });
            }
            let boundary_next = self.next(boundary_prev);
            let patch_start = self.next(inner_prev);
            let patch_end = self.prev(inner_next);
            relinks.push((boundary_prev, patch_start));
            relinks.push((patch_end, boundary_next));
            relinks.push((inner_prev, inner_next));
        }
        Ok(Plan { sides, relinks })
    }

    /// Adds the face `vertices` (counter-clockwise, at least 3), creating the edges that
    /// do not exist yet. Follows OpenMesh's `PolyConnectivity::add_face`: every vertex
    /// must be on the boundary (or isolated), every existing edge must be free on the
    /// face's side, and the boundary is re-linked so that each vertex's outgoing halfedge
    /// stays a boundary one where it has one. As in OpenMesh, a face may touch an
    /// existing one at a vertex only (a vertex with two fans), which
    /// [`to_mesh`](Self::to_mesh) refuses until the fans are joined. The new face, edges
    /// and halfedges get the property defaults. F grows by 1 and E by the number of new
    /// edges.
    ///
    /// # Errors
    /// Those of [`check_add_face`](Self::check_add_face); the mesh is then unchanged.
    ///
    /// # Complexity
    /// O(Σ valence) over the face's vertices.
    pub fn add_face(&mut self, vertices: &[VertexId]) -> Result<FaceId, EditError> {
        let Plan { sides, relinks } = self.plan_face(vertices)?;
        let vs = vertices;
        let n = vs.len();
        let is_new: Vec<bool> = sides.iter().map(Option::is_none).collect();
        let hs: Vec<HalfedgeId> = (0..n)
            .map(|i| match sides[i] {
                Some(h) => h,
                None => self.new_edge(vs[i], vs[(i + 1) % n]),
            })
            .collect();
        let f = self.new_face(hs[n - 1]);
        let mut cache = relinks;
        let mut needs_adjust = vec![false; n];
        for i in 0..n {
            let ii = (i + 1) % n;
            let vh = vs[ii];
            let inner_prev = hs[i];
            let inner_next = hs[ii];
            if is_new[i] || is_new[ii] {
                let outer_prev = inner_next.twin();
                let outer_next = inner_prev.twin();
                match (is_new[i], is_new[ii]) {
                    (true, false) => {
                        let boundary_prev = self.prev(inner_next);
                        cache.push((boundary_prev, outer_next));
                        self.set_outgoing(vh, Some(outer_next));
                    }
                    (false, true) => {
                        let boundary_next = self.next(inner_prev);
                        cache.push((outer_prev, boundary_next));
                        self.set_outgoing(vh, Some(boundary_next));
                    }
                    _ => match self.outgoing_halfedge(vh) {
                        None => {
                            self.set_outgoing(vh, Some(outer_next));
                            cache.push((outer_prev, outer_next));
                        }
                        Some(boundary_next) => {
                            let boundary_prev = self.prev(boundary_next);
                            cache.push((boundary_prev, outer_next));
                            cache.push((outer_prev, boundary_next));
                        }
                    },
                }
                cache.push((inner_prev, inner_next));
            } else {
                needs_adjust[ii] = self.outgoing_halfedge(vh) == Some(inner_next);
            }
            self.set_face(inner_prev, Some(f));
        }
        for (a, b) in cache {
            self.link(a, b);
        }
        for (i, &v) in vs.iter().enumerate() {
            if needs_adjust[i] {
                self.adjust_outgoing(v);
            }
        }
        Ok(f)
    }

    /// Deletes face `f`. Its edges that are left without a face are deleted too, and so
    /// are vertices left without edges (as OpenMesh's `delete_face` with
    /// `delete_isolated_vertices`). Property values of the removed elements are dropped
    /// by the next garbage collection. F shrinks by 1; E and V by what became free.
    ///
    /// Deleting faces can leave a vertex with two fans (a pinch), which
    /// [`to_mesh`](Self::to_mesh) refuses.
    ///
    /// # Errors
    /// [`EditError::NoSuchFace`] when `f` is not a live face; the mesh is then unchanged.
    ///
    /// # Complexity
    /// O(Σ valence) over the face's vertices.
    pub fn delete_face(&mut self, f: FaceId) -> Result<(), EditError> {
        self.live_face(f)?;
        self.mark_face_deleted(f);
        let mut free_edges: Vec<EdgeId> = Vec::new();
        let mut corners: Vec<VertexId> = Vec::new();
        let hs: Vec<HalfedgeId> = self.halfedges_around_face(f).collect();
        for &h in &hs {
            self.set_face(h, None);
            if self.is_boundary_halfedge(h.twin()) {
                free_edges.push(h.edge());
            }
            corners.push(self.to_vertex(h));
        }
        for e in free_edges {
            let [h0, h1] = e.halfedges();
            let v0 = self.to_vertex(h0);
            let next0 = self.next(h0);
            let prev0 = self.prev(h0);
            let v1 = self.to_vertex(h1);
            let next1 = self.next(h1);
            let prev1 = self.prev(h1);
            self.link(prev0, next1);
            self.link(prev1, next0);
            self.mark_edge_deleted(e);
            if self.outgoing_halfedge(v0) == Some(h1) {
                if next0 == h1 {
                    self.mark_vertex_deleted(v0);
                } else {
                    self.set_outgoing(v0, Some(next0));
                }
            }
            if self.outgoing_halfedge(v1) == Some(h0) {
                if next1 == h0 {
                    self.mark_vertex_deleted(v1);
                } else {
                    self.set_outgoing(v1, Some(next1));
                }
            }
        }
        for v in corners {
            if self.is_live_vertex(v) {
                self.adjust_outgoing(v);
            }
        }
        Ok(())
    }

    /// Deletes vertex `v` with every face around it (each by
    /// [`delete_face`](Self::delete_face), so edges and vertices left free go too).
    ///
    /// # Errors
    /// [`EditError::NoSuchVertex`] when `v` is not a live vertex; the mesh is then
    /// unchanged.
    ///
    /// # Complexity
    /// O(Σ valence) over the vertices of its faces.
    pub fn delete_vertex(&mut self, v: VertexId) -> Result<(), EditError> {
        self.live_vertex(v)?;
        let faces: Vec<FaceId> = self.faces_around_vertex(v).collect();
        for f in faces {
            self.delete_face(f)?;
        }
        self.mark_vertex_deleted(v);
        Ok(())
    }
}

/// What [`EditMesh::add_face`] will do, decided before anything is written.
struct Plan {
    sides: Vec<Option<HalfedgeId>>,
    relinks: Vec<(HalfedgeId, HalfedgeId)>,
}
