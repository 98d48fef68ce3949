//! # beltrami
//!
//! Discrete Laplace–Beltrami operators on half-edge triangle meshes, built for
//! surface metrology: smoothing measured free-form surfaces into a reference
//! form and measuring what the smoothing did.
//!
//! This facade re-exports the library crates so that one dependency is enough:
//!
//! | module | crate | what it holds |
//! |---|---|---|
//! | [`halfedge`] | `beltrami-halfedge` | connectivity, validation and repair, circulators, attribute maps, geometry helpers, primitives, the editable `EditMesh` (Euler operators, properties that follow edits, garbage collection) |
//! | [`io`] | `beltrami-io` | PLY, STL, OBJ and OFF readers and writers, per-vertex scalars, atomic and staged writes |
//! | [`weights`] | `beltrami-weights` | the `WeightScheme` plug-in trait, built-in schemes, the registry, the Laplacian |
//! | [`smooth`] | `beltrami-smooth` | explicit and implicit diffusion smoothing, Taubin, HC, boundary handling, observers |
//! | [`schemes`] | `beltrami-schemes` | edge-preserving plug-in schemes (`bilateral`) |
//! | [`metrics`] | `beltrami-metrics` | distances to a surface, normal deviation, fits, distortion, profiles, ISO 25178-2 parameters |
//! | [`surfaces`] | `beltrami-surfaces` | the paper's test surfaces and seeded normal noise |
//! | [`algorithms`] | `beltrami-algorithms` | Loop and √3 subdivision, Delaunay edge flips |
//!
//! [`prelude`] brings the names of a typical program into scope.
//!
//! ```
//! use beltrami::prelude::*;
//!
//! // Smooth a noisy sphere and measure how close it came to the clean one.
//! let clean = primitives::icosphere(4);
//! let mesh = clean.mesh()?;
//! let noisy = clean
//!     .positions
//!     .iter()
//!     .enumerate()
//!     .map(|(i, p)| *p * (1.0 + 0.02 * ((i % 7) as f64 - 3.0) / 3.0))
//!     .collect::<Vec<_>>();
//! let smoothed = smooth(&mesh, &noisy, &Cotangent, SmoothConfig::new(0.5, 2))?;
//! let index = SurfaceIndex::new(&mesh, &clean.positions)?;
//! let mean = |d: Vec<f64>| d.iter().sum::<f64>() / d.len() as f64;
//! let before = mean(index.distances(&noisy)?);
//! let after = mean(index.distances(&smoothed.positions)?);
//! assert!(after < 0.5 * before, "{before} -> {after}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Editing goes through [`EditMesh`](halfedge::EditMesh): convert, edit with Euler
//! operators (properties follow), and convert back.
//!
//! ```
//! use beltrami::prelude::*;
//!
//! let cube = primitives::cube();
//! let mut edit = EditMesh::from_mesh_data(&cube)?;
//! let height: VertexProperty<f64> = edit.add_vertex_property("height", 0.0)?;
//! for v in edit.vertices().collect::<Vec<_>>() {
//!     let z = edit.position(v).z;
//!     edit.set(height, v, z);
//! }
//! // Split every edge at its midpoint: the new vertex's height is interpolated.
//! for e in edit.edges().collect::<Vec<_>>() {
//!     let [a, b] = edit.edge_vertices(e);
//!     let mid = 0.5 * (edit.position(a) + edit.position(b));
//!     let v = edit.split_edge(e, mid)?;
//!     assert!((edit.get(height, v) - mid.z).abs() < 1e-12);
//! }
//! let maps = edit.garbage_collection();
//! assert!(maps.is_identity());
//! let (mesh, positions) = edit.into_mesh()?;
//! assert_eq!(mesh.n_vertices(), 8 + 18);
//! assert_eq!(positions.len(), mesh.n_vertices());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub use beltrami_algorithms as algorithms;
pub use beltrami_halfedge as halfedge;
pub use beltrami_io as io;
pub use beltrami_metrics as metrics;
pub use beltrami_schemes as schemes;
pub use beltrami_smooth as smooth;
pub use beltrami_surfaces as surfaces;
pub use beltrami_weights as weights;

/// The names most programs use: the mesh and its ids, geometry, editing, reading and
/// writing, the weight schemes, smoothing and the distance index.
pub mod prelude {
    pub use beltrami_algorithms::{
        DelaunayOptions, Scheme, delaunay_flip, loop_subdivide, sqrt3_subdivide,
    };
    pub use beltrami_halfedge::edit::{
        EdgeProperty, FaceProperty, HalfedgeProperty, VertexProperty,
    };
    pub use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
    pub use beltrami_halfedge::{
        DVec3, EdgeId, EditError, EditMesh, FaceId, FaceMap, GarbageMaps, HalfedgeId, HalfedgeMesh,
        PolygonList, RepairOptions, TopologyError, VertexId, VertexMap, primitives, repair,
    };
    pub use beltrami_io::{
        IoError, MeshData, VertexAttributes, WriteOptions, read_mesh, write_mesh, write_ply,
    };
    pub use beltrami_metrics::MetricsError;
    pub use beltrami_metrics::distance::SurfaceIndex;
    pub use beltrami_smooth::{
        Boundary, SmoothConfig, SmoothError, Smoother, WeightUpdate, smooth,
    };
    pub use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightRegistry, WeightScheme};
}
