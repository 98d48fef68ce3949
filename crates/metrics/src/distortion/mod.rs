//! Boundary and edge distortion: how far smoothing moved the boundary, how far that
//! reaches inward, and how much it blurred the sharp edges.
//!
//! Three measurements compare a smoothed mesh with its original of the same topology
//! (same vertex count, same faces listed with the same vertices in the same order):
//!
//! - [`boundary_displacement`]: the displacement of the boundary vertices, total and split
//!   into the part along the original vertex normal and the tangential rest;
//! - [`boundary_rings`] and [`error_by_ring`]: the graph distance of every vertex from the
//!   boundary (its ring index) and the RMS and maximum of a per-vertex error on every
//!   ring, which shows how far boundary distortion reaches into the surface;
//! - [`dihedral_angle`] and [`feature_edge_distortion`]: the dihedral angles at the
//!   feature edges of the original (edges sharper than a threshold) before and after.
//!
//! # Conventions
//!
//! - **Units.** Displacements and errors are in the unit of the positions; angles are in
//!   degrees.
//! - **Boundary.** A boundary vertex is a vertex on a boundary loop (a vertex with a
//!   boundary edge). Isolated vertices are not on the surface and are never counted.
//! - **Empty sets.** A closed mesh has no boundary: the displacement statistics are all 0
//!   with a count of 0, and the ring profile is empty. A mesh without feature edges gives
//!   statistics of 0 over an empty edge list. These are not errors; check the counts.
//! - **Order.** The first argument is the original (reference), the second the smoothed
//!   mesh. Correspondence is by vertex and face index.
//!
//! # Examples
//!
//! ```
//! use beltrami_halfedge::geometry::Geometry;
//! use beltrami_halfedge::{primitives, DVec3};
//! use beltrami_metrics::distortion::{boundary_displacement, boundary_rings};
//!
//! let grid = primitives::grid(4, 4);
//! let mesh = grid.mesh()?;
//! // Lift the whole grid by 0.5 along its normal (+z).
//! let lifted: Vec<DVec3> = grid.positions.iter().map(|&p| p + DVec3::new(0.0, 0.0, 0.5)).collect();
//! let d = boundary_displacement(&Geometry::new(&mesh, &grid.positions)?, &Geometry::new(&mesh, &lifted)?)?;
//! assert_eq!(d.count, 16);
//! assert!((d.mean_normal - 0.5).abs() < 1e-15 && d.max_tangential < 1e-15);
//!
//! // The centre vertex (2, 2) is two edges away from the border.
//! assert_eq!(boundary_rings(&mesh)[beltrami_halfedge::VertexId::new(12)], Some(2));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # References
//!
//! - The cross-sectional and boundary comparisons of smoothed against original surfaces
//!   follow the evaluation of *Comparison of discrete Laplacian–Beltrami operators and
//!   their applications in surface metrology* (section 3).
//! - X. Jiang, L. Cooper, P. J. Scott: *Freeform surface filtering using the diffusion
//!   equation*. Proc. R. Soc. A 467 (2011) 841, doi 10.1098/rspa.2010.0307 (the diffusion
//!   filter whose boundary and edge behaviour these quantities measure).
//! - X. Sun, P. L. Rosin, R. R. Martin, F. C. Langbein: *Fast and effective
//!   feature-preserving mesh denoising*. IEEE TVCG 13(5), 2007 (sharp features under
//!   smoothing, judged by normals).

mod boundary;
mod dihedral;
mod rings;

use beltrami_halfedge::{DVec3, HalfedgeMesh};

use crate::MetricsError;

pub use boundary::{BoundaryDisplacement, boundary_displacement};
pub use dihedral::{
    AngleSummary, FeatureEdge, FeatureEdgeDistortion, dihedral_angle, dihedral_angles,
    feature_edge_distortion,
};
pub use rings::{RingError, RingProfile, boundary_rings, error_by_ring};

/// Checks that `smoothed` has the topology of `original`: the same number of vertices and
/// the same faces, each with the same vertices in the same order.
///
/// # Errors
/// [`MetricsError::TopologyMismatch`] naming the first difference.
pub(crate) fn check_same_topology(
    original: &HalfedgeMesh,
    smoothed: &HalfedgeMesh,
) -> Result<(), MetricsError> {
    if std::ptr::eq(original, smoothed) {
        return Ok(());
    }
    let mismatch = |detail: String| Err(MetricsError::TopologyMismatch { detail });
    if original.n_vertices() != smoothed.n_vertices() {
        return mismatch(format!(
            "{} vertices vs {}",
            original.n_vertices(),
            smoothed.n_vertices()
        ));
    }
    if original.n_faces() != smoothed.n_faces() {
        return mismatch(format!(
            "{} faces vs {}",
            original.n_faces(),
            smoothed.n_faces()
        ));
    }
    for f in original.faces() {
        if !original
            .vertices_around_face(f)
            .eq(smoothed.vertices_around_face(f))
        {
            let list = |m: &HalfedgeMesh| {
                m.vertices_around_face(f)
                    .map(|v| v.raw().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return mismatch(format!(
                "face {} has vertices [{}] vs [{}]",
                f.raw(),
                list(original),
                list(smoothed)
            ));
        }
    }
    Ok(())
}

/// Checks that every position is finite.
///
/// # Errors
/// [`MetricsError::NonFinite`] with `what = "position"` and the first offending index.
pub(crate) fn check_finite_positions(positions: &[DVec3]) -> Result<(), MetricsError> {
    match positions.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(MetricsError::NonFinite {
            what: "position",
            index,
        }),
        None => Ok(()),
    }
}

/// The Euclidean length of `v`, without overflow or underflow of the squares for any
/// finite `v` (the largest component is factored out when it is far from 1).
pub(crate) fn robust_length(v: DVec3) -> f64 {
    let m = v.abs().max_element();
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    if (1e-150..=1e150).contains(&m) {
        v.length()
    } else {
        m * (v / m).length()
    }
}
