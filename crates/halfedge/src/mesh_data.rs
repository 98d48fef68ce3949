//! [`MeshData`]: positions and faces, the exchange type of the whole workspace.

use glam::DVec3;

use crate::error::TopologyError;
use crate::mesh::HalfedgeMesh;
use crate::polygons::PolygonList;

/// Vertex positions and polygon faces: what a file holds, what a procedural
/// primitive or test surface is made of, and what a repair returns.
///
/// Coordinates are in whatever unit the source uses (typically millimetres for scans);
/// nothing in the workspace ever scales them. Faces are 0-based indices into
/// `positions`, counter-clockwise seen from the outside. The half-edge connectivity is
/// built on demand with [`mesh`](Self::mesh); the positions stay here, beside it.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{DVec3, MeshData, PolygonList};
/// let data = MeshData {
///     positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
///     faces: PolygonList::from_triangles(&[[0, 1, 2]]),
/// };
/// let mesh = data.mesh()?;
/// assert_eq!((mesh.n_vertices(), mesh.n_faces()), (3, 1));
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Faces as vertex-index lists.
    pub faces: PolygonList,
}

impl MeshData {
    /// Positions and faces together.
    #[must_use]
    pub fn new(positions: Vec<DVec3>, faces: PolygonList) -> Self {
        Self { positions, faces }
    }

    /// Builds the half-edge connectivity of the faces over `positions.len()` vertices.
    ///
    /// # Errors
    /// Those of [`HalfedgeMesh::from_polygon_list`]: anything that is not an oriented
    /// 2-manifold, named by input index ([`repair`](crate::repair) fixes what can be
    /// fixed).
    pub fn mesh(&self) -> Result<HalfedgeMesh, TopologyError> {
        HalfedgeMesh::from_polygon_list(self.positions.len(), &self.faces)
    }
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
