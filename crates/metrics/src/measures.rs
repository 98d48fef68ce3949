//! Enclosed volume and surface area of a mesh, for comparing a mesh with its reference.
//!
//! Both take a [`Geometry`], like the other metrics, and are checked wrappers of its
//! queries: they reject a mesh without faces and non-finite positions with a
//! [`MetricsError`] (positions that do not match the mesh are refused by
//! [`Geometry::new`]). They are also re-exported from [`distance`](crate::distance).

use beltrami_halfedge::TopologyError;
use beltrami_halfedge::geometry::Geometry;

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
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::measures::{surface_area, volume};
/// let cube = primitives::cube();
/// let mesh = cube.mesh()?;
/// let geometry = Geometry::new(&mesh, &cube.positions)?;
/// assert!((volume(&geometry)? - 1.0).abs() < 1e-15);
/// assert!((surface_area(&geometry)? - 6.0).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`MetricsError::Empty`] for a mesh without faces;
/// [`MetricsError::Topology`] with
/// [`TopologyError::NotClosed`] for an open
/// mesh; [`MetricsError::NonFinite`] for a non-finite position.
pub fn volume(geometry: &Geometry<'_>) -> Result<f64, MetricsError> {
    check(geometry)?;
    Ok(geometry.volume()?)
}

/// The enclosed volume of a closed mesh, in unit³, `None` for an open one: [`volume`]
/// with the open mesh not an error.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::measures::closed_volume;
/// let grid = primitives::grid(2, 2);
/// let mesh = grid.mesh()?;
/// assert_eq!(closed_volume(&Geometry::new(&mesh, &grid.positions)?)?, None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`MetricsError::Empty`] for a mesh without faces; [`MetricsError::NonFinite`] for a
/// non-finite position.
pub fn closed_volume(geometry: &Geometry<'_>) -> Result<Option<f64>, MetricsError> {
    match volume(geometry) {
        Ok(v) => Ok(Some(v)),
        Err(MetricsError::Topology(TopologyError::NotClosed { .. })) => Ok(None),
        Err(e) => Err(e),
    }
}

/// The diagonal of the bounding box of the vertices in a face (the surface's extent,
/// in the positions' unit; isolated vertices, which enclose nothing, left out), 0 for a
/// mesh without faces: the `extent` of [`volume_ratio`].
#[must_use]
pub fn surface_extent(geometry: &Geometry<'_>) -> f64 {
    let (mesh, positions) = (geometry.mesh(), geometry.positions());
    let mut on = mesh
        .vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .map(|v| positions[v.index()]);
    let Some(first) = on.next() else {
        return 0.0;
    };
    let (lo, hi) = on.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    lo.distance(hi)
}

/// `mesh / reference` of two enclosed volumes (unit³), or `None` when the reference
/// encloses no volume: its magnitude at most `1e-12 · extent³` (`extent` the
/// reference's bounding-box diagonal, in the same unit), where a closed but flat
/// surface's volume, zero but for rounding, lies whatever plane it is in. A ratio
/// against that rounding would be a number of 10¹⁶ meaning nothing.
///
/// # Examples
/// ```
/// use beltrami_metrics::measures::volume_ratio;
/// assert_eq!(volume_ratio(0.5, 1.0, 2.0), Some(0.5));
/// assert_eq!(volume_ratio(0.5, 3e-17, 1.0), None);
/// assert_eq!(volume_ratio(0.5, 0.0, 1.0), None);
/// ```
#[must_use]
pub fn volume_ratio(mesh: f64, reference: f64, extent: f64) -> Option<f64> {
    let negligible = 1e-12 * extent * extent * extent;
    (reference.abs() > negligible)
        .then(|| mesh / reference)
        .filter(|r| r.is_finite())
}

/// The total area of a mesh's faces, in unit² (compensated sum of the face areas; a thin
/// wrapper of [`Geometry::surface_area`]).
///
/// # Errors
/// [`MetricsError::Empty`] for a mesh without faces; [`MetricsError::NonFinite`] for a
/// non-finite position.
pub fn surface_area(geometry: &Geometry<'_>) -> Result<f64, MetricsError> {
    check(geometry)?;
    Ok(geometry.surface_area())
}

/// Refuses a mesh without faces and non-finite positions.
fn check(geometry: &Geometry<'_>) -> Result<(), MetricsError> {
    if geometry.mesh().n_faces() == 0 {
        return Err(MetricsError::Empty { what: "mesh" });
    }
    if let Some(index) = geometry.positions().iter().position(|p| !p.is_finite()) {
        return Err(MetricsError::NonFinite {
            what: "position",
            index,
        });
    }
    Ok(())
}
