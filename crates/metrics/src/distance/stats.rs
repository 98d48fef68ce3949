//! Summary statistics of vertex distances to a reference surface.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, ElementId, FaceId, HalfedgeMesh};
use rayon::prelude::*;

use super::index::SurfaceIndex;
use crate::MetricsError;
use crate::sum::Sum;

/// Statistics of unsigned distances (or displacements) over the vertices of a mesh, in the
/// positions' unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceStats {
    /// Root mean square over vertices, `sqrt(Σ d_i² / N)`: the paper's smoothness metric.
    pub rms: f64,
    /// Mean, `Σ d_i / N`.
    pub mean: f64,
    /// Maximum (the one-sided Hausdorff distance over vertices).
    pub max: f64,
    /// Area-weighted root mean square, `sqrt(Σ A_i d_i² / Σ A_i)`, with `A_i` the
    /// barycentric area of vertex `i` (a third of its incident triangles' areas) on the
    /// measured mesh. It removes the bias of vertex averages on irregular meshes. Equal to
    /// [`rms`](Self::rms) when the mesh has no area (a point set).
    pub area_weighted_rms: f64,
    /// The number of vertices, `N`.
    pub count: usize,
}

impl DistanceStats {
    /// Statistics of `distances` (non-negative), with `areas` the weight of each value for
    /// [`area_weighted_rms`](Self::area_weighted_rms).
    ///
    /// Sums are compensated and sequential, so the result is accurate to about one rounding
    /// and does not depend on the thread count.
    ///
    /// # Errors
    /// [`MetricsError::Empty`] for no distances; [`MetricsError::FieldLength`] when `areas`
    /// has another length; [`MetricsError::NonFinite`] for a non-finite distance or area;
    /// [`MetricsError::InvalidParameter`] for a negative distance or area.
    ///
    /// # References
    /// The RMS, mean and maximum are those of Metro (P. Cignoni, C. Rocchini, R. Scopigno:
    /// *Metro: measuring error on simplified surfaces*. Computer Graphics Forum 17(2),
    /// 1998); the area-weighted RMS is the L2 vertex error of mesh-denoising benchmarks
    /// (X. Sun, P. L. Rosin, R. R. Martin, F. C. Langbein: *Fast and effective
    /// feature-preserving mesh denoising*. IEEE TVCG 13(5), 2007).
    pub fn new(distances: &[f64], areas: &[f64]) -> Result<Self, MetricsError> {
        if distances.is_empty() {
            return Err(MetricsError::Empty {
                what: "distance set",
            });
        }
        if areas.len() != distances.len() {
            return Err(MetricsError::FieldLength {
                what: "vertex areas",
                got: areas.len(),
                expected: distances.len(),
            });
        }
        check_values(distances, "distance")?;
        check_values(areas, "vertex area")?;
        let mut sum = Sum::default();
        let mut squares = Sum::default();
        let mut weighted = Sum::default();
        let mut weights = Sum::default();
        let mut max = 0.0f64;
        for (&d, &a) in distances.iter().zip(areas) {
            sum.add(d);
            squares.add(d * d);
            weighted.add(a * d * d);
            weights.add(a);
            max = max.max(d);
        }
        let n = distances.len() as f64;
        let rms = (squares.value() / n).sqrt();
        let total = weights.value();
        let area_weighted_rms = if total > 0.0 && total.is_finite() {
            (weighted.value() / total).sqrt()
        } else {
            rms
        };
        Ok(Self {
            rms,
            mean: sum.value() / n,
            max,
            area_weighted_rms,
            count: distances.len(),
        })
    }
}

/// Statistics of signed distances over the vertices of a mesh, in the positions' unit
/// (positive on the side the reference's normals point to).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistanceStats {
    /// Mean signed distance, `Σ s_i / N`: a bias (a shrunk smoothed sphere has a negative
    /// mean).
    pub mean: f64,
    /// Most negative signed distance (deepest point inside).
    pub min: f64,
    /// Most positive signed distance (farthest point outside).
    pub max: f64,
    /// Standard deviation about the mean, `sqrt(Σ (s_i − mean)² / N)`.
    pub std_dev: f64,
    /// The number of vertices, `N`.
    pub count: usize,
}

