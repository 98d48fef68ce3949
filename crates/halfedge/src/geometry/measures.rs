//! Whole-mesh measures: bounding box, surface area, enclosed volume, centroid.

use glam::DVec3;

use super::Geometry;
use super::kernel::{Frame, Sum, VecSum, ldexp};
use crate::error::TopologyError;
use crate::ids::FaceId;

impl Geometry<'_> {
    /// The axis-aligned bounding box `(min, max)` of all vertices (isolated ones
    /// included), or `None` for a mesh without vertices.
    ///
    /// # Complexity
    /// O(V).
    #[must_use]
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        let (&first, rest) = self.positions.split_first()?;
        Some(
            rest.iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }

    /// The total area of all faces in unit² (the sum of
    /// [`face_area`](Self::face_area)), compensated summation. 0.0 without faces.
    ///
    /// # Complexity
    /// O(F + H).
    #[must_use]
    pub fn surface_area(&self) -> f64 {
        let mut sum = Sum::default();
        for f in self.mesh.faces() {
            sum.add(self.face_area(f));
        }
        sum.value()
    }

    /// The signed volume in unit³ enclosed by a closed mesh, by the divergence theorem:
    /// `Σ p0 · (p1 × p2) / 6` over all triangles, larger faces fanned from their first
    /// vertex. Positive when the faces are oriented outwards (counter-clockwise seen from
    /// outside), negative when inwards; for several closed components, the sum of their
    /// signed volumes.
    ///
    /// The result is exact for any closed polyhedral surface and does not depend on the
    /// origin. To keep it accurate far from the origin, positions are taken relative to
    /// the centre of the bounding box of the vertices that have edges; the triple products
    /// are added with compensated summation.
    ///
    /// # Errors
    /// [`TopologyError::NotClosed`] when the mesh has a boundary (isolated vertices do not
    /// count).
    ///
    /// # Complexity
    /// O(V + H).
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{primitives, TopologyError};
    /// let tetrahedron = primitives::tetrahedron(); // inscribed in the unit sphere
    /// let mesh = tetrahedron.mesh()?;
    /// let volume = Geometry::new(&mesh, &tetrahedron.positions)?.volume()?;
    /// assert!((volume - 8.0 / (9.0 * 3f64.sqrt())).abs() < 1e-15);
    ///
    /// let grid = primitives::grid(2, 2);
    /// let mesh = grid.mesh()?;
    /// let err = Geometry::new(&mesh, &grid.positions)?.volume().unwrap_err();
    /// assert_eq!(err, TopologyError::NotClosed { boundary_loops: 1 });
    /// # Ok::<(), TopologyError>(())
    /// ```
    pub fn volume(&self) -> Result<f64, TopologyError> {
        if !self.mesh.is_closed() {
            return Err(TopologyError::NotClosed {
                boundary_loops: self.mesh.boundary_loops().count(),
            });
        }
        let Some(frame) = self.centred_frame() else {
            return Ok(0.0);
        };
        let mut sum = Sum::default();
        for f in self.mesh.faces() {
            self.fan(f, &frame, |q0, q1, q2| sum.add(q0.dot(q1.cross(q2))));
        }
        Ok(ldexp(sum.value() / 6.0, 3 * frame.exponent()))
    }

    /// The centre of area of the surface: the area-weighted mean of the triangle centroids
    /// (larger faces fanned from their first vertex), or `None` when the total area is
    /// zero. Positions are taken relative to the centre of the bounding box of the vertices
    /// that have edges and summed with compensation.
    ///
    /// # Complexity
    /// O(V + H).
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{primitives, DVec3};
    /// let cube = primitives::cube();
    /// let mesh = cube.mesh()?;
    /// let centroid = Geometry::new(&mesh, &cube.positions)?.surface_centroid();
    /// assert!((centroid.unwrap() - DVec3::splat(0.5)).length() < 1e-15);
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    #[must_use]
    pub fn surface_centroid(&self) -> Option<DVec3> {
        let frame = self.centred_frame()?;
        let mut weight = Sum::default();
        let mut moment = VecSum::default();
        for f in self.mesh.faces() {
            self.fan(f, &frame, |q0, q1, q2| {
                let w = (q1 - q0).cross(q2 - q0).length();
                weight.add(w);
                moment.add((q0 + q1 + q2) * (w / 3.0));
            });
        }
        let w = weight.value();
        if w.is_nan() || w <= 0.0 {
            return None;
        }
        let offset = moment.value() / w;
        let e = frame.exponent();
        Some(
            frame.origin() + DVec3::new(ldexp(offset.x, e), ldexp(offset.y, e), ldexp(offset.z, e)),
        )
    }

    /// A frame around the centre of the bounding box of the vertices that have edges
    /// (isolated vertices, possibly far away, would only cost digits), `None` when there
    /// are none.
    fn centred_frame(&self) -> Option<Frame> {
        let m = self.mesh;
        let mut used = m
            .vertices()
            .filter(|&v| !m.is_isolated(v))
            .map(|v| self.position(v));
        let first = used.next()?;
        let (lo, hi) = used.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        let centre = lo * 0.5 + hi * 0.5;
        Some(Frame::new(centre, &[lo, hi]))
    }

    /// Calls `visit` with the scaled positions of each triangle of the fan of face `f`
    /// from its first vertex.
    fn fan(&self, f: FaceId, frame: &Frame, mut visit: impl FnMut(DVec3, DVec3, DVec3)) {
        let mut corners = self
            .mesh
            .vertices_around_face(f)
            .map(|v| frame.span(self.position(v)));
        let (Some(q0), Some(mut q1)) = (corners.next(), corners.next()) else {
            return;
        };
        for q2 in corners {
            visit(q0, q1, q2);
            q1 = q2;
        }
    }
}
