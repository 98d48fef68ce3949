//! Distances from a mesh to a reference surface: closest points on the closest triangle,
//! signed distances, RMS / mean / max statistics, the symmetric Hausdorff distance and plain
//! per-vertex displacement. The enclosed volume and area of a mesh live in
//! [`measures`](crate::measures) and are re-exported here.
//!
//! The paper judges smoothing by the RMS over the vertices of the smoothed mesh of their
//! distance to the clean reference surface,
//! `E_rms = sqrt( (1/N) Σ_i d(v_i, M_ref)² )`, where `d(p, S) = min_{q ∈ S} |p − q|` is
//! measured to the closest point on the closest *triangle*, not the closest vertex.
//!
//! # Quick start
//!
//! ```
//! use beltrami_halfedge::{primitives, DVec3};
//! use beltrami_metrics::distance::{SurfaceIndex, distance_stats, signed_distance_stats};
//!
//! let sphere = primitives::icosphere(3);
//! let mesh = sphere.mesh()?;
//! let reference = SurfaceIndex::new(&mesh, &sphere.positions)?; // build once
//!
//! // A copy grown by 1 %: each vertex is 0.01 from its reference vertex, the closest
//! // point of the convex reference.
//! let grown: Vec<DVec3> = sphere.positions.iter().map(|p| *p * 1.01).collect();
//! let stats = distance_stats(&mesh, &grown, &reference)?;
//! assert!((stats.rms - 0.01).abs() < 1e-12);
//! let signed = signed_distance_stats(&mesh, &grown, &reference)?;
//! assert!(signed.min > 0.0); // every vertex is outside
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Conventions
//!
//! - Lengths are in the unit of the positions. Nothing here returns NaN; inputs with a
//!   non-finite coordinate, or one beyond [`MAX_COORDINATE`], are rejected.
//! - Signs follow the reference's orientation: positive on the side its normals point to.
//! - Batch queries run in parallel with rayon, in fixed chunks; every reduction is
//!   sequential and compensated, so results are identical for any thread count.
//!
//! # References
//! - D. Eberly: *Distance Between Point and Triangle in 3D*. Geometric Tools, 1999.
//! - J. A. Bærentzen, H. Aanæs: *Signed distance computation using the angle weighted
//!   pseudonormal*. IEEE TVCG 11(3), 2005.
//! - P. Cignoni, C. Rocchini, R. Scopigno: *Metro: measuring error on simplified
//!   surfaces*. Computer Graphics Forum 17(2), 1998.

mod bvh;
mod displacement;
mod hausdorff;
mod index;
mod sampling;
mod stats;
mod triangle;

pub use crate::measures::{surface_area, volume};
pub use displacement::{check_same_topology, displacement_stats, displacements};
pub use hausdorff::{
    HausdorffDistance, HausdorffSampling, SampledDistance, SurfaceDistance, hausdorff,
    one_sided_hausdorff, one_sided_hausdorff_from_vertex_distances, sampled_distance,
    surface_distance,
};
pub use index::{ClosestPoint, Feature, MAX_COORDINATE, SurfaceIndex};
pub(crate) use stats::vertex_areas;
pub use stats::{DistanceStats, SignedDistanceStats, distance_stats, signed_distance_stats};
pub use triangle::{TriangleFeature, TrianglePoint, closest_point_on_triangle};
