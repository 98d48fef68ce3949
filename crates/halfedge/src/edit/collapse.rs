//! Halfedge collapse: the start vertex of a halfedge is merged into its end vertex.
//!
//! ```text
//!        vl                  vl
//!       /  \                 |
//!     v0 -> v1      →        v1
//!       \  /                 |
//!        vr                  vr
//! ```

use super::error::EditError;
use super::storage::EditMesh;
use crate::ids::{HalfedgeId, VertexId};

impl EditMesh {
    /// Checks the preconditions of [`collapse_edge`](Self::collapse_edge), the rules of
    /// OpenMesh's `TriConnectivity::is_collapse_ok` for the halfedge `v0 → v1`:
    ///
    /// 1. the halfedge is live and the faces at it are triangles;
    /// 2. a triangle at the edge must not have both its other edges on the boundary;
    /// 3. the vertices opposite the edge on its two sides must differ;
    /// 4. the link condition: every common neighbour of `v0` and `v1` is opposite the
    ///    edge;
    /// 5. an interior edge must not join two boundary vertices;
    /// 6. `v0` and `v1` must be joined by this edge only. OpenMesh does not check this;
    ///    it matters only on meshes that are not simplicial complexes (a split edge
    ///    whose two triangles had the same opposite vertex leaves two edges between
    ///    the new vertex and that one), where the collapse would create a loop edge.
    ///
    /// Geometry (fold-overs, long edges) is the caller's concern.
    ///
    /// # Errors
    /// [`EditError::NoSuchHalfedge`], [`EditError::NotTriangle`],
    /// [`EditError::CollapseDanglingTriangle`], [`EditError::CollapseSameOpposite`],
    /// [`EditError::CollapseLinkCondition`], [`EditError::CollapseBoundaryPinch`],
    /// [`EditError::CollapseDuplicateEdge`], [`EditError::CollapseClosesHole`].
    ///
    /// # Complexity
    /// O(valence(v0) · valence(v1)).
    pub fn check_collapse(&self, h: HalfedgeId) -> Result<(), EditError> {
        self.live_halfedge(h)?;
        let o = h.twin();
        self.triangle_or_boundary(h)?;
        self.triangle_or_boundary(o)?;
        let v0 = self.from_vertex(h);
        let v1 = self.to_vertex(h);
        let mut vl = None;
        let mut vr = None;
        for (side, slot) in [(h, &mut vl), (o, &mut vr)] {
            if !self.is_boundary_halfedge(side) {
                let h1 = self.next(side);
                let h2 = self.next(h1);
                let opposite = self.to_vertex(h1);
                *slot = Some(opposite);
                if self.is_boundary_halfedge(h1.twin()) && self.is_boundary_halfedge(h2.twin()) {
                    return Err(EditError::CollapseDanglingTriangle {
                        halfedge: h,
                        vertex: opposite,
                    });
                }
            }
        }
        if vl == vr {
            // Both are set: an edge always has a face on one side, so two `None`s
            // cannot happen in a valid mesh.
            if let Some(vertex) = vl {
                return Err(EditError::CollapseSameOpposite {
                    halfedge: h,
                    vertex,
                });
            }
        }
        if self
            .halfedges_around_vertex(v0)
            .filter(|&g| self.to_vertex(g) == v1)
            .count()
            > 1
        {
            return Err(EditError::CollapseDuplicateEdge { halfedge: h });
        }
        // `v1`'s neighbours are gathered once (on the stack for the usual valences)
        // rather than walked again for each neighbour of `v0`.
        let mut ring = [VertexId::new(0); 24];
        let mut len = 0;
        for m in self.vertices_around_vertex(v1) {
            if len == ring.len() {
                len = usize::MAX;
                break;
            }
            ring[len] = m;
            len += 1;
        }
        for n in self.vertices_around_vertex(v0) {
            if Some(n) == vl || Some(n) == vr {
                continue;
            }
            let common = if len <= ring.len() {
                ring[..len].contains(&n)
            } else {
                self.vertices_around_vertex(v1).any(|m| m == n)
            };
            if common {
                return Err(EditError::CollapseLinkCondition {
                    halfedge: h,
                    vertex: n,
                });
            }
        }
        for side in [h, o] {
            if self.is_boundary_halfedge(side) && self.next(self.next(self.next(side))) == side {
                return Err(EditError::CollapseClosesHole { halfedge: h });
            }
        }
        if self.is_boundary_vertex(v0)
            && self.is_boundary_vertex(v1)
            && !self.is_boundary_halfedge(h)
            && !self.is_boundary_halfedge(o)
        {
            return Err(EditError::CollapseBoundaryPinch { halfedge: h });
        }
        Ok(())
    }

