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
///
/// A list of triangles alone keeps no offsets (12 bytes per face instead of 20): face `f`
/// is `indices[3f..3f + 3]`. The offsets are made when the first face that is not a
/// triangle is pushed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PolygonList {
    indices: Vec<u32>,
    /// Empty while every face is a triangle (face `f` is `3f..3f + 3` of `indices`);
    /// otherwise `offsets[f]..offsets[f + 1]` is the range of face `f` in `indices`
    /// (`len() + 1` entries from 0). So two lists of the same faces are equal.
    offsets: Vec<usize>,
}

impl PolygonList {
    /// An empty list.
    #[must_use]
    pub fn new() -> Self {
        Self {
            indices: Vec::new(),
            offsets: Vec::new(),
        }
    }

    /// An empty list with room for `faces` faces of `indices` indices in all (the
    /// offsets are made only once a face is not a triangle, so `faces` is not reserved
    /// ahead).
    #[must_use]
    pub fn with_capacity(faces: usize, indices: usize) -> Self {
        let _ = faces;
        Self {
            indices: Vec::with_capacity(indices),
            offsets: Vec::new(),
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
        if self.offsets.is_empty() {
            if face.len() == 3 {
                self.indices.extend_from_slice(face);
                return;
            }
            // The first face that is not a triangle: the triangles so far get offsets.
            let n = self.indices.len() / 3;
            self.offsets.reserve_exact(n + 2);
            self.offsets.extend((0..=n).map(|f| 3 * f));
        }
        self.indices.extend_from_slice(face);
        self.offsets.push(self.indices.len());
    }

    /// The number of faces.
    #[must_use]
    pub fn len(&self) -> usize {
        if self.offsets.is_empty() {
            self.indices.len() / 3
        } else {
            self.offsets.len() - 1
        }
    }

    /// The range of face `f` in [`indices`](Self::indices).
    ///
    /// # Panics
    /// If `f >= len()`.
    #[must_use]
    pub fn face_range(&self, f: usize) -> std::ops::Range<usize> {
        if self.offsets.is_empty() {
            assert!(f < self.len(), "face {f} of {}", self.len());
            3 * f..3 * f + 3
        } else {
            self.offsets[f]..self.offsets[f + 1]
        }
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
        (f < self.len()).then(|| &self.indices[self.face_range(f)])
    }

    /// The faces in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &[u32]> + Clone + '_ {
        (0..self.len()).map(move |f| &self.indices[self.face_range(f)])
    }

    /// Whether every face is a triangle (O(1)).
    #[must_use]
    pub fn is_triangles(&self) -> bool {
        // Offsets exist only once a face that is not a triangle was pushed.
        self.offsets.is_empty()
    }

    /// Frees the list: the same as dropping it, with its buffers freed by
    /// [`release`](crate::release) (so that a large list's memory goes back to the
    /// system with glibc's allocator).
    pub fn release(self) {
        crate::release(self.indices);
        crate::release(self.offsets);
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
    /// at the end (`len() + 1` entries). A list of triangles keeps no offsets, so for one
    /// they are made here (`0, 3, 6, …`; 8 bytes per face): a caller that walks a large
    /// list reads [`face_range`](Self::face_range) instead.
    #[must_use]
    pub fn offsets(&self) -> std::borrow::Cow<'_, [usize]> {
        if self.offsets.is_empty() {
            std::borrow::Cow::Owned((0..=self.len()).map(|f| 3 * f).collect())
        } else {
            std::borrow::Cow::Borrowed(&self.offsets)
        }
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

#[cfg(test)]
mod tests {
    use super::PolygonList;

    #[test]
    fn triangles_keep_no_offsets_and_a_polygon_makes_them() {
        let mut list = PolygonList::with_capacity(3, 9);
        list.push(&[0, 1, 2]);
        list.push(&[2, 1, 3]);
        assert!(list.is_triangles());
        assert_eq!(list.offsets.capacity(), 0, "no offsets for triangles");
        assert_eq!(list.len(), 2);
        assert_eq!(list.face_range(1), 3..6);
        assert_eq!(list.get(1), Some(&[2, 1, 3][..]));
        assert_eq!(list.get(2), None);
        assert_eq!(&*list.offsets(), &[0, 3, 6]);
        // A quad: the offsets of the triangles before it are made.
        list.push(&[3, 1, 4, 5]);
        list.push(&[5, 4, 6]);
        assert!(!list.is_triangles());
        assert_eq!(list.len(), 4);
        assert_eq!(&*list.offsets(), &[0, 3, 6, 10, 13]);
        assert_eq!(list.face_range(2), 6..10);
        assert_eq!(list.get(3), Some(&[5, 4, 6][..]));
        let faces: Vec<&[u32]> = list.iter().collect();
        assert_eq!(
            faces,
            [&[0, 1, 2][..], &[2, 1, 3], &[3, 1, 4, 5], &[5, 4, 6]]
        );
        assert_eq!(list.iter().len(), 4);
        // The same faces give equal lists, however they were collected.
        let again: PolygonList = faces.iter().copied().collect();
        assert_eq!(again, list);
        let tris: PolygonList = [&[0u32, 1, 2][..], &[2, 1, 3]].into_iter().collect();
        assert_eq!(tris, PolygonList::from_triangles(&[[0, 1, 2], [2, 1, 3]]));
        assert_ne!(tris, list);
    }

    #[test]
    fn an_empty_list_has_one_offset() {
        let list = PolygonList::new();
        assert!(list.is_empty() && list.is_triangles());
        assert_eq!(&*list.offsets(), &[0]);
        assert_eq!(list.iter().count(), 0);
        assert_eq!(list, PolygonList::default());
    }

    #[test]
    #[should_panic(expected = "face 1 of 1")]
    fn a_face_past_the_end_panics() {
        let list = PolygonList::from_triangles(&[[0, 1, 2]]);
        let _ = list.face_range(1);
    }
}
