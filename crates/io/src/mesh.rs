//! The mesh data the readers return and the writers take.

use beltrami_halfedge::PolygonList;
use beltrami_halfedge::primitives::Primitive;
use glam::DVec3;

/// Vertex positions and polygon faces, as stored in a file.
///
/// Coordinates are whatever the file holds (typically millimetres for scans); no
/// reader or writer ever scales them. Faces are 0-based indices into `positions`,
/// counter-clockwise seen from the outside. Readers check that every index is in
/// range and every coordinate finite, but leave faces with fewer than three vertices
/// or repeated vertices for [`HalfedgeMesh::from_polygons`] to report.
///
/// [`HalfedgeMesh::from_polygons`]: beltrami_halfedge::HalfedgeMesh::from_polygons
///
/// # Examples
/// ```
/// use beltrami_io::{MeshData, PolygonList};
/// use glam::DVec3;
/// let mesh = MeshData {
///     positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
///     faces: PolygonList::from_triangles(&[[0, 1, 2]]),
/// };
/// assert_eq!(mesh.faces.len(), 1);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Faces as vertex-index lists.
    pub faces: PolygonList,
}

impl Default for MeshData {
    /// No vertices, no faces (the face list of [`PolygonList::new`]).
    fn default() -> Self {
        Self {
            positions: Vec::new(),
            faces: PolygonList::new(),
        }
    }
}

impl From<Primitive> for MeshData {
    fn from(primitive: Primitive) -> Self {
        Self {
            positions: primitive.positions,
            faces: primitive.faces,
        }
    }
}