    /// Whether [`collapse_edge`](Self::collapse_edge) would accept `h`.
    #[must_use]
    pub fn is_collapse_ok(&self, h: HalfedgeId) -> bool {
        self.check_collapse(h).is_ok()
    }

    /// Whether collapsing `h` would flatten a tetrahedron: the vertices opposite the
    /// edge on its two sides are joined by an edge and both have valence 3, so the
    /// edge's component is a closed tetrahedron, and the collapse would leave two
    /// triangles on the same three vertices (a closed but flat surface, which any later
    /// smoothing or projection draws into one point).
    ///
    /// [`check_collapse`](Self::check_collapse) allows that collapse, as OpenMesh's
    /// `TriConnectivity::is_collapse_ok` does; an algorithm that must keep every closed
    /// component a solid (decimation, as OpenMesh's `DecimaterT` does, and remeshing)
    /// refuses it with this test. `false` for a boundary edge and for a halfedge that
    /// is not live.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{primitives, EditMesh};
    ///
    /// let t = primitives::tetrahedron();
    /// let mesh = EditMesh::from_mesh(&t.mesh().unwrap(), &t.positions).unwrap();
    /// let h = mesh.halfedges().next().unwrap();
    /// assert!(mesh.is_collapse_ok(h) && mesh.collapse_flattens_tetrahedron(h));
    /// ```
    #[must_use]
    pub fn collapse_flattens_tetrahedron(&self, h: HalfedgeId) -> bool {
        if !self.is_live_halfedge(h) {
            return false;
        }
        // Valence 3, tested by counting at most four spokes.
        let valence_3 = |v: VertexId| self.halfedges_around_vertex(v).take(4).count() == 3;
        match (self.opposite_vertex(h), self.opposite_vertex(h.twin())) {
            (Some(l), Some(r)) => {
                valence_3(l) && valence_3(r) && self.find_halfedge(l, r).is_some()
            }
            _ => false,
        }
    }

    /// Collapses halfedge `h = v0 → v1`: `v0` is removed and its edges are moved to
    /// `v1`, which keeps its position and property values (move it afterwards for a
    /// midpoint collapse). Each triangle at the edge degenerates and is removed with one
    /// of its two other edges; the edge at `v1` survives and keeps its value, and its
    /// halfedge that takes the removed one's place in the neighbouring face takes that
    /// halfedge's value. Returns `v1`. With k faces at the edge, V, E and F shrink by 1,
    /// 1 + k and k; the removed elements are marked deleted.
    ///
    /// # Errors
    /// Those of [`check_collapse`](Self::check_collapse); the mesh is then unchanged.
    ///
    /// # Complexity
    /// O(valence(v0) · valence(v1)) for the check, O(valence(v0)) for the collapse.
    pub fn collapse_edge(&mut self, h: HalfedgeId) -> Result<VertexId, EditError> {
        self.check_collapse(h)?;
        let h1 = self.next(h);
        let o = h.twin();
        let o1 = self.next(o);
        let kept = self.to_vertex(h);
        // Only a vertex on the boundary needs its outgoing halfedge pointed at a boundary
        // one again, and only the two ends and the (one or two) opposite vertices can
        // be on it afterwards if they were not before (the removed vertex's boundary
        // passes to the kept one). Without a boundary among them, that walk around
        // each of their rings is skipped (it would find nothing).
        let boundary = [h, o].into_iter().any(|g| {
            self.is_boundary_vertex(self.to_vertex(g))
                || (!self.is_boundary_halfedge(g)
                    && self.is_boundary_vertex(self.to_vertex(self.next(g))))
        });
        self.collapse_halfedge(h, boundary);
        if self.next(self.next(h1)) == h1 {
            let loop_start = self.next(h1);
            self.collapse_loop(loop_start, boundary);
        }
        if self.next(self.next(o1)) == o1 {
            self.collapse_loop(o1, boundary);
        }
        Ok(kept)
    }

