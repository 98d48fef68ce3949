//! # beltrami-halfedge
//!
//! Half-edge connectivity for polygon meshes (triangles first), with validation that
//! names the offending face or vertex, counter-clockwise circulators, boundary loops,
//! connected components, dense attribute maps and geometry helpers over a positions
//! slice.
//!
//! Topology and geometry are kept apart: a [`HalfedgeMesh`] holds connectivity only,
//! and positions are a `&[DVec3]` (glam, f64) passed beside it.
//!
//! ## Quick start
//!
//! ```
//! use beltrami_halfedge::{HalfedgeMesh, VertexId};
//!
//! // A square split into two triangles, counter-clockwise seen from +z.
//! let faces = [[0u32, 1, 2], [0, 2, 3]];
//! let mesh = HalfedgeMesh::from_polygons(4, &faces)?;
//! mesh.check_integrity()?;
//!
//! assert_eq!((mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()), (4, 5, 2));
//! assert!(mesh.is_boundary_vertex(VertexId::new(0)));
//! let ring: Vec<u32> = mesh.vertices_around_vertex(VertexId::new(0)).map(|v| v.raw()).collect();
//! // Counter-clockwise, starting across the boundary edge that leaves vertex 0.
//! assert_eq!(ring, [3, 1, 2]);
//! assert_eq!(mesh.boundary_loops().count(), 1);
//! # Ok::<(), beltrami_halfedge::TopologyError>(())
//! ```
//!
//! ## Where to start
//!
//! - Reading a mesh: [`HalfedgeMesh`] (built by [`HalfedgeMesh::from_polygons`] or
//!   [`MeshData::mesh`]), its circulators and [`geometry::Geometry`].
//! - Changing connectivity: [`EditMesh`] (module [`edit`]): flips, edge and face
//!   splits, halfedge collapses, incremental [`add_face`](EditMesh::add_face), deletion
//!   and [`garbage_collection`](EditMesh::garbage_collection), with typed per-vertex,
//!   per-edge, per-halfedge and per-face properties that every operator updates.
//!   Convert with [`EditMesh::from_mesh`] and [`EditMesh::to_mesh`], both O(n); the
//!   frozen [`HalfedgeMesh`] stays what smoothing and the weights read.
//!   `docs/editing.md` describes the model, each operator's preconditions and the
//!   property rules.
//!
//! ```
//! use beltrami_halfedge::{EditMesh, primitives};
//!
//! let grid = primitives::grid(4, 4);
//! let mut mesh = EditMesh::from_mesh_data(&grid)?;
//! let height = mesh.add_vertex_property("height", 0.0_f64)?;
//! let e = mesh.edges().find(|&e| mesh.is_flip_ok(e)).unwrap();
//! mesh.flip_edge(e)?;
//! let h = mesh.halfedges().find(|&h| mesh.is_collapse_ok(h)).unwrap();
//! mesh.collapse_edge(h)?;
//! mesh.garbage_collection();
//! let (frozen, positions) = mesh.to_mesh()?;
//! assert_eq!(mesh.values(height).len(), positions.len());
//! assert_eq!(frozen.n_vertices(), 24);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A polygon soup that does not build (pinched vertices, edges of more than two faces,
//! duplicate or degenerate faces, inconsistent orientation) can be cleaned with
//! [`repair`], which returns a face list that builds and a report of every change.
//!
//! See `docs/conventions.md` in the repository for the half-edge conventions with a
//! diagram.

mod boundary;
mod build;
mod circulators;
mod components;
pub mod edit;
mod error;
pub mod geometry;
mod ids;
mod integrity;
mod map;
mod mesh;
mod mesh_data;
mod polygons;
pub mod primitives;
mod raw;
mod refine;
mod release;
pub mod reorder;
mod repair;
mod text;
mod triangulate;

pub use boundary::BoundaryLoops;
pub use build::{BuildOptions, BuildReport, MAX_ELEMENTS, VertexSplit};
pub use circulators::{
    FacesAroundFace, FacesAroundVertex, HalfedgesAroundFace, HalfedgesAroundVertex,
    VerticesAroundFace, VerticesAroundVertex,
};
pub use components::{ComponentSummary, Components};
pub use edit::{EditError, EditMesh, GarbageMaps};
pub use error::TopologyError;
pub use glam::DVec3;
pub use ids::{EdgeId, ElementId, FaceId, HalfedgeId, IdRange, VertexId};
pub use map::{EdgeMap, FaceMap, HalfedgeMap, IdMap, VertexMap};
pub use mesh::HalfedgeMesh;
pub use mesh_data::MeshData;
pub use polygons::PolygonList;
pub use raw::RawConnectivity;
pub use release::release;
pub use repair::{RepairOptions, RepairReport, Repaired, repair};
pub use text::{exact_number, short_number};
pub use triangulate::triangulate_polygon;
