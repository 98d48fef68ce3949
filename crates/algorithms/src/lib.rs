//! # beltrami-algorithms
//!
//! Algorithms that make a new mesh from a [`HalfedgeMesh`](beltrami_halfedge::HalfedgeMesh)
//! and its positions, as free functions, one file per algorithm, each citing its
//! reference:
//!
//! - [`loop_subdivide`]: Loop subdivision (Loop 1987), with the boundary curve rules;
//! - [`sqrt3_subdivide`]: √3 subdivision (Kobbelt 2000), with its boundary rule on odd
//!   steps;
//! - [`delaunay_flip`]: Lawson's edge flips towards a Delaunay mesh on the same vertices
//!   (every cotangent weight non-negative), written on the editable
//!   [`EditMesh`](beltrami_halfedge::EditMesh), with a dihedral bound for curved
//!   surfaces and the change of the surface measured;
//! - [`decimate`]: quadric-error decimation (Garland & Heckbert 1997) by halfedge
//!   collapses, as OpenMesh's `DecimaterT` + `ModQuadricT`, with boundary, normal,
//!   aspect-ratio and distance constraints and the Hausdorff distance reported;
//! - [`remesh`]: isotropic remeshing (Botsch & Kobbelt 2004) towards a target edge
//!   length by splits, collapses, flips and tangential relaxation, keeping the boundary
//!   and sharp features and projecting the vertices back onto the input surface;
//! - [`fill_holes`]: hole filling after Liepa (2003): each boundary loop but the outer
//!   one closed by a minimum-weight triangulation, refined to the rim's density and
//!   faired;
//! - [`remove_flat_triangles`]: caps and needles (zero-area slivers) removed by edge
//!   flips, boundary deletions and short collapses (Botsch et al. 2010, as CGAL's
//!   `remove_degenerate_faces`), leaving the surface where it is;
//! - [`mesh_quality`] and [`flipped_faces`] (module [`quality`]): angles, aspect
//!   ratios, edge lengths, valences and negative cotangent weights, the figures every
//!   algorithm here is judged by.
//!
//! [`remesh`], [`decimate`], [`fill_holes`], [`delaunay_flip`] and the quality figures
//! give the same result in any unit ([`remove_flat_triangles`] does by itself): a mesh
//! whose largest coordinate lies outside `2^-40..=2^40` is run at a power of two times
//! its size, which is exact, and the result and the report's lengths are scaled back, so
//! that the result is the unit-size one times that power of two, bit for bit
//! (`tests/scale.rs`, from `2^-1000` to `2^1000`).
//!
//! The subdivision schemes match OpenMesh's `Subdivider::Uniform::LoopT` and `Sqrt3T`
//! (positions within 1e-12 of the bounding-box diagonal, the same triangles);
//! `docs/subdivision.md` in the repository has the rules, the numbering of the new
//! vertices and the comparison. [`Scheme`] names a scheme at run time and predicts the
//! size of the result before anything is computed.
//!
//! ## Quick start
//!
//! ```
//! use beltrami_algorithms::{loop_subdivide, sqrt3_subdivide};
//! use beltrami_halfedge::primitives;
//!
//! let ico = primitives::icosphere(1);
//! let mesh = ico.mesh()?;
//! let (fine, positions) = loop_subdivide(&mesh, &ico.positions, 2)?;
//! assert_eq!(fine.n_faces(), 16 * mesh.n_faces());
//! assert_eq!(positions.len(), fine.n_vertices());
//!
//! let (fine, _) = sqrt3_subdivide(&mesh, &ico.positions, 2)?;
//! assert_eq!(fine.n_faces(), 9 * mesh.n_faces());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod decimate;
mod delaunay;
mod error;
mod fill_holes;
mod flat_triangles;
pub mod quality;
mod remesh;
mod scale;
pub mod subdivision;
mod valence;

pub use decimate::{
    BlockedBy, DEFAULT_FIT_ROUNDS, DecimateError, DecimateOptions, DecimateReport, DecimateStop,
    DecimateTarget, MAX_FIT_ROUNDS, Placement, RefusalCounts, decimate, decimate_with_progress,
};
pub use delaunay::{DelaunayOptions, DelaunayReport, delaunay_flip};
pub use error::{DelaunayError, SubdivisionError};
pub use fill_holes::{
    FairWeights, FillError, FillOptions, FillReport, FilledHole, SkipReason, SkippedHole,
    fill_hole, fill_holes, fill_holes_with_progress,
};
pub use flat_triangles::{
    FlatError, FlatOptions, FlatReport, MAX_HEIGHT_RATIO, remove_flat_triangles,
};
pub use quality::{MeshQuality, QualityError, flipped_faces, mesh_quality};
pub use remesh::{
    AdaptiveLengths, AdaptiveSizing, DEFAULT_CORNER_ANGLE, EdgeLength, FOLD_ANGLE,
    MAX_REMESH_FACES, MAX_REMESH_ITERATIONS, MIN_EXTENT_SHARE, RemeshError, RemeshIteration,
    RemeshOptions, RemeshReport, SMOOTH_ANGLE, remesh, remesh_with_feature_edges,
    remesh_with_progress,
};
pub use subdivision::{MeshCounts, Scheme, loop_subdivide, sqrt3_subdivide};
