//! Enclosed volume and surface area of a mesh, for comparing a mesh with its reference.
//!
//! Both are checked wrappers of the [`Geometry`] queries: they reject a mesh without
//! faces, positions that do not match the mesh and non-finite positions with a
//! [`MetricsError`]. They are also re-exported from [`distance`](crate::distance).

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh};

use crate::MetricsError;

/// The volume enclosed by a closed mesh, in unit³, by the divergence theorem:
/// `V = Σ_f p_a · (p_b × p_c) / 6` over the triangles (larger faces fanned). Positive for
/// outward (counter-clockwise seen from outside) orientation.
///
/// A thin wrapper of [`Geometry::volume`], which evaluates the sum around the bounding-box
/// centre with compensated summation, so the result does not depend on where the mesh
/// sits. For an inscribed polyhedron of a sphere the value is below `4π r³ / 3`.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::measures::volume;
/// let cube = primitives::cube();
/// assert!((volume(&cube.mesh()?, &cube.positions)? - 1.0).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`MetricsError::Empty`] for a mesh without faces;
/// [`MetricsError::Topology`] with
/// [`TopologyError::NotClosed`](beltrami_halfedge::TopologyError::NotClosed) for an open
/// mesh, or `PositionCount` when `positions` does not match; [`MetricsError::NonFinite`]
/// for a non-finite position.
pub fn volume(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<f64, MetricsError> {
    let geometry = checked(mesh, positions)?;
    Ok(geometry.volume()?)
}

/// The total area of a mesh's faces, in unit² (compensated sum of the face areas; a thin
/// wrapper of [`Geometry::surface_area`]).
///
/// # Errors
/// [`MetricsError::Empty`] for a mesh without faces; [`MetricsError::Topology`] when
/// `positions` does not match the mesh; [`MetricsError::NonFinite`] for a non-finite
/// position.
pub fn surface_area(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<f64, MetricsError> {
    Ok(checked(mesh, positions)?.surface_area())
}

fn checked<'a>(
    mesh: &'a HalfedgeMesh,
    positions: &'a [DVec3],
) -> Result<Geometry<'a>, MetricsError> {
    let geometry = Geometry::new(mesh, positions)?;
    if mesh.n_faces() == 0 {
        return Err(MetricsError::Empty { what: "mesh" });
    }
    if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
        return Err(MetricsError::NonFinite {
            what: "position",
            index,
        });
    }
    Ok(geometry)
}
