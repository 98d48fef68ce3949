//! The storage of an [`EditMesh`]: the half-edge arrays of
//! [`HalfedgeMesh`](crate::HalfedgeMesh) plus deletion marks, positions and properties.

use glam::DVec3;

use super::properties::Properties;
use crate::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::INVALID;

/// An editable half-edge mesh: connectivity, positions and typed user properties that
/// follow every edit.
///
/// Same conventions as [`HalfedgeMesh`](crate::HalfedgeMesh) (edge `e` owns halfedges
/// `2e` and `2e + 1`, the twin of `h` is `h ^ 1`, inner halfedges run counter-clockwise,
/// a boundary vertex's outgoing halfedge is a boundary halfedge), plus deletion marks in
/// the OpenMesh / pmp-library manner: an operator that removes an element only marks it
/// deleted, so every other id stays valid, and
/// [`garbage_collection`](Self::garbage_collection) compacts the arrays and returns the
/// old → new id maps. Counts ([`n_vertices`](Self::n_vertices) …) and iterators
/// ([`vertices`](Self::vertices) …) see live elements only. The link accessors and
/// circulators are [`HalfedgeMesh`](crate::HalfedgeMesh)'s, and take a live element: on
/// a deleted one they return what the slot last held, and they panic when the id is
/// out of range.
///
/// Convert with [`from_mesh`](Self::from_mesh) and [`to_mesh`](Self::to_mesh) (both
/// O(n)); the frozen [`HalfedgeMesh`](crate::HalfedgeMesh) stays the type the smoother
/// and the weights read. `docs/editing.md` in the repository describes the model, each
/// operator's preconditions and the property rules.
///
/// # Panics
/// Operators panic only if the mesh would hold more than `u32::MAX − 1` elements of one
/// kind.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{DVec3, EditMesh, primitives};
///
/// let grid = primitives::grid(2, 2); // 3 × 3 vertices, 8 triangles
/// let mut mesh = EditMesh::from_mesh(&grid.mesh()?, &grid.positions)?;
/// let height = mesh.add_vertex_property("height", 0.0_f64)?;
/// for v in mesh.vertices().collect::<Vec<_>>() {
///     let z = mesh.position(v).x;
///     mesh.set(height, v, z);
/// }
/// // Split an edge at its midpoint: the new vertex's height is interpolated.
/// let e = mesh.edges().next().unwrap();
/// let [a, b] = mesh.edge_vertices(e);
/// let mid = 0.5 * (mesh.position(a) + mesh.position(b));
/// let v = mesh.split_edge(e, mid)?;
/// assert_eq!(*mesh.get(height, v), mid.x);
/// mesh.check_integrity()?;
/// let (frozen, positions) = mesh.to_mesh()?;
/// assert_eq!(frozen.n_vertices(), positions.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct EditMesh {
    pub(crate) v_out: Vec<u32>,
    pub(crate) v_pos: Vec<DVec3>,
    pub(crate) v_deleted: Vec<bool>,
    pub(crate) h_to: Vec<u32>,
    pub(crate) h_next: Vec<u32>,
    pub(crate) h_prev: Vec<u32>,
    pub(crate) h_face: Vec<u32>,
    pub(crate) e_deleted: Vec<bool>,
    pub(crate) f_he: Vec<u32>,
    pub(crate) f_deleted: Vec<bool>,
    pub(crate) deleted_vertices: usize,
    pub(crate) deleted_edges: usize,
    pub(crate) deleted_faces: usize,
    pub(crate) props: Properties,
}

impl Default for EditMesh {
    fn default() -> Self {
        Self::new()
    }
}

fn raw<I: ElementId>(id: I) -> u32 {
    // Ids come from `I::from_index`, so they fit.
    id.index() as u32
}

impl EditMesh {
    /// An empty mesh: no vertices, no faces, no properties.
    #[must_use]
    pub fn new() -> Self {
        Self {
            v_out: Vec::new(),
            v_pos: Vec::new(),
            v_deleted: Vec::new(),
            h_to: Vec::new(),
            h_next: Vec::new(),
            h_prev: Vec::new(),
            h_face: Vec::new(),
            e_deleted: Vec::new(),
            f_he: Vec::new(),
            f_deleted: Vec::new(),
            deleted_vertices: 0,
            deleted_edges: 0,
            deleted_faces: 0,
            props: Properties::new(0, 0, 0),
        }
    }

    // ------------------------------------------------------------ element creation

    /// A new isolated vertex slot at `p`; properties get their defaults.
    pub(crate) fn new_vertex(&mut self, p: DVec3) -> VertexId {
        let v = VertexId::from_index(self.v_out.len());
        self.v_out.push(INVALID);
        self.v_pos.push(p);
        self.v_deleted.push(false);
        self.props.vertex().push();
        v
    }

    /// A new edge from `from` to `to`; returns its halfedge `from → to` (`2e`). Links
    /// other than the target vertices are left unset.
    pub(crate) fn new_edge(&mut self, from: VertexId, to: VertexId) -> HalfedgeId {
        let h = HalfedgeId::from_index(self.h_to.len());
        let _ = HalfedgeId::from_index(self.h_to.len() + 1);
        self.h_to.extend([raw(to), raw(from)]);
        self.h_next.extend([INVALID, INVALID]);
        self.h_prev.extend([INVALID, INVALID]);
        self.h_face.extend([INVALID, INVALID]);
        self.e_deleted.push(false);
        self.props.halfedge().push();
        self.props.halfedge().push();
        self.props.edge().push();
        h
    }

    /// A new face slot whose halfedge is `h`.
    pub(crate) fn new_face(&mut self, h: HalfedgeId) -> FaceId {
        let f = FaceId::from_index(self.f_he.len());
        self.f_he.push(raw(h));
        self.f_deleted.push(false);
        self.props.face().push();
        f
    }

