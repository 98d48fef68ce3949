//! Building a [`HalfedgeMesh`] from a polygon list, with validation and opt-in repairs.

use rayon::prelude::*;

use crate::error::TopologyError;
use crate::mesh::HalfedgeMesh;
use crate::polygons::PolygonList;

mod assemble;
mod corners;
mod options;
mod repair;

use assemble::assemble;
pub(crate) use corners::Corners;
pub use options::{BuildOptions, BuildReport, VertexSplit};
use repair::{reorient, split_nonmanifold_vertices};

/// The largest number of elements of one kind (handles are `u32`; `u32::MAX` is
/// reserved internally).
pub const MAX_ELEMENTS: usize = u32::MAX as usize;

impl HalfedgeMesh {
    /// Builds the connectivity of `n_vertices` vertices and the given faces, rejecting
    /// anything that is not an oriented 2-manifold (with boundary).
    ///
    /// Faces list vertex indices (0-based) counter-clockwise; triangles and larger
    /// polygons are accepted. Vertices used by no face are kept as isolated vertices.
    /// Edge `e` is numbered by the first appearance of its vertex pair when walking the
    /// faces in order, and its halfedge `2e` runs in that first direction (as in OpenMesh).
    ///
    /// # Errors
    /// The first problem found, with input indices: [`TopologyError::VertexOutOfRange`],
    /// [`FaceTooSmall`](TopologyError::FaceTooSmall),
    /// [`RepeatedVertex`](TopologyError::RepeatedVertex),
    /// [`NonManifoldEdge`](TopologyError::NonManifoldEdge),
    /// [`InconsistentOrientation`](TopologyError::InconsistentOrientation),
    /// [`NonManifoldVertex`](TopologyError::NonManifoldVertex),
    /// [`TooManyElements`](TopologyError::TooManyElements). Among edge problems, the one
    /// whose first face comes first in the input is reported.
    ///
    /// # Complexity
    /// O(C log C) time and O(C) memory for C face corners.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{HalfedgeMesh, TopologyError};
    /// let tet = [[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    /// let mesh = HalfedgeMesh::from_polygons(4, &tet).unwrap();
    /// assert!(mesh.is_closed());
    /// assert_eq!(mesh.euler_characteristic(), 2);
    ///
    /// let err = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 5]]).unwrap_err();
    /// assert_eq!(err.to_string(), "face 0 refers to vertex 5, but there are only 3 vertices");
    /// ```
    pub fn from_polygons<F: AsRef<[u32]>>(
        n_vertices: usize,
        faces: impl IntoIterator<Item = F>,
    ) -> Result<Self, TopologyError> {
        Self::build(n_vertices, faces, &BuildOptions::new()).map(|(mesh, _)| mesh)
    }

    /// Like [`from_polygons`](Self::from_polygons), for a face list already in memory:
    /// the same mesh and the same errors, but the faces are checked in parallel and
    /// not copied. This is the fast path for meshes read from files.
    ///
    /// # Errors
    /// Those of [`from_polygons`](Self::from_polygons), the first problem found in the
    /// same order.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{HalfedgeMesh, PolygonList};
    /// let tet = PolygonList::from_triangles(&[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
    /// let mesh = HalfedgeMesh::from_polygon_list(4, &tet).unwrap();
    /// assert_eq!(mesh, HalfedgeMesh::from_polygons(4, tet.iter()).unwrap());
    /// ```
    pub fn from_polygon_list(
        n_vertices: usize,
        faces: &PolygonList,
    ) -> Result<Self, TopologyError> {
        check_count("vertices", n_vertices)?;
        // Fixed chunks of faces, each checked by a plain loop; the first problem of the
        // first chunk that has one is the first in input order.
        let n_faces = faces.len();
        let problem = (0..n_faces.div_ceil(FACE_CHUNK))
            .into_par_iter()
            .find_map_first(|c| {
                let end = ((c + 1) * FACE_CHUNK).min(n_faces);
                first_bad_face(faces, c * FACE_CHUNK..end, n_vertices)
            });
        if let Some(err) = problem {
            return Err(err);
        }
        check_count("faces", faces.len())?;
        check_count("halfedges", 2 * faces.n_corners())?;
        assemble(n_vertices, faces, Origin(&[]))
    }

