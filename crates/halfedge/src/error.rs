//! Errors of `beltrami-halfedge`.

/// Why a face list could not be turned into a half-edge mesh, or a geometric query
/// could not be answered. Every variant names the offending element(s) by their input
/// index (faces and vertices are 0-based, in the order given to the builder).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TopologyError {
    /// More elements than a `u32` handle can address.
    #[error("too many {kind}: {count} (at most {max} are supported)")]
    TooManyElements {
        /// `"vertices"`, `"faces"` or `"halfedges"`.
        kind: &'static str,
        /// How many were asked for.
        count: usize,
        /// The largest supported count.
        max: usize,
    },
    /// A face lists fewer than three vertices.
    #[error("face {face} has {len} vertices; a face needs at least 3")]
    FaceTooSmall {
        /// Input face index.
        face: usize,
        /// Number of vertices it lists.
        len: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but there are only {n_vertices} vertices")]
    VertexOutOfRange {
        /// Input face index.
        face: usize,
        /// The offending vertex index.
        vertex: u32,
        /// The number of vertices.
        n_vertices: usize,
    },
    /// A face lists the same vertex twice.
    #[error("face {face} lists vertex {vertex} more than once")]
    RepeatedVertex {
        /// Input face index.
        face: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// An edge is shared by more than two faces.
    #[error(
        "non-manifold edge ({a}, {b}): shared by {} faces ({}); a manifold edge has at most 2",
        faces.len(),
        join(faces)
    )]
    NonManifoldEdge {
        /// First vertex of the edge (the smaller index).
        a: u32,
        /// Second vertex of the edge.
        b: u32,
        /// Input indices of all faces that use the edge.
        faces: Vec<usize>,
    },
    /// Two faces traverse their shared edge in the same direction.
    #[error(
        "inconsistent orientation: faces {} and {} both traverse edge {from} -> {to}",
        faces[0],
        faces[1]
    )]
    InconsistentOrientation {
        /// Start vertex of the edge as both faces traverse it.
        from: u32,
        /// End vertex of the edge.
        to: u32,
        /// The two faces.
        faces: [usize; 2],
    },
    /// The faces around a vertex form more than one fan (the surface is pinched there).
    #[error("non-manifold vertex {vertex}: its faces form {fans} separate fans")]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
        /// The number of fans (at least 2).
        fans: usize,
    },
    /// A connected component cannot be oriented consistently (e.g. a Möbius strip).
    #[error("the component of face {face} is not orientable: no consistent orientation exists")]
    NonOrientable {
        /// A face of the component.
        face: usize,
    },
    /// A query that needs a closed mesh (e.g. an enclosed volume) was asked of an open one.
    #[error(
        "the mesh is not closed: it has {boundary_loops} boundary {}",
        if *boundary_loops == 1 { "loop" } else { "loops" }
    )]
    NotClosed {
        /// How many boundary loops the mesh has.
        boundary_loops: usize,
    },
    /// A query that needs triangles was asked of a mesh with a larger face.
    #[error("face {face} has {len} vertices; this operation needs a triangle mesh")]
    NotTriangle {
        /// A face that is not a triangle.
        face: u32,
        /// Its number of vertices.
        len: usize,
    },
    /// A positions slice whose length does not match the mesh.
    #[error("{positions} positions were given for a mesh of {vertices} vertices")]
    PositionCount {
        /// Length of the positions slice.
        positions: usize,
        /// Number of vertices of the mesh.
        vertices: usize,
    },
    /// A half-edge invariant does not hold: found by
    /// [`check_integrity`](crate::HalfedgeMesh::check_integrity) (after a mesh built by
    /// this crate, a bug) or by
    /// [`from_raw_parts`](crate::HalfedgeMesh::from_raw_parts), which validates arrays a
    /// caller assembled (bad input).
    #[error("integrity violated at {element}: {invariant}")]
    Integrity {
        /// The element where the check failed, e.g. `"halfedge 12"`.
        element: String,
        /// The invariant that failed.
        invariant: &'static str,
    },
}

impl TopologyError {
    /// Whether [`repair`](crate::repair) fixes this problem: every topological problem
    /// of a face list with valid indices (a face of fewer than three vertices, a vertex
    /// repeated in a face, a non-manifold edge or vertex, an inconsistent orientation, a
    /// non-orientable surface). Indices out of range, counts and non-finite positions
    /// are not.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::HalfedgeMesh;
    /// let bow_tie = HalfedgeMesh::from_polygons(5, [[0u32, 1, 2], [0, 3, 4]]).unwrap_err();
    /// assert!(bow_tie.is_repairable());
    /// let out_of_range = HalfedgeMesh::from_polygons(3, [[0u32, 1, 5]]).unwrap_err();
    /// assert!(!out_of_range.is_repairable());
    /// ```
    #[must_use]
    pub fn is_repairable(&self) -> bool {
        matches!(
            self,
            Self::FaceTooSmall { .. }
                | Self::RepeatedVertex { .. }
                | Self::NonManifoldEdge { .. }
                | Self::InconsistentOrientation { .. }
                | Self::NonManifoldVertex { .. }
                | Self::NonOrientable { .. }
        )
    }
}

fn join(items: &[usize]) -> String {
    items
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}
