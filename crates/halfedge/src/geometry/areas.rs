//! Vertex areas: the share of the surface that a vertex stands for.

use super::Geometry;
use crate::error::TopologyError;
use crate::ids::VertexId;
use crate::map::VertexMap;

/// How the area around a vertex is measured (the `A_i` of an area-normalised Laplacian,
/// `1 / (2 A_i)`).
///
/// Both kinds split every face among its vertices, so over all vertices they sum to the
/// surface area (mixed Voronoi: less the area of degenerate triangles, each below
/// `½ DEGENERACY_RATIO × (longest edge)²`).
///
/// # References
/// M. Meyer, M. Desbrun, P. Schröder, A. H. Barr: *Discrete differential-geometry
/// operators for triangulated 2-manifolds*. Visualization and Mathematics III, 2003,
/// Section 3.3 and Fig. 4.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum VertexAreaKind {
    /// One third of each incident triangle's area (`1/k` of a `k`-gon's area).
    Barycentric,
    /// Meyer et al.'s mixed Voronoi area (their Fig. 4), per incident triangle: for a
    /// non-obtuse triangle the Voronoi area `⅛ (|p_i p_k|² cot θ_j + |p_i p_j|² cot θ_k)`,
    /// where `j` and `k` are the other two corners; for an obtuse triangle `A/2` when the
    /// obtuse angle is at the vertex and `A/4` otherwise. A right triangle counts as
    /// non-obtuse (both rules agree there). Degenerate triangles contribute 0. Needs
    /// triangles.
    MixedVoronoi,
}

impl Geometry<'_> {
    /// The area of vertex `v` in unit² under `kind`: the sum of its shares of the incident
    /// faces, added counter-clockwise (in
    /// [`faces_around_vertex`](crate::HalfedgeMesh::faces_around_vertex) order). 0.0 for an
    /// isolated vertex.
    ///
    /// A face that is not a triangle contributes its barycentric share `A/k` under either
    /// kind; [`vertex_areas`](Self::vertex_areas) rejects such meshes for
    /// [`VertexAreaKind::MixedVoronoi`] instead.
    ///
    /// # Panics
    /// If `v` is not a vertex of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
    /// use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
    /// // An obtuse triangle of area 2 with the obtuse angle at vertex 2.
    /// let mesh = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 2]])?;
    /// let positions = [DVec3::ZERO, DVec3::new(4.0, 0.0, 0.0), DVec3::new(2.0, 1.0, 0.0)];
    /// let geometry = Geometry::new(&mesh, &positions)?;
    /// let mixed = |v| geometry.vertex_area(VertexId::new(v), VertexAreaKind::MixedVoronoi);
    /// assert_eq!((mixed(0), mixed(1), mixed(2)), (0.5, 0.5, 1.0));
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    ///
    /// # References
    /// Meyer, Desbrun, Schröder, Barr 2003, Fig. 4.
    #[must_use]
    pub fn vertex_area(&self, v: VertexId, kind: VertexAreaKind) -> f64 {
        let m = self.mesh;
        let mut area = 0.0;
        for h in m.halfedges_around_vertex(v) {
            let Some(f) = m.face(h) else { continue };
            let share = match (kind, self.triangle(f)) {
                (VertexAreaKind::Barycentric, Some(t)) => t.area() / 3.0,
                (VertexAreaKind::MixedVoronoi, Some(t)) => {
                    // The corner at v is where the halfedge entering v ends; the face's
                    // halfedge ends at corner 0.
                    let entering = m.prev(h);
                    let h0 = m.face_halfedge(f);
                    let corner = if entering == h0 {
                        0
                    } else if entering == m.next(h0) {
                        1
                    } else {
                        2
                    };
                    t.mixed_area(corner)
                }
                (_, None) => self.face_area(f) / m.face_valence(f) as f64,
            };
            area += share;
        }
        area
    }

    /// The area of every vertex in unit² under `kind` (see
    /// [`vertex_area`](Self::vertex_area)); each entry is bit-identical to the per-vertex
    /// query.
    ///
    /// # Errors
    /// [`TopologyError::NotTriangle`] for [`VertexAreaKind::MixedVoronoi`] when a face is
    /// not a triangle (the first such face is named).
    ///
    /// # Complexity
    /// O(V + H), in parallel with fixed chunks (see
    /// [`vertex_areas_into`](Self::vertex_areas_into)).
    pub fn vertex_areas(&self, kind: VertexAreaKind) -> Result<VertexMap<f64>, TopologyError> {
        let mut areas = vec![0.0; self.mesh.n_vertices()];
        self.vertex_areas_into(kind, &mut areas)?;
        Ok(VertexMap::from_vec(areas))
    }
}
