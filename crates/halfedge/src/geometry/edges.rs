//! Edge queries: vectors and lengths.

use glam::DVec3;

use super::Geometry;
use super::kernel::{self, Sum};
use crate::ids::{EdgeId, HalfedgeId};

impl Geometry<'_> {
    /// The vector along halfedge `h`, `position(to_vertex(h)) − position(from_vertex(h))`,
    /// in the positions' unit.
    ///
    /// # Panics
    /// If `h` is not a halfedge of the mesh.
    #[inline]
    #[must_use]
    pub fn edge_vector(&self, h: HalfedgeId) -> DVec3 {
        self.position(self.mesh.to_vertex(h)) - self.position(self.mesh.from_vertex(h))
    }

    /// The length of halfedge `h`, `|x_to − x_from|`, in the positions' unit: the same
    /// bits as `edge_vector(h).length()` wherever that is accurate, and finite (rescaled
    /// by a power of two) where the plain expression would overflow or underflow.
    ///
    /// # Panics
    /// If `h` is not a halfedge of the mesh.
    #[inline]
    #[must_use]
    pub fn halfedge_length(&self, h: HalfedgeId) -> f64 {
        kernel::distance(
            self.position(self.mesh.from_vertex(h)),
            self.position(self.mesh.to_vertex(h)),
        )
    }

    /// The length of edge `e` in the positions' unit: `sqrt(x² + y² + z²)` of the vector
    /// of its halfedge `2e` (OpenMesh's `calc_edge_length`), rescaled only where that
    /// expression would overflow or underflow. Zero for coincident end points.
    ///
    /// # Panics
    /// If `e` is not an edge of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{DVec3, EdgeId, HalfedgeMesh};
    /// let mesh = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 2]])?;
    /// let positions = [DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0), DVec3::Y];
    /// let geometry = Geometry::new(&mesh, &positions)?;
    /// assert_eq!(geometry.edge_length(EdgeId::new(0)), 5.0); // edge 0 joins vertices 0 and 1
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    #[inline]
    #[must_use]
    pub fn edge_length(&self, e: EdgeId) -> f64 {
        let [from, to] = self.mesh.edge_vertices(e);
        kernel::distance(self.position(from), self.position(to))
    }

    /// The mean edge length in the positions' unit, or `None` for a mesh without edges.
    /// Compensated summation.
    ///
    /// # Complexity
    /// O(E).
    #[must_use]
    pub fn mean_edge_length(&self) -> Option<f64> {
        let n = self.mesh.n_edges();
        if n == 0 {
            return None;
        }
        let mut sum = Sum::default();
        for e in self.mesh.edges() {
            sum.add(self.edge_length(e));
        }
        let mean = sum.value() / n as f64;
        if mean.is_finite() {
            return Some(mean);
        }
        // The total overflowed although the mean may be representable.
        let mut sum = Sum::default();
        for e in self.mesh.edges() {
            sum.add(self.edge_length(e) / n as f64);
        }
        Some(sum.value())
    }
}
