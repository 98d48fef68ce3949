//! A generated test surface.

use beltrami_halfedge::{DVec3, HalfedgeMesh, PolygonList, TopologyError};

/// A generated surface: positions, counter-clockwise faces (normals outwards for the
/// closed ones, towards +z for the F-lens), and the unit its coordinates are in.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// The surface's name (`"flens"`, `"sphere"`, `"block"`, `"golfball"`).
    pub name: &'static str,
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Triangles, counter-clockwise.
    pub faces: PolygonList,
    /// The length unit of the coordinates (`"mm"`, or `"1"` for the unit sphere).
    pub unit: &'static str,
}

impl Surface {
    /// Builds the half-edge connectivity.
    ///
    /// # Errors
    /// Never for the surfaces of this crate (they are valid by construction and tested);
    /// the `Result` is that of [`HalfedgeMesh::from_polygons`].
    pub fn mesh(&self) -> Result<HalfedgeMesh, TopologyError> {
        HalfedgeMesh::from_polygons(self.positions.len(), self.faces.iter())
    }
}
