//! Vertex normals: mean, area-weighted and angle-weighted averages of face normals.

use glam::DVec3;

use super::Geometry;
use super::kernel::{ScaledSum, unit_or_zero};
use crate::ids::{FaceId, HalfedgeId, VertexId};
use crate::map::{FaceMap, VertexMap};

/// How face normals are averaged into a vertex normal.
///
/// Every weighting sums its terms over the faces around the vertex and normalises the sum
/// (`n * (1.0 / |n|)`, as OpenMesh does); the result is a unit vector, or
/// [`DVec3::ZERO`] when the sum vanishes (an isolated vertex, a vertex whose faces are all
/// degenerate, or normals that cancel).
///
/// The faces are visited in OpenMesh's order, that of its default vertex-face circulator
/// started at OpenMesh's outgoing halfedge: clockwise, starting at a boundary vertex from
/// the face beside the boundary edge that leaves the vertex, and at an interior vertex
/// from the face with the largest id (OpenMesh's `add_face` leaves the outgoing halfedge
/// of an interior vertex in the face that closed its fan, the last one added). The order
/// matters only for the last bit of the sum.
///
/// # References
/// G. Thürmer, C. A. Wüthrich: *Computing vertex normals from polygonal facets*. Journal
/// of Graphics Tools 3(1), 1998.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum NormalWeighting {
    /// The unweighted sum of the unit face normals
    /// ([`face_normal`](Geometry::face_normal)): what OpenMesh's `update_normals` computes
    /// (`calc_vertex_normal_fast`), bit for bit when OpenMesh built the mesh from the same
    /// face list in the same order. A degenerate face adds its normal like any other face
    /// (the zero vector when its vertices are exactly collinear).
    Mean,
    /// The sum of the face vector areas ([`face_vector_area`](Geometry::face_vector_area)):
    /// each unit normal weighted by its face's area. Degenerate faces add nothing.
    Area,
    /// The sum of the unit face normals each weighted by the face's interior angle at the
    /// vertex ([`corner_angle`](Geometry::corner_angle)), after Thürmer and Wüthrich: the
    /// result does not change when a planar face is split into triangles (the cube's
    /// corners get the diagonal however their sides are split). Degenerate faces add
    /// nothing.
    Angle,
}

impl Geometry<'_> {
    /// The unit normal of vertex `v` under `weighting`, or [`DVec3::ZERO`] for an isolated
    /// vertex or when the weighted sum vanishes. Never NaN.
    ///
    /// # Panics
    /// If `v` is not a vertex of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::{Geometry, NormalWeighting};
    /// use beltrami_halfedge::{primitives, DVec3, VertexId};
    /// let cube = primitives::cube();
    /// let mesh = cube.mesh()?;
    /// let geometry = Geometry::new(&mesh, &cube.positions)?;
    /// // Vertex 1 = (1, 0, 0) has two triangles on the x = 1 side and one each on y = 0 and
    /// // z = 0: the mean leans towards +x, the angle-weighted normal is the cube diagonal.
    /// let v = VertexId::new(1);
    /// let mean = geometry.vertex_normal(v, NormalWeighting::Mean);
    /// let angle = geometry.vertex_normal(v, NormalWeighting::Angle);
    /// assert!((mean - DVec3::new(2.0, -1.0, -1.0) / 6f64.sqrt()).length() < 1e-15);
    /// assert!((angle - DVec3::new(1.0, -1.0, -1.0) / 3f64.sqrt()).length() < 1e-15);
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    ///
    /// # References
    /// Thürmer and Wüthrich 1998 for [`NormalWeighting::Angle`].
    #[must_use]
    pub fn vertex_normal(&self, v: VertexId, weighting: NormalWeighting) -> DVec3 {
        self.vertex_normal_with(v, weighting, |f| self.face_normal(f))
    }

    /// The unit normal of every vertex under `weighting` (see
    /// [`vertex_normal`](Self::vertex_normal)); each entry is bit-identical to the
    /// per-vertex query.
    ///
    /// # Complexity
    /// O(V + H); face normals are computed once.
    #[must_use]
    pub fn vertex_normals(&self, weighting: NormalWeighting) -> VertexMap<DVec3> {
        let normals: Option<FaceMap<DVec3>> = match weighting {
            NormalWeighting::Area => None,
            _ => Some(self.face_normals()),
        };
        let normal = |f: FaceId| normals.as_ref().map_or(DVec3::ZERO, |n| n[f]);
        VertexMap::from_vec(
            self.mesh
                .vertices()
                .map(|v| self.vertex_normal_with(v, weighting, normal))
                .collect(),
        )
    }

    /// The faces around `v` with the outgoing halfedge of `v` in each, in OpenMesh's
    /// vertex-face order: clockwise, boundary gaps skipped, starting where OpenMesh's
    /// outgoing halfedge of `v` is after building the mesh face by face: at a boundary
    /// vertex the outgoing boundary halfedge, at an interior vertex the halfedge leaving
    /// `v` in the face with the largest id (the face added last closes the fan).
    fn faces_clockwise(&self, v: VertexId) -> impl Iterator<Item = (HalfedgeId, FaceId)> + '_ {
        let m = self.mesh;
        let start = if m.is_boundary_vertex(v) {
            m.outgoing_halfedge(v)
        } else {
            m.halfedges_around_vertex(v).max_by_key(|&h| m.face(h))
        };
        std::iter::successors(start, move |&h| {
            let n = m.cw_rotated(h);
            (Some(n) != start).then_some(n)
        })
        .filter_map(move |h| m.face(h).map(|f| (h, f)))
    }

    fn vertex_normal_with(
        &self,
        v: VertexId,
        weighting: NormalWeighting,
        face_normal: impl Fn(FaceId) -> DVec3,
    ) -> DVec3 {
        let m = self.mesh;
        let faces = self.faces_clockwise(v);
        match weighting {
            NormalWeighting::Mean => {
                let mut sum = DVec3::ZERO;
                for (_, f) in faces {
                    sum += face_normal(f);
                }
                unit_or_zero(sum)
            }
            NormalWeighting::Area => {
                // Twice the vector areas, each in its own power-of-two unit, so that the
                // direction survives areas beyond the range of f64. With unit 1 (the
                // usual case) this is the plain sum.
                let mut sum = ScaledSum::default();
                for (_, f) in faces {
                    let (c, unit) = match self.triangle(f) {
                        Some(t) if t.is_degenerate() => continue,
                        Some(t) => t.double_vector_area(),
                        None => {
                            let p = self.polygon(f);
                            if p.is_degenerate() {
                                continue;
                            }
                            p.double_vector_area()
                        }
                    };
                    sum.add(c, unit);
                }
                sum.direction()
            }
            NormalWeighting::Angle => {
                let mut sum = DVec3::ZERO;
                for (h, f) in faces {
                    if !self.is_degenerate_face(f) {
                        // The corner at v is the one at the end of the halfedge entering v.
                        sum += face_normal(f) * self.corner_angle(m.prev(h));
                    }
                }
                unit_or_zero(sum)
            }
        }
    }
}
