//! Connected components, Euler characteristic and genus.

use petgraph::unionfind::UnionFind;

use crate::ids::VertexId;
use crate::map::{FaceMap, VertexMap};
use crate::mesh::HalfedgeMesh;

/// The connected components of a mesh: vertices joined by edges. An isolated vertex is a
/// component of its own. Components are numbered by their lowest vertex.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Components {
    /// The component of each vertex.
    pub vertex_component: VertexMap<u32>,
    /// The component of each face.
    pub face_component: FaceMap<u32>,
    /// Size and shape of each component, indexed by component number.
    pub summaries: Vec<ComponentSummary>,
}

impl Components {
    /// The number of components.
    #[must_use]
    pub fn count(&self) -> usize {
        self.summaries.len()
    }
}

/// Element counts and topological invariants of one connected component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ComponentSummary {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of edges.
    pub edges: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of boundary loops.
    pub boundary_loops: usize,
}

impl ComponentSummary {
    /// `V − E + F` of the component.
    #[must_use]
    pub fn euler_characteristic(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.faces as i64
    }

    /// Whether the component has faces and no boundary.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.faces > 0 && self.boundary_loops == 0
    }

    /// The genus g of the component as an orientable surface with b boundary loops,
    /// from χ = 2 − 2g − b. `None` for an isolated vertex (not a surface).
    #[must_use]
    pub fn genus(&self) -> Option<u32> {
        if self.faces == 0 {
            return None;
        }
        let twice = 2 - self.euler_characteristic() - self.boundary_loops as i64;
        u32::try_from(twice / 2).ok()
    }
}

impl HalfedgeMesh {
    /// Labels the connected components (vertices joined by edges; isolated vertices count).
    ///
    /// # Complexity
    /// O(E α(V)) with petgraph's union-find, plus one pass over the boundary.
    #[must_use]
    pub fn connected_components(&self) -> Components {
        let mut uf = UnionFind::<u32>::new(self.n_vertices());
        for e in self.edges() {
            let [a, b] = self.edge_vertices(e);
            uf.union(a.raw(), b.raw());
        }
        let mut label_of_root = vec![u32::MAX; self.n_vertices()];
        let mut vertex_component = self.vertex_map(0u32);
        let mut summaries: Vec<ComponentSummary> = Vec::new();
        for v in self.vertices() {
            let root = uf.find(v.raw()) as usize;
            if label_of_root[root] == u32::MAX {
                label_of_root[root] = summaries.len() as u32;
                summaries.push(ComponentSummary {
                    vertices: 0,
                    edges: 0,
                    faces: 0,
                    boundary_loops: 0,
                });
            }
            let c = label_of_root[root];
            vertex_component[v] = c;
            summaries[c as usize].vertices += 1;
        }
        for e in self.edges() {
            let [a, _] = self.edge_vertices(e);
            summaries[vertex_component[a] as usize].edges += 1;
        }
        let mut face_component = self.face_map(0u32);
        for f in self.faces() {
            let c = vertex_component[self.to_vertex(self.face_halfedge(f))];
            face_component[f] = c;
            summaries[c as usize].faces += 1;
        }
        for l in self.boundary_loops() {
            let v: VertexId = self.to_vertex(l[0]);
            summaries[vertex_component[v] as usize].boundary_loops += 1;
        }
        Components {
            vertex_component,
            face_component,
            summaries,
        }
    }

    /// The genus of a closed, connected mesh (χ = 2 − 2g); `None` when the mesh is open,
    /// empty or has more than one component. Per-component genera are in
    /// [`connected_components`](Self::connected_components).
    #[must_use]
    pub fn genus(&self) -> Option<u32> {
        let components = self.connected_components();
        match components.summaries.as_slice() {
            [only] if only.is_closed() => only.genus(),
            _ => None,
        }
    }
}
