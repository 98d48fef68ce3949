//! A compact list of polygons: the face list a mesh is built from.

/// Faces as vertex-index lists, stored flat (one index buffer plus offsets).
///
/// This is the exchange format between the readers of `beltrami-io` and
/// [`HalfedgeMesh::from_polygons`](crate::HalfedgeMesh::from_polygons). Vertex indices
/// are 0-based; a face lists its vertices counter-clockwise when seen from the side its
/// normal points to.
///
/// # Examples
/// ```
/// use beltrami_halfedge::PolygonList;
/// let mut faces = PolygonList::new();
/// faces.push(&[0, 1, 2]);
/// faces.push(&[0, 2, 3, 4]);
/// assert_eq!(faces.len(), 2);
/// assert_eq!(faces.get(1), Some(&[0, 2, 3, 4][..]));
/// assert!(!faces.is_triangles());
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PolygonList {
    indices: Vec<u32>,
    /// `offsets[f]..offsets[f + 1]` is the range of face `f` in `indices`.
    offsets: Vec<usize>,
}

impl PolygonList {
    /// An empty list.
    #[must_use]
    pub fn new() -> Self {
        Self {
            indices: Vec::new(),
            offsets: vec![0],
        }
    }

    /// An empty list with room for `faces` faces of `indices` indices in all.
    #[must_use]
    pub fn with_capacity(faces: usize, indices: usize) -> Self {
        let mut offsets = Vec::with_capacity(faces + 1);
        offsets.push(0);
        Self {
            indices: Vec::with_capacity(indices),
            offsets,
        }
    }

    /// A list of triangles.
    #[must_use]
    pub fn from_triangles(triangles: &[[u32; 3]]) -> Self {
        let mut list = Self::with_capacity(triangles.len(), 3 * triangles.len());
        for t in triangles {
            list.push(t);
        }
        list
    }

    /// Appends a face.
    pub fn push(&mut self, face: &[u32]) {
        self.indices.extend_from_slice(face);
        self.offsets.push(self.indices.len());
    }

    /// The number of faces.
    #[must_use]
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there are no faces.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The total number of vertex indices over all faces (the number of corners).
    #[must_use]
    pub fn n_corners(&self) -> usize {
        self.indices.len()
    }

    /// Face `f`, or `None` when out of range.
    #[must_use]
    pub fn get(&self, f: usize) -> Option<&[u32]> {
        let start = *self.offsets.get(f)?;
        let end = *self.offsets.get(f + 1)?;
        Some(&self.indices[start..end])
    }

    /// The faces in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &[u32]> + Clone + '_ {
        self.offsets
            .windows(2)
            .map(move |w| &self.indices[w[0]..w[1]])
    }

    /// Whether every face is a triangle.
    #[must_use]
    pub fn is_triangles(&self) -> bool {
        self.offsets.windows(2).all(|w| w[1] - w[0] == 3)
    }

    /// The largest vertex index used, or `None` without faces.
    #[must_use]
    pub fn max_index(&self) -> Option<u32> {
        self.indices.iter().copied().max()
    }

    /// All indices, face after face.
    #[must_use]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Offset of each face's first index in [`indices`](Self::indices), plus the total
    /// at the end (`len() + 1` entries).
    #[must_use]
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }
}

impl Default for PolygonList {
    /// An empty list (the same as [`PolygonList::new`]).
    fn default() -> Self {
        Self::new()
    }
}

impl<'a> FromIterator<&'a [u32]> for PolygonList {
    fn from_iter<T: IntoIterator<Item = &'a [u32]>>(iter: T) -> Self {
        let mut list = Self::new();
        for f in iter {
            list.push(f);
        }
        list
    }
}

impl crate::HalfedgeMesh {
    /// The faces of a triangle mesh as one flat index list, three per face in face
    /// order, each from the face's first vertex: the indices of
    /// [`to_polygons`](Self::to_polygons), without its offsets (12 bytes per face
    /// instead of 20). The mesh is consumed and its buffers are reused: the list is
    /// written into one of them as the others are freed, so that no more memory than
    /// the mesh's is ever held. For a caller that needs only the faces of a large mesh
    /// (to write them, or to rebuild the mesh with
    /// [`from_polygons`](Self::from_polygons) over `chunks_exact(3)`).
    ///
    /// # Errors
    /// The mesh itself (boxed), unchanged, when a face is not a triangle.
    ///
    /// # Complexity
    /// O(F + H) time, sequential; no allocation beyond the mesh's (the list is shrunk to
    /// its length, which on a mesh with a boundary may move it).
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::primitives;
    /// let sphere = primitives::icosphere(1);
    /// let mesh = sphere.mesh().unwrap();
    /// let polygons = mesh.to_polygons();
    /// let flat = mesh.into_triangle_indices().unwrap();
    /// assert_eq!(flat, polygons.indices());
    /// ```
    pub fn into_triangle_indices(self) -> Result<Vec<u32>, Box<Self>> {
        if !self.is_triangle_mesh() {
            return Err(Box::new(self));
        }
        let Self {
            v_out,
            h_to,
            h_next,
            h_prev,
            h_face,
            f_he,
        } = self;
        drop(v_out);
        drop(h_face);
        // Three indices per face fit in the halfedges' buffer (3F ≤ H).
        let mut out = h_prev;
        for (f, &h0) in f_he.iter().enumerate() {
            let h1 = h_next[h0 as usize];
            let h2 = h_next[h1 as usize];
            out[3 * f] = h_to[h0 as usize];
            out[3 * f + 1] = h_to[h1 as usize];
            out[3 * f + 2] = h_to[h2 as usize];
        }
        out.truncate(3 * f_he.len());
        drop((h_to, h_next, f_he));
        out.shrink_to_fit();
        Ok(out)
    }
}
