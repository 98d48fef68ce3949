//! Splits: a new vertex on an edge (1 → 2 triangles on each side) or inside a face
//! (1 → n triangles).
//!
//! ```text
//!   split_edge              split_face
//!        v1                     c
//!       /|\                    /|\
//!      / | \                  / | \
//!   v2 --p-- v0              /  p  \
//!      \ | /                / /   \ \
//!       \|/                a ------- b
//!        v3
//! ```

use glam::DVec3;

use super::error::EditError;
use super::storage::EditMesh;
use crate::ids::{EdgeId, FaceId, VertexId};

impl EditMesh {
    /// Checks the preconditions of [`split_edge`](Self::split_edge): `e` is live and
    /// each face at it is a triangle (a boundary edge has one).
    ///
    /// # Errors
    /// [`EditError::NoSuchEdge`], [`EditError::NotTriangle`].
    pub fn check_split_edge(&self, e: EdgeId) -> Result<(), EditError> {
        self.live_edge(e)?;
        let [h, t] = e.halfedges();
        self.triangle_or_boundary(h)?;
        self.triangle_or_boundary(t)
    }

    /// Whether [`split_edge`](Self::split_edge) would accept `e`.
    #[must_use]
    pub fn is_split_edge_ok(&self, e: EdgeId) -> bool {
        self.check_split_edge(e).is_ok()
    }

    /// Splits edge `e` at a new vertex placed at `p`, and each triangle at the edge into
    /// two by joining the new vertex to the opposite corner. Returns the new vertex.
    ///
    /// With `[v2, v0] = edge_vertices(e)`, edge `e` keeps the half from the new vertex to
    /// `v0`; the half to `v2` is a new edge. Properties: the new vertex gets the values
    /// of `v2` and `v0` interpolated at `t`, the parameter of `p` projected onto the
    /// segment `v2 → v0` and clamped to `[0, 1]` (½ for a zero-length edge) — the
    /// default for types that do not interpolate; both halves of the edge keep `e`'s
    /// value (each halfedge its parent's); the new triangle on each side copies the
    /// values of the triangle it was cut from; the edges to the opposite corners get the
    /// defaults. With k faces at the edge (1 or 2), V, E and F grow by 1, 1 + k and k.
    ///
    /// # Errors
    /// Those of [`check_split_edge`](Self::check_split_edge); the mesh is then unchanged.
    ///
    /// # Complexity
    /// O(1).
    pub fn split_edge(&mut self, e: EdgeId, p: DVec3) -> Result<VertexId, EditError> {
        self.check_split_edge(e)?;
        let [h0, o0] = e.halfedges();
        let v2 = self.to_vertex(o0);
        let v0 = self.to_vertex(h0);
        let t = segment_parameter(self.position(v2), self.position(v0), p);

        let vh = self.new_vertex(p);
        self.props
            .vertex()
            .interpolate(v2.index(), v0.index(), t, vh.index());
        let e1 = self.new_edge(vh, v2);
        let t1 = e1.twin();
        self.props.edge().copy(e.index(), e1.edge().index());
        self.props.halfedge().copy(o0.index(), e1.index());
        self.props.halfedge().copy(h0.index(), t1.index());

        let f0 = self.face(h0);
        let f3 = self.face(o0);
        self.set_outgoing(vh, Some(h0));
        self.set_to(o0, vh);

        match f0 {
            Some(f0) => {
                let h1 = self.next(h0);
                let h2 = self.next(h1);
                let v1 = self.to_vertex(h1);
                let e0 = self.new_edge(vh, v1);
                let t0 = e0.twin();
                let f1 = self.new_face(h2);
                self.props.face().copy(f0.index(), f1.index());
                self.set_face_halfedge(f0, h0);
                self.set_face(t0, Some(f0));
                self.set_face(h2, Some(f1));
                self.set_face(t1, Some(f1));
                self.set_face(e0, Some(f1));
                self.link(h0, h1);
                self.link(h1, t0);
                self.link(t0, h0);
                self.link(e0, h2);
                self.link(h2, t1);
                self.link(t1, e0);
            }
            None => {
                let p0 = self.prev(h0);
                self.link(p0, t1);
                self.link(t1, h0);
            }
        }

        match f3 {
            Some(f3) => {
                let o1 = self.next(o0);
                let o2 = self.next(o1);
                let v3 = self.to_vertex(o1);
                let e2 = self.new_edge(vh, v3);
                let t2 = e2.twin();
                let f2 = self.new_face(o1);
                self.props.face().copy(f3.index(), f2.index());
                self.set_face_halfedge(f3, o0);
                self.set_face(o1, Some(f2));
                self.set_face(t2, Some(f2));
                self.set_face(e1, Some(f2));
                self.set_face(e2, Some(f3));
                self.link(e1, o1);
                self.link(o1, t2);
                self.link(t2, e1);
                self.link(o0, e2);
                self.link(e2, o2);
                self.link(o2, o0);
            }
            None => {
                let n0 = self.next(o0);
                self.link(e1, n0);
                self.link(o0, e1);
                self.set_outgoing(vh, Some(e1));
            }
        }

        if self.outgoing_halfedge(v2) == Some(h0) {
            self.set_outgoing(v2, Some(t1));
        }
        Ok(vh)
    }