    // ------------------------------------------------------------ link writes

    /// `next(h) = n` and `prev(n) = h`.
    #[inline]
    pub(crate) fn link(&mut self, h: HalfedgeId, n: HalfedgeId) {
        self.h_next[h.index()] = raw(n);
        self.h_prev[n.index()] = raw(h);
    }

    #[inline]
    pub(crate) fn set_to(&mut self, h: HalfedgeId, v: VertexId) {
        self.h_to[h.index()] = raw(v);
    }

    #[inline]
    pub(crate) fn set_face(&mut self, h: HalfedgeId, f: Option<FaceId>) {
        self.h_face[h.index()] = f.map_or(INVALID, raw);
    }

    #[inline]
    pub(crate) fn set_face_halfedge(&mut self, f: FaceId, h: HalfedgeId) {
        self.f_he[f.index()] = raw(h);
    }

    #[inline]
    pub(crate) fn set_outgoing(&mut self, v: VertexId, h: Option<HalfedgeId>) {
        self.v_out[v.index()] = h.map_or(INVALID, raw);
    }

    /// Points `v` at an outgoing boundary halfedge if it has one (the boundary
    /// invariant); leaves it alone otherwise.
    pub(crate) fn adjust_outgoing(&mut self, v: VertexId) {
        let found = self
            .halfedges_around_vertex(v)
            .find(|&h| self.is_boundary_halfedge(h));
        if let Some(h) = found {
            self.set_outgoing(v, Some(h));
        }
    }

    pub(crate) fn mark_vertex_deleted(&mut self, v: VertexId) {
        if !self.v_deleted[v.index()] {
            self.v_deleted[v.index()] = true;
            self.v_out[v.index()] = INVALID;
            self.deleted_vertices += 1;
        }
    }

    pub(crate) fn mark_edge_deleted(&mut self, e: EdgeId) {
        if !self.e_deleted[e.index()] {
            self.e_deleted[e.index()] = true;
            self.deleted_edges += 1;
        }
    }

    pub(crate) fn mark_face_deleted(&mut self, f: FaceId) {
        if !self.f_deleted[f.index()] {
            self.f_deleted[f.index()] = true;
            self.deleted_faces += 1;
        }
    }

    // ------------------------------------------------------------ counts and status

    /// The number of live vertices (isolated ones included).
    #[must_use]
    pub fn n_vertices(&self) -> usize {
        self.v_out.len() - self.deleted_vertices
    }

    /// The number of live edges.
    #[must_use]
    pub fn n_edges(&self) -> usize {
        self.e_deleted.len() - self.deleted_edges
    }

    /// The number of live halfedges (twice the number of live edges).
    #[must_use]
    pub fn n_halfedges(&self) -> usize {
        2 * self.n_edges()
    }

    /// The number of live faces.
    #[must_use]
    pub fn n_faces(&self) -> usize {
        self.f_he.len() - self.deleted_faces
    }

    /// The number of vertex slots, deleted ones included: every live vertex id is below
    /// it.
    #[must_use]
    pub fn vertex_capacity(&self) -> usize {
        self.v_out.len()
    }

    /// The number of edge slots, deleted ones included.
    #[must_use]
    pub fn edge_capacity(&self) -> usize {
        self.e_deleted.len()
    }

    /// The number of face slots, deleted ones included.
    #[must_use]
    pub fn face_capacity(&self) -> usize {
        self.f_he.len()
    }

    /// Whether some element is marked deleted (and
    /// [`garbage_collection`](Self::garbage_collection) would compact).
    #[must_use]
    pub fn has_garbage(&self) -> bool {
        self.deleted_vertices + self.deleted_edges + self.deleted_faces > 0
    }

    /// Whether `v` is a live vertex (in range and not deleted).
    #[must_use]
    pub fn is_live_vertex(&self, v: VertexId) -> bool {
        self.v_deleted.get(v.index()).is_some_and(|d| !d)
    }

    /// Whether `e` is a live edge (in range and not deleted).
    #[must_use]
    pub fn is_live_edge(&self, e: EdgeId) -> bool {
        self.e_deleted.get(e.index()).is_some_and(|d| !d)
    }

    /// Whether `h` is a live halfedge (its edge is live).
    #[must_use]
    pub fn is_live_halfedge(&self, h: HalfedgeId) -> bool {
        self.is_live_edge(h.edge())
    }

    /// Whether `f` is a live face (in range and not deleted).
    #[must_use]
    pub fn is_live_face(&self, f: FaceId) -> bool {
        self.f_deleted.get(f.index()).is_some_and(|d| !d)
    }

    /// The Euler characteristic `V − E + F` of the live elements (isolated vertices
    /// included).
    #[must_use]
    pub fn euler_characteristic(&self) -> i64 {
        self.n_vertices() as i64 - self.n_edges() as i64 + self.n_faces() as i64
    }

    // ------------------------------------------------------------ positions

    /// The position of `v` (kept for deleted vertices until garbage collection).
    ///
    /// # Panics
    /// If `v` is out of range.
    #[inline]
    #[must_use]
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.v_pos[v.index()]
    }

    /// Moves `v` to `p`. Connectivity is not affected.
    ///
    /// # Panics
    /// If `v` is out of range.
    #[inline]
    pub fn set_position(&mut self, v: VertexId, p: DVec3) {
        self.v_pos[v.index()] = p;
    }

    /// All positions by vertex index, deleted slots included.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.v_pos
    }

    /// All positions by vertex index, mutably, deleted slots included.
    #[must_use]
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        &mut self.v_pos
    }
}
