//! # beltrami
//!
//! Discrete Laplace–Beltrami operators on half-edge triangle meshes, built for
//! surface metrology: smoothing measured free-form surfaces into a reference
//! form and measuring what the smoothing did.
//!
//! This facade re-exports the workspace crates so that one dependency is enough:
//!
//! | module | crate | what it holds |
//! |---|---|---|
//! | [`halfedge`] | `beltrami-halfedge` | connectivity, validation, circulators, geometry helpers |
//! | [`io`] | `beltrami-io` | PLY, STL and OBJ readers and writers |
//! | [`weights`] | `beltrami-weights` | the `WeightScheme` plug-in trait, built-in schemes, the Laplacian |
//! | [`smooth`] | `beltrami-smooth` | explicit diffusion smoothing with boundary handling and observers |
//!
//! ```
//! use beltrami::halfedge::HalfedgeMesh;
//!
//! // Two triangles sharing an edge: an open quad.
//! let mesh = HalfedgeMesh::from_polygons(4, &[[0u32, 1, 2], [0, 2, 3]]).unwrap();
//! assert_eq!(mesh.n_edges(), 5);
//! assert_eq!(mesh.boundary_loops().count(), 1);
//! ```

pub use beltrami_halfedge as halfedge;
pub use beltrami_io as io;
pub use beltrami_smooth as smooth;
pub use beltrami_weights as weights;
