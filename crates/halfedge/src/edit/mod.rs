//! Editable half-edge meshes: [`EditMesh`], its Euler operators, user properties that
//! follow edits, and garbage collection.
//!
//! [`HalfedgeMesh`](crate::HalfedgeMesh) is frozen and tuned for the smoother;
//! [`EditMesh`] is the type to change connectivity with. The round trip is O(n):
//!
//! ```
//! use beltrami_halfedge::{EditMesh, primitives};
//!
//! let sphere = primitives::icosphere(1);
//! let mut mesh = EditMesh::from_mesh(&sphere.mesh()?, &sphere.positions)?;
//! let chi = mesh.euler_characteristic();
//! // Flip every edge that may be flipped once, collapse one, then compact.
//! for e in mesh.edges().collect::<Vec<_>>() {
//!     if mesh.is_flip_ok(e) {
//!         mesh.flip_edge(e)?;
//!     }
//! }
//! let h = mesh.halfedges().find(|&h| mesh.is_collapse_ok(h)).unwrap();
//! mesh.collapse_edge(h)?;
//! assert_eq!(mesh.euler_characteristic(), chi);
//! let maps = mesh.garbage_collection();
//! assert_eq!(maps.vertices.iter().filter(|(_, new)| new.is_none()).count(), 1);
//! let (frozen, positions) = mesh.into_mesh()?;
//! frozen.check_integrity()?;
//! assert_eq!(positions.len(), 41);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | operator | refused with | Δ(V, E, F) |
//! |---|---|---|
//! | [`flip_edge`](EditMesh::flip_edge) | boundary edge, non-triangle, same opposite vertex, existing edge | (0, 0, 0) |
//! | [`split_edge`](EditMesh::split_edge) | non-triangle neighbour | (1, 1 + k, k), k = faces at the edge |
//! | [`split_face`](EditMesh::split_face) | — | (1, n, n − 1), n = face valence |
//! | [`collapse_edge`](EditMesh::collapse_edge) | OpenMesh's `is_collapse_ok` rules | (−1, −1 − k, −k) |
//! | [`add_vertex`](EditMesh::add_vertex) | — | (1, 0, 0) |
//! | [`add_face`](EditMesh::add_face) | complex vertex / edge, no boundary gap | (0, new edges, 1) |
//! | [`delete_face`](EditMesh::delete_face) | — | (−isolated, −free edges, −1) |
//! | [`delete_vertex`](EditMesh::delete_vertex) | — | its faces, then itself |

mod collapse;
mod convert;
mod error;
mod faces;
mod flip;
mod garbage;
mod integrity;
mod navigation;
mod properties;
mod split;
mod storage;

pub use error::EditError;
pub use garbage::GarbageMaps;
pub use navigation::{HalfedgesAroundFace, HalfedgesAroundVertex, LiveElements};
pub use properties::{
    EdgeProperty, FaceProperty, HalfedgeProperty, Property, PropertyElement, PropertyValue,
    VertexProperty,
};
pub use storage::EditMesh;

use crate::ids::{EdgeId, FaceId, HalfedgeId, VertexId};

impl EditMesh {
    pub(crate) fn live_vertex(&self, vertex: VertexId) -> Result<(), EditError> {
        if self.is_live_vertex(vertex) {
            Ok(())
        } else {
            Err(EditError::NoSuchVertex { vertex })
        }
    }

    pub(crate) fn live_edge(&self, edge: EdgeId) -> Result<(), EditError> {
        if self.is_live_edge(edge) {
            Ok(())
        } else {
            Err(EditError::NoSuchEdge { edge })
        }
    }

    pub(crate) fn live_halfedge(&self, halfedge: HalfedgeId) -> Result<(), EditError> {
        if self.is_live_halfedge(halfedge) {
            Ok(())
        } else {
            Err(EditError::NoSuchHalfedge { halfedge })
        }
    }

    pub(crate) fn live_face(&self, face: FaceId) -> Result<(), EditError> {
        if self.is_live_face(face) {
            Ok(())
        } else {
            Err(EditError::NoSuchFace { face })
        }
    }

    /// `Ok` when the face of `h` (if any) is a triangle.
    pub(crate) fn triangle_or_boundary(&self, h: HalfedgeId) -> Result<(), EditError> {
        match self.face(h) {
            None => Ok(()),
            Some(face) => {
                let len = self.face_valence(face);
                if len == 3 {
                    Ok(())
                } else {
                    Err(EditError::NotTriangle { face, len })
                }
            }
        }
    }
}