    /// Splits face `f` at a new vertex placed at `p`: the face becomes a fan of
    /// triangles around the vertex, one per edge of the face (1 → 3 for a triangle).
    /// Returns the new vertex. Always possible on a live face.
    ///
    /// Properties: the new vertex gets the face's corner values blended by the
    /// barycentric coordinates of `p` projected onto the triangle's plane (clamped to the
    /// triangle; equal weights for a polygon or a degenerate triangle) — the default for
    /// types that do not interpolate; every triangle of the fan copies the face's values
    /// (the face keeps its id as one of them); the new edges and their halfedges get the
    /// defaults. With n vertices in the face, V, E and F grow by 1, n and n − 1.
    ///
    /// # Errors
    /// [`EditError::NoSuchFace`] when `f` is not a live face; the mesh is then unchanged.
    ///
    /// # Complexity
    /// O(n).
    pub fn split_face(&mut self, f: FaceId, p: DVec3) -> Result<VertexId, EditError> {
        self.live_face(f)?;
        let corners: Vec<VertexId> = self.vertices_around_face(f).collect();
        let weights = corner_weights(
            &corners
                .iter()
                .map(|&c| self.position(c))
                .collect::<Vec<_>>(),
            p,
        );

        let v = self.new_vertex(p);
        // Blend pairwise: the running value holds the normalised blend of the corners
        // seen so far; each step brings in one more corner at its share.
        let mut acc = 0.0;
        for (i, (&c, &w)) in corners.iter().zip(&weights).enumerate() {
            if i == 0 {
                self.props.vertex().copy(c.index(), v.index());
                acc = w;
                continue;
            }
            acc += w;
            let t = if acc > 0.0 { w / acc } else { 0.0 };
            self.props
                .vertex()
                .interpolate(v.index(), c.index(), t, v.index());
        }

        let hend = self.face_halfedge(f);
        let mut h = self.next(hend);
        let first = self.new_edge(self.to_vertex(hend), v);
        self.link(hend, first);
        self.set_face(first, Some(f));
        let mut hold = first.twin();
        while h != hend {
            let hnext = self.next(h);
            let fnew = self.new_face(h);
            self.props.face().copy(f.index(), fnew.index());
            let hnew = self.new_edge(self.to_vertex(h), v);
            self.link(hnew, hold);
            self.link(hold, h);
            self.link(h, hnew);
            self.set_face(hnew, Some(fnew));
            self.set_face(hold, Some(fnew));
            self.set_face(h, Some(fnew));
            hold = hnew.twin();
            h = hnext;
        }
        self.link(hold, hend);
        self.link(first, hold);
        self.set_face(hold, Some(f));
        self.set_face_halfedge(f, hend);
        self.set_outgoing(v, Some(hold));
        Ok(v)
    }
}

/// The parameter of `p` projected onto the segment `a → b`, clamped to `[0, 1]`; ½ for a
/// zero-length segment.
fn segment_parameter(a: DVec3, b: DVec3, p: DVec3) -> f64 {
    let d = b - a;
    let len2 = d.length_squared();
    if len2 > 0.0 && len2.is_finite() {
        let t = (p - a).dot(d) / len2;
        if t.is_finite() {
            return t.clamp(0.0, 1.0);
        }
    }
    0.5
}

/// Barycentric weights of `p` in a triangle (projected onto its plane, negative ones set
/// to zero, renormalised); equal weights for a polygon or a degenerate triangle.
fn corner_weights(corners: &[DVec3], p: DVec3) -> Vec<f64> {
    let equal = vec![1.0 / corners.len() as f64; corners.len()];
    let [a, b, c] = match corners {
        [a, b, c] => [*a, *b, *c],
        _ => return equal,
    };
    let n = (b - a).cross(c - a);
    let area2 = n.length_squared();
    if !(area2 > 0.0 && area2.is_finite()) {
        return equal;
    }
    let wa = (c - b).cross(p - b).dot(n) / area2;
    let wb = (a - c).cross(p - c).dot(n) / area2;
    let wc = (b - a).cross(p - a).dot(n) / area2;
    let w = [wa.max(0.0), wb.max(0.0), wc.max(0.0)];
    let sum: f64 = w.iter().sum();
    if sum > 0.0 && sum.is_finite() {
        w.iter().map(|x| x / sum).collect()
    } else {
        equal
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_parameter_projects_and_clamps() {
        let (a, b) = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(segment_parameter(a, b, DVec3::new(0.5, 3.0, 0.0)), 0.25);
        assert_eq!(segment_parameter(a, b, DVec3::new(-1.0, 0.0, 0.0)), 0.0);
        assert_eq!(segment_parameter(a, a, DVec3::X), 0.5);
    }

    #[test]
    fn corner_weights_are_barycentric() {
        let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let w = corner_weights(&tri, DVec3::new(0.25, 0.5, 7.0));
        let expect = [0.25, 0.25, 0.5];
        for (x, e) in w.iter().zip(expect) {
            assert!((x - e).abs() < 1e-15, "{w:?}");
        }
        assert_eq!(
            corner_weights(&[DVec3::ZERO; 3], DVec3::X),
            vec![1.0 / 3.0; 3]
        );
    }
}