impl SignedDistanceStats {
    /// Statistics of `signed` distances.
    ///
    /// # Errors
    /// [`MetricsError::Empty`] for no values; [`MetricsError::NonFinite`] for a non-finite
    /// value.
    pub fn new(signed: &[f64]) -> Result<Self, MetricsError> {
        if signed.is_empty() {
            return Err(MetricsError::Empty {
                what: "distance set",
            });
        }
        let mut sum = Sum::default();
        let mut min = f64::INFINITY;
        let mut max = f64::NEG_INFINITY;
        for (index, &s) in signed.iter().enumerate() {
            if !s.is_finite() {
                return Err(MetricsError::NonFinite {
                    what: "signed distance",
                    index,
                });
            }
            sum.add(s);
            min = min.min(s);
            max = max.max(s);
        }
        let n = signed.len() as f64;
        let mean = sum.value() / n;
        let mut spread = Sum::default();
        for &s in signed {
            spread.add((s - mean) * (s - mean));
        }
        Ok(Self {
            mean,
            min,
            max,
            std_dev: (spread.value() / n).sqrt(),
            count: signed.len(),
        })
    }
}

/// Distance statistics of the vertices of a mesh (`mesh` with `positions`) against a
/// reference surface: each vertex's distance to the closest point on the closest reference
/// triangle, then RMS, mean, max and area-weighted RMS (see [`DistanceStats`]).
///
/// Every vertex counts, isolated ones included (they have no area, so they do not enter
/// the area-weighted RMS).
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::distance::{SurfaceIndex, distance_stats};
///
/// let grid = primitives::grid(4, 4);
/// let reference = SurfaceIndex::new(&grid.mesh()?, &grid.positions)?;
/// let lifted: Vec<DVec3> = grid.positions.iter().map(|p| *p + DVec3::Z * 0.5).collect();
/// let stats = distance_stats(&grid.mesh()?, &lifted, &reference)?;
/// assert_eq!((stats.rms, stats.max, stats.count), (0.5, 0.5, 25));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`MetricsError::Topology`] when `positions` does not match the mesh;
/// [`MetricsError::Empty`] for a mesh without vertices; [`MetricsError::NonFinite`]
/// (`"position"`, with the vertex index) or [`MetricsError::InvalidParameter`] for a bad
/// position.
///
/// # References
/// Cignoni, Rocchini, Scopigno, *Metro*, CGF 17(2), 1998 (vertex sampling, RMS/mean/max);
/// Eberly 1999 (point–triangle distance).
pub fn distance_stats(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    reference: &SurfaceIndex,
) -> Result<DistanceStats, MetricsError> {
    let areas = vertex_areas(mesh, positions)?;
    let distances = reference.distances(positions)?;
    DistanceStats::new(&distances, &areas)
}

/// Signed-distance statistics of the vertices of a mesh against a reference surface (see
/// [`SurfaceIndex::signed_distance`] for the sign and [`SignedDistanceStats`]).
///
/// # Errors
/// As for [`distance_stats`].
pub fn signed_distance_stats(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    reference: &SurfaceIndex,
) -> Result<SignedDistanceStats, MetricsError> {
    let _ = Geometry::new(mesh, positions)?;
    if positions.is_empty() {
        return Err(MetricsError::Empty { what: "mesh" });
    }
    super::index::check_points(positions, "vertex")?;
    let signed = reference.signed_distances(positions)?;
    SignedDistanceStats::new(&signed)
}

/// The barycentric vertex areas of a mesh (a third of each incident triangle, `1/k` of a
/// `k`-gon), after checking the positions. Face areas are computed in parallel and added
/// to their vertices in face order, so the result does not depend on the thread count.
pub(crate) fn vertex_areas(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
) -> Result<Vec<f64>, MetricsError> {
    let geometry = Geometry::new(mesh, positions)?;
    if positions.is_empty() {
        return Err(MetricsError::Empty { what: "mesh" });
    }
    super::index::check_points(positions, "vertex")?;
    let face_areas: Vec<f64> = (0..mesh.n_faces())
        .into_par_iter()
        .map(|f| geometry.face_area(FaceId::from_index(f)))
        .collect();
    let mut areas = vec![0.0; mesh.n_vertices()];
    for (f, area) in mesh.faces().zip(face_areas) {
        let share = area / mesh.face_valence(f) as f64;
        for v in mesh.vertices_around_face(f) {
            areas[v.index()] += share;
        }
    }
    Ok(areas)
}

fn check_values(values: &[f64], what: &'static str) -> Result<(), MetricsError> {
    for (index, &v) in values.iter().enumerate() {
        if !v.is_finite() {
            return Err(MetricsError::NonFinite { what, index });
        }
        if v < 0.0 {
            return Err(MetricsError::InvalidParameter {
                name: what,
                reason: "must not be negative",
            });
        }
    }
    Ok(())
}
