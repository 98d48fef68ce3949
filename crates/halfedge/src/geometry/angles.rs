//! Corner queries: interior angles and cotangents.

use super::Geometry;
use super::kernel::Corner;
use crate::ids::{FaceId, HalfedgeId};

impl Geometry<'_> {
    /// The interior angle of the face corner at `to_vertex(h)`, in radians in `[0, π]`:
    /// the angle between `h` reversed and `next(h)`. 0.0 for a boundary halfedge, which has
    /// no face corner, so summing `corner_angle` over the incoming halfedges of a vertex
    /// gives the vertex's angle sum.
    ///
    /// With `u` and `v` the edge vectors leaving the corner, the angle is
    /// `atan2(|u × v|, u · v)`, accurate for every angle and 0 when an edge has zero
    /// length. At a reflex corner of a non-convex polygon it is the angle between the two
    /// edges (below π), not the interior angle.
    ///
    /// # Panics
    /// If `h` is not a halfedge of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{primitives, VertexId};
    /// let hexagon = primitives::hexagon_fan();
    /// let mesh = hexagon.mesh()?;
    /// let geometry = Geometry::new(&mesh, &hexagon.positions)?;
    /// // The six corners at the centre of the hexagon make a full turn.
    /// let centre = VertexId::new(0);
    /// let sum: f64 = mesh
    ///     .halfedges_around_vertex(centre)
    ///     .map(|h| geometry.corner_angle(h.twin()))
    ///     .sum();
    /// assert!((sum - std::f64::consts::TAU).abs() < 1e-14);
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    #[must_use]
    pub fn corner_angle(&self, h: HalfedgeId) -> f64 {
        if self.mesh.is_boundary_halfedge(h) {
            return 0.0;
        }
        self.corner(h).angle()
    }

    /// The angle in radians at the vertex opposite `h` in its triangle (the corner at
    /// `to_vertex(next(h))`), or `None` when `h` is a boundary halfedge or its face is not a
    /// triangle.
    ///
    /// Computed as in [`corner_angle`](Self::corner_angle); finite for degenerate
    /// triangles too (a collinear triangle has angles 0, 0 and π).
    ///
    /// # Panics
    /// If `h` is not a halfedge of the mesh.
    #[must_use]
    pub fn opposite_angle(&self, h: HalfedgeId) -> Option<f64> {
        let f = self.mesh.face(h)?;
        self.triangle(f)?;
        Some(self.corner(self.mesh.next(h)).angle())
    }

    /// The cotangent of the angle opposite `h` in its triangle (see
    /// [`opposite_angle`](Self::opposite_angle)), the term of the cotangent Laplacian
    /// weight of `h`'s edge that comes from `h`'s face.
    ///
    /// With `u` and `v` the edge vectors leaving the opposite corner, the cotangent is
    /// `(u · v) / |u × v|`. It is 0.0 for a boundary halfedge, for a face that is not a
    /// triangle and for a degenerate triangle (see
    /// [`is_degenerate_face`](Self::is_degenerate_face)); otherwise it is finite (below
    /// about 10¹² in magnitude) and negative for an obtuse angle.
    ///
    /// # Panics
    /// If `h` is not a halfedge of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{primitives, HalfedgeId};
    /// let hexagon = primitives::hexagon_fan();
    /// let mesh = hexagon.mesh()?;
    /// let geometry = Geometry::new(&mesh, &hexagon.positions)?;
    /// for h in mesh.halfedges() {
    ///     let cot = geometry.opposite_cotangent(h);
    ///     if mesh.is_boundary_halfedge(h) {
    ///         assert_eq!(cot, 0.0);
    ///     } else {
    ///         assert!((cot - 1.0 / 3f64.sqrt()).abs() < 1e-14); // cot 60°
    ///     }
    /// }
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    ///
    /// # References
    /// Meyer, Desbrun, Schröder, Barr 2003, Eq. 5 (the cotangent formula).
    #[must_use]
    pub fn opposite_cotangent(&self, h: HalfedgeId) -> f64 {
        let Some(f) = self.mesh.face(h) else {
            return 0.0;
        };
        match self.triangle(f) {
            Some(t) if !t.is_degenerate() => self.corner(self.mesh.next(h)).cot(),
            _ => 0.0,
        }
    }

    /// The cotangents opposite the three halfedges of triangle `f`, as `(h, cot)` pairs
    /// in face order: bit for bit what [`opposite_cotangent`](Self::opposite_cotangent)
    /// gives for each `h`, with the degeneracy test done once per face. `None` when `f`
    /// is not a triangle (its cotangents are then 0).
    ///
    /// # Panics
    /// If `f` is not a face of the mesh.
    #[must_use]
    pub fn face_opposite_cotangents(&self, f: FaceId) -> Option<[(HalfedgeId, f64); 3]> {
        let t = self.triangle(f)?;
        let h0 = self.mesh.face_halfedge(f);
        let h1 = self.mesh.next(h0);
        let h2 = self.mesh.next(h1);
        if t.is_degenerate() {
            return Some([(h0, 0.0), (h1, 0.0), (h2, 0.0)]);
        }
        // h0 ends at vertex 0, so the corner opposite it is vertex 1; likewise h1 ↔ 2 and
        // h2 ↔ 0. A corner's products do not depend on the order of its two edges, so
        // these are the bits `opposite_cotangent` computes.
        Some([
            (h0, t.corner(1).cot()),
            (h1, t.corner(2).cot()),
            (h2, t.corner(0).cot()),
        ])
    }

    /// The products of the edge vectors leaving the corner at `to_vertex(h)`: towards
    /// `from_vertex(h)` and towards `to_vertex(next(h))`.
    #[inline]
    pub(super) fn corner(&self, h: HalfedgeId) -> Corner {
        let m = self.mesh;
        Corner::new(
            self.position(m.to_vertex(h)),
            self.position(m.from_vertex(h)),
            self.position(m.to_vertex(m.next(h))),
        )
    }
}
