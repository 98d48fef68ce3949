//! Conversion between [`EditMesh`] and the frozen [`HalfedgeMesh`] + positions, in O(n).

use glam::DVec3;

use super::properties::Properties;
use super::storage::EditMesh;
use crate::error::TopologyError;
use crate::ids::VertexId;
use crate::mesh::HalfedgeMesh;
use crate::mesh_data::MeshData;
use crate::polygons::PolygonList;

impl EditMesh {
    /// An editable copy of `mesh` with `positions` (one per vertex); ids are kept, no
    /// properties yet.
    ///
    /// # Errors
    /// [`TopologyError::PositionCount`] when `positions.len() != mesh.n_vertices()`.
    ///
    /// # Complexity
    /// O(V + H + F): the arrays are copied.
    pub fn from_mesh(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<Self, TopologyError> {
        if positions.len() != mesh.n_vertices() {
            return Err(TopologyError::PositionCount {
                positions: positions.len(),
                vertices: mesh.n_vertices(),
            });
        }
        Ok(Self {
            v_out: mesh.v_out.clone(),
            v_pos: positions.to_vec(),
            v_deleted: vec![false; mesh.n_vertices()],
            h_to: mesh.h_to.clone(),
            h_next: mesh.h_next.clone(),
            h_prev: mesh.h_prev.clone(),
            h_face: mesh.h_face.clone(),
            e_deleted: vec![false; mesh.n_edges()],
            f_he: mesh.f_he.clone(),
            f_deleted: vec![false; mesh.n_faces()],
            deleted_vertices: 0,
            deleted_edges: 0,
            deleted_faces: 0,
            props: Properties::new(mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()),
        })
    }

    /// Builds an editable mesh from positions and faces, as
    /// [`HalfedgeMesh::from_polygons`] does.
    ///
    /// # Errors
    /// Those of [`HalfedgeMesh::from_polygons`].
    pub fn from_mesh_data(data: &MeshData) -> Result<Self, TopologyError> {
        Self::from_mesh(&data.mesh()?, &data.positions)
    }

    /// The live mesh as a frozen [`HalfedgeMesh`] and its positions, renumbered as
    /// [`garbage_collection`](Self::garbage_collection) would (this mesh is not changed;
    /// collect first to make the property values line up by index).
    ///
    /// # Errors
    /// [`TopologyError::NonManifoldVertex`] for a vertex with more than one fan (which
    /// [`add_face`](Self::add_face) and [`delete_face`](Self::delete_face) may leave on
    /// the way), with its index after renumbering; [`TopologyError::Integrity`] if a
    /// half-edge invariant does not hold (a bug, never expected).
    ///
    /// # Complexity
    /// O(V + H + F).
    pub fn to_mesh(&self) -> Result<(HalfedgeMesh, Vec<DVec3>), TopologyError> {
        let c = self.compacted();
        let mesh = HalfedgeMesh {
            v_out: c.v_out,
            h_to: c.h_to,
            h_next: c.h_next,
            h_prev: c.h_prev,
            h_face: c.h_face,
            f_he: c.f_he,
        };
        mesh.check_integrity()?;
        for v in mesh.vertices() {
            let fans = mesh
                .halfedges_around_vertex(v)
                .filter(|&h| mesh.is_boundary_halfedge(h))
                .count();
            if fans > 1 {
                return Err(TopologyError::NonManifoldVertex {
                    vertex: v.raw(),
                    fans,
                });
            }
        }
        Ok((mesh, c.v_pos))
    }

    /// [`to_mesh`](Self::to_mesh), consuming the mesh.
    ///
    /// # Errors
    /// Those of [`to_mesh`](Self::to_mesh).
    pub fn into_mesh(self) -> Result<(HalfedgeMesh, Vec<DVec3>), TopologyError> {
        self.to_mesh()
    }

    /// The live positions and faces (counter-clockwise vertex lists), renumbered as
    /// [`garbage_collection`](Self::garbage_collection) would: what a writer takes. Not
    /// validated (see [`to_mesh`](Self::to_mesh)).
    ///
    /// # Complexity
    /// O(V + H + F).
    #[must_use]
    pub fn to_mesh_data(&self) -> MeshData {
        let mut new_index = vec![u32::MAX; self.vertex_capacity()];
        let mut positions = Vec::with_capacity(self.n_vertices());
        for v in self.vertices() {
            new_index[v.index()] = positions.len() as u32;
            positions.push(self.position(v));
        }
        let mut faces = PolygonList::with_capacity(self.n_faces(), 3 * self.n_faces());
        let mut buf = Vec::new();
        for f in self.faces() {
            buf.clear();
            buf.extend(
                self.vertices_around_face(f)
                    .map(|v: VertexId| new_index[v.index()]),
            );
            faces.push(&buf);
        }
        MeshData { positions, faces }
    }
}
