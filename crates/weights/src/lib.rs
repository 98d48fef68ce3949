//! # beltrami-weights
//!
//! Laplacian weight schemes and the assembled Laplace–Beltrami operator.
//!
//! A [`WeightScheme`] gives each halfedge `i → j` a weight `w_ij`; a [`Laplacian`]
//! assembles them row by row with a normalisation (weight sum, the paper's Eq. 2, or
//! vertex area, Eq. 6) and a policy for negative weights. Three schemes are built in —
//! [`Uniform`], [`InverseDistance`] and [`Cotangent`] — and a [`WeightRegistry`] lets
//! the CLI and the study choose any registered scheme by name, including your own.
//!
//! ## Quick start
//!
//! ```
//! use beltrami_halfedge::{primitives, VertexId};
//! use beltrami_weights::{Cotangent, Laplacian, LaplacianOptions};
//!
//! let grid = primitives::grid(4, 4);
//! let mesh = grid.mesh().unwrap();
//! let lap = Laplacian::new(&mesh, &grid.positions, &Cotangent, LaplacianOptions::default())?;
//! // The cotangent Laplacian of a plane vanishes at interior vertices.
//! let interior = VertexId::new(6);
//! assert!(lap.laplacian_at(interior, &grid.positions).unwrap().length() < 1e-15);
//! # Ok::<(), beltrami_weights::WeightError>(())
//! ```

mod cotangent;
mod error;
mod inverse_distance;
mod laplacian;
mod openmesh;
mod registry;
mod scheme;
mod uniform;

/// Items per parallel work unit (even, so that a chunk of halfedges holds whole twin
/// pairs). Fixed, so that results do not depend on the thread count.
const PAR_CHUNK: usize = 8192;

pub use cotangent::Cotangent;
pub use error::WeightError;
pub use inverse_distance::{DISTANCE_EPSILON, InverseDistance};
pub use laplacian::{
    CotangentKernel, FreshRows, Laplacian, LaplacianOptions, LaplacianRows, NegativeWeights,
    Normalization,
};
pub use openmesh::OpenMeshCotangent;
pub use registry::WeightRegistry;
pub use scheme::{WeightContext, WeightScheme};
pub use uniform::Uniform;