    /// Like [`from_polygons`](Self::from_polygons), with the opt-in repairs of `options`.
    /// Returns the mesh and a report of what was repaired.
    ///
    /// # Errors
    /// As [`from_polygons`](Self::from_polygons) for every problem that the enabled
    /// repairs do not fix, and [`TopologyError::NonOrientable`] when re-orientation is
    /// asked of a non-orientable component.
    pub fn build<F: AsRef<[u32]>>(
        n_vertices: usize,
        faces: impl IntoIterator<Item = F>,
        options: &BuildOptions,
    ) -> Result<(Self, BuildReport), TopologyError> {
        check_count("vertices", n_vertices)?;
        let mut report = BuildReport::default();
        let mut list = PolygonList::new();
        // Input index of each kept face; empty while no face was dropped (then face
        // `f` is input face `f`), so a mesh that needs no repair never fills it.
        let mut origin = Vec::new();
        let mut scratch = Vec::new();
        for (fi, face) in faces.into_iter().enumerate() {
            let face = face.as_ref();
            if let Some(err) = out_of_range(fi, face, n_vertices) {
                return Err(err);
            }
            match degenerate(fi, face, &mut scratch) {
                Some(_) if options.drops_degenerate_faces() => {
                    if report.dropped_faces.is_empty() {
                        origin.extend(0..fi);
                    }
                    report.dropped_faces.push(fi);
                }
                Some(err) => return Err(err),
                None => {
                    list.push(face);
                    if !report.dropped_faces.is_empty() {
                        origin.push(fi);
                    }
                }
            }
        }
        check_count("faces", list.len())?;
        check_count("halfedges", 2 * list.n_corners())?;

        let origin = Origin(&origin);
        if options.reorients() {
            reorient(&mut list, origin, &mut report)?;
        }
        let mut n_vertices = n_vertices;
        if options.splits_nonmanifold_vertices() {
            split_nonmanifold_vertices(&mut list, &mut n_vertices, &mut report)?;
        }
        let mesh = assemble(n_vertices, &list, origin)?;
        if !report.dropped_faces.is_empty() {
            report.face_origin = origin.0.to_vec();
        }
        Ok((mesh, report))
    }
}

/// The input index of each face of the polygon list being built.
#[derive(Clone, Copy)]
struct Origin<'a>(&'a [usize]);

impl Origin<'_> {
    /// The input index of face `f` (`f` itself when no face was dropped).
    fn of(self, f: usize) -> usize {
        if self.0.is_empty() { f } else { self.0[f] }
    }
}

pub(crate) fn check_count(kind: &'static str, count: usize) -> Result<(), TopologyError> {
    if count > MAX_ELEMENTS {
        return Err(TopologyError::TooManyElements {
            kind,
            count,
            max: MAX_ELEMENTS,
        });
    }
    Ok(())
}

/// Faces checked by one parallel task of [`HalfedgeMesh::from_polygon_list`].
const FACE_CHUNK: usize = 1 << 14;

/// The first problem of the faces `range` of `faces` that [`out_of_range`] or
/// [`degenerate`] finds, in input order.
fn first_bad_face(
    faces: &PolygonList,
    range: std::ops::Range<usize>,
    n_vertices: usize,
) -> Option<TopologyError> {
    let indices = faces.indices();
    let mut scratch = Vec::new();
    for fi in range {
        let face = &indices[faces.face_range(fi)];
        if let &[a, b, c] = face {
            // The common case in one test: three distinct vertices in range.
            let n = n_vertices;
            if (a as usize) < n
                && (b as usize) < n
                && (c as usize) < n
                && a != b
                && a != c
                && b != c
            {
                continue;
            }
        }
        if let Some(err) =
            out_of_range(fi, face, n_vertices).or_else(|| degenerate(fi, face, &mut scratch))
        {
            return Some(err);
        }
    }
    None
}

/// [`TopologyError::VertexOutOfRange`] when input face `fi` names a vertex `>= n_vertices`.
fn out_of_range(fi: usize, face: &[u32], n_vertices: usize) -> Option<TopologyError> {
    face.iter()
        .find(|&&v| v as usize >= n_vertices)
        .map(|&vertex| TopologyError::VertexOutOfRange {
            face: fi,
            vertex,
            n_vertices,
        })
}

/// [`TopologyError::FaceTooSmall`] or [`TopologyError::RepeatedVertex`] when input face
/// `fi` has fewer than three corners or a vertex twice.
fn degenerate(fi: usize, face: &[u32], scratch: &mut Vec<u32>) -> Option<TopologyError> {
    if face.len() < 3 {
        Some(TopologyError::FaceTooSmall {
            face: fi,
            len: face.len(),
        })
    } else {
        repeated_vertex(face, scratch)
            .map(|vertex| TopologyError::RepeatedVertex { face: fi, vertex })
    }
}

/// The first vertex that appears twice in `face` (in order of its second appearance).
pub(crate) fn repeated_vertex(face: &[u32], scratch: &mut Vec<u32>) -> Option<u32> {
    if let &[a, b, c] = face {
        return if a == b || a == c {
            Some(a)
        } else if b == c {
            Some(b)
        } else {
            None
        };
    }
    if face.len() <= 16 {
        for (i, &v) in face.iter().enumerate() {
            if face[..i].contains(&v) {
                return Some(v);
            }
        }
        None
    } else {
        scratch.clear();
        scratch.extend_from_slice(face);
        scratch.sort_unstable();
        scratch.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}