    /// Removes the edge of `h` and its start vertex, leaving two-halfedge loops where
    /// the triangles were; `boundary`: a vertex involved is on the boundary (see
    /// [`collapse_edge`](Self::collapse_edge)).
    fn collapse_halfedge(&mut self, h: HalfedgeId, boundary: bool) {
        let hn = self.next(h);
        let hp = self.prev(h);
        let o = h.twin();
        let on = self.next(o);
        let op = self.prev(o);
        let fh = self.face(h);
        let fo = self.face(o);
        let vh = self.to_vertex(h);
        let vo = self.to_vertex(o);

        // The halfedges into `vo` now point to `vh`. Retargeting changes `to` only, and
        // the walk around `vo` follows `prev` and twins, so it is done in place (no list
        // of the incoming halfedges, one allocation fewer per collapse).
        if let Some(start) = self.outgoing_halfedge(vo) {
            let mut g = start;
            loop {
                self.set_to(g.twin(), vh);
                g = self.ccw_rotated(g);
                if g == start {
                    break;
                }
            }
        }
        self.link(hp, hn);
        self.link(op, on);
        if let Some(fh) = fh {
            self.set_face_halfedge(fh, hn);
        }
        if let Some(fo) = fo {
            self.set_face_halfedge(fo, on);
        }
        if self.outgoing_halfedge(vh) == Some(o) {
            self.set_outgoing(vh, Some(hn));
        }
        if boundary {
            self.adjust_outgoing(vh);
        }
        self.mark_edge_deleted(h.edge());
        self.mark_vertex_deleted(vo);
    }

    /// Removes a two-halfedge face loop `h0, h1 = next(h0)`: the edge of `h0` goes, and
    /// `h1` takes the place of `twin(h0)` in the face beyond; `boundary` as for
    /// [`collapse_halfedge`](Self::collapse_halfedge).
    fn collapse_loop(&mut self, h0: HalfedgeId, boundary: bool) {
        let h1 = self.next(h0);
        let o0 = h0.twin();
        let o1 = h1.twin();
        let v0 = self.to_vertex(h0);
        let v1 = self.to_vertex(h1);
        let fh = self.face(h0);
        let fo = self.face(o0);

        let on = self.next(o0);
        let op = self.prev(o0);
        self.link(h1, on);
        self.link(op, h1);
        self.set_face(h1, fo);
        self.props.halfedge().copy(o0.index(), h1.index());

        self.set_outgoing(v0, Some(h1));
        if boundary {
            self.adjust_outgoing(v0);
        }
        self.set_outgoing(v1, Some(o1));
        if boundary {
            self.adjust_outgoing(v1);
        }

        if let Some(fo) = fo
            && self.face_halfedge(fo) == o0
        {
            self.set_face_halfedge(fo, h1);
        }
        if let Some(fh) = fh {
            self.mark_face_deleted(fh);
        }
        self.mark_edge_deleted(h0.edge());
    }
}

#[cfg(test)]
mod tests {
    use crate::{DVec3, EditError, EditMesh, FaceId, HalfedgeMesh, VertexId};

    /// A disc of `n` triangles around vertex 0, the triangle `(0, 1, 2)` split at a
    /// new vertex: vertex 2 is then a common neighbour of 0 and 1 that is not opposite
    /// their edge.
    fn split_fan(n: u32) -> EditMesh {
        let faces: Vec<[u32; 3]> = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
        let mesh = HalfedgeMesh::from_polygons(n as usize + 1, &faces).unwrap();
        let mut positions = vec![DVec3::ZERO];
        positions.extend((0..n).map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            DVec3::new(t.cos(), t.sin(), 0.0)
        }));
        let mut fan = EditMesh::from_mesh(&mesh, &positions).unwrap();
        let first = fan
            .faces()
            .find(|&f| {
                let c: Vec<VertexId> = fan.vertices_around_face(f).collect();
                c.contains(&VertexId::new(1)) && c.contains(&VertexId::new(2))
            })
            .unwrap_or(FaceId::new(0));
        fan.split_face(first, DVec3::new(0.3, 0.1, 0.0)).unwrap();
        fan
    }

    #[test]
    fn the_link_condition_holds_for_small_and_large_valences() {
        // Valence 7 and 31 at the centre: the gathered ring and the walked one.
        for n in [6, 30] {
            let fan = split_fan(n);
            let (centre, rim) = (VertexId::new(0), VertexId::new(1));
            assert!(fan.valence(centre) > n as usize);
            for (from, to) in [(centre, rim), (rim, centre)] {
                let h = fan.find_halfedge(from, to).unwrap();
                assert_eq!(
                    fan.check_collapse(h),
                    Err(EditError::CollapseLinkCondition {
                        halfedge: h,
                        vertex: VertexId::new(2),
                    }),
                    "valence {n}: {from:?} -> {to:?}"
                );
            }
            // An edge of the disc away from the split collapses.
            let far = fan.find_halfedge(VertexId::new(1 + n / 2), centre).unwrap();
            assert!(fan.is_collapse_ok(far), "valence {n}");
        }
    }
}
