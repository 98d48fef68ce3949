//! The symmetric Hausdorff distance between two surfaces, over vertices and samples.

use beltrami_halfedge::DVec3;

use super::index::SurfaceIndex;
use crate::MetricsError;

/// Which points of each surface are measured against the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HausdorffSampling {
    /// The vertices that belong to a face (isolated vertices are not on the surface).
    Vertices,
    /// The vertices, plus `samples` points per surface spread uniformly by area with
    /// [`SurfaceIndex::sample_surface`] (the same `seed` for both surfaces). Samples catch
    /// the far-off face interiors that vertices miss, as Metro's face sampling does.
    VerticesAndSurface {
        /// Samples per surface.
        samples: usize,
        /// The seed of the sample stream.
        seed: u64,
    },
}

/// One-sided and symmetric Hausdorff distances between two surfaces `A` and `B`, in the
/// positions' unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HausdorffDistance {
    /// `max over sampled a ∈ A of d(a, B)`: how far `A` strays from `B`.
    pub forward: f64,
    /// `max over sampled b ∈ B of d(b, A)`.
    pub backward: f64,
    /// `max(forward, backward)`, the symmetric Hausdorff distance.
    pub symmetric: f64,
}

impl HausdorffDistance {
    /// The symmetric distance of two one-sided ones (`symmetric` is their maximum), for a
    /// caller that computed them separately (e.g. `forward` from distances it already
    /// has, `backward` with [`one_sided_hausdorff`]).
    #[must_use]
    pub fn from_one_sided(forward: f64, backward: f64) -> Self {
        Self {
            forward,
            backward,
            symmetric: forward.max(backward),
        }
    }
}

/// The Hausdorff distance between the surfaces of two indexes, sampled as `sampling` says.
///
/// Each one-sided distance is the largest distance from a sample point of one surface to
/// the closest point of the other surface (exact point–triangle distances). With vertex
/// sampling only, the one-sided values are lower bounds of the true one-sided Hausdorff
/// distances (exact when the farthest point is a vertex, as for a patch inside a larger
/// one); surface samples tighten them. MeshLab's *Hausdorff Distance* filter reports a
/// single direction; this reports both and their maximum.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::distance::{HausdorffSampling, SurfaceIndex, hausdorff};
///
/// // A 1 × 1 square inside a 2 × 2 square, in the same plane.
/// let small = primitives::grid(1, 1);
/// let large = primitives::grid(2, 2);
/// let a = SurfaceIndex::new(&small.mesh()?, &small.positions)?;
/// let b = SurfaceIndex::new(&large.mesh()?, &large.positions)?;
/// let h = hausdorff(&a, &b, HausdorffSampling::Vertices)?;
/// assert_eq!(h.forward, 0.0); // every point of the small square is on the large one
/// assert_eq!(h.backward, 2f64.sqrt()); // the far corner (2, 2) to (1, 1)
/// assert_eq!(h.symmetric, h.backward);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// None in practice: both indexes hold validated, non-empty surfaces. The `Result` carries
/// the query errors of [`SurfaceIndex::distances`].
///
/// # References
/// Cignoni, Rocchini, Scopigno: *Metro: measuring error on simplified surfaces*. Computer
/// Graphics Forum 17(2), 1998.
pub fn hausdorff(
    a: &SurfaceIndex,
    b: &SurfaceIndex,
    sampling: HausdorffSampling,
) -> Result<HausdorffDistance, MetricsError> {
    let forward = one_sided_hausdorff(a, b, sampling)?;
    let backward = one_sided_hausdorff(b, a, sampling)?;
    Ok(HausdorffDistance::from_one_sided(forward, backward))
}

/// The one-sided Hausdorff distance from the surface of `from` to that of `to`, in the
/// positions' unit: the largest distance from a sample point of `from` (its vertices on a
/// face, plus surface samples as `sampling` says) to the closest point of `to`. A lower
/// bound of the true one-sided distance (see [`hausdorff`]); `0` or more.
///
/// # Errors
/// None in practice (both indexes hold validated surfaces); the `Result` carries the
/// query errors of [`SurfaceIndex::distances`].
pub fn one_sided_hausdorff(
    from: &SurfaceIndex,
    to: &SurfaceIndex,
    sampling: HausdorffSampling,
) -> Result<f64, MetricsError> {
    let mut points: Vec<DVec3> = from.surface_vertices();
    if let HausdorffSampling::VerticesAndSurface { samples, seed } = sampling {
        points.extend(from.sample_surface(samples, seed));
    }
    let distances = to.distances(&points)?;
    Ok(distances.iter().fold(0.0f64, |m, &d| m.max(d)))
}

/// [`one_sided_hausdorff`] for a caller that already has the distances of `from`'s
/// vertices to `to`, for example from [`SurfaceIndex::signed_distances`] of the mesh it
/// also reports signed statistics for: only the surface samples are queried, and the
/// vertex pass is not repeated.
///
/// `vertex_distances[v]` is the distance of vertex `v` of `from` to the surface of `to`,
/// signed or unsigned (its absolute value counts). Vertices that belong to no face are
/// skipped, as in [`one_sided_hausdorff`], so for the distances `to` gives this returns
/// the same value as [`one_sided_hausdorff`]`(from, to, sampling)`.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::distance::{
///     HausdorffSampling, SurfaceIndex, one_sided_hausdorff,
///     one_sided_hausdorff_from_vertex_distances,
/// };
///
/// let small = primitives::grid(1, 1);
/// let large = primitives::grid(2, 2);
/// let a = SurfaceIndex::new(&small.mesh()?, &small.positions)?;
/// let b = SurfaceIndex::new(&large.mesh()?, &large.positions)?;
/// let signed = a.signed_distances(&large.positions)?; // large's vertices to small
/// let sampling = HausdorffSampling::Vertices;
/// let h = one_sided_hausdorff_from_vertex_distances(&b, &signed, &a, sampling)?;
/// assert_eq!(h, one_sided_hausdorff(&b, &a, sampling)?);
/// assert_eq!(h, 2f64.sqrt()); // the far corner (2, 2) to (1, 1)
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`MetricsError::FieldLength`] when `vertex_distances` does not have one value per
/// vertex of `from`; otherwise as for [`one_sided_hausdorff`].
pub fn one_sided_hausdorff_from_vertex_distances(
    from: &SurfaceIndex,
    vertex_distances: &[f64],
    to: &SurfaceIndex,
    sampling: HausdorffSampling,
) -> Result<f64, MetricsError> {
    let n = from.positions().len();
    if vertex_distances.len() != n {
        return Err(MetricsError::FieldLength {
            what: "vertex distances",
            got: vertex_distances.len(),
            expected: n,
        });
    }
    let on_vertices = vertex_distances
        .iter()
        .zip(from.on_surface())
        .filter(|&(_, on)| on)
        .fold(0.0f64, |m, (d, _)| m.max(d.abs()));
    Ok(match sampling {
        HausdorffSampling::Vertices => on_vertices,
        HausdorffSampling::VerticesAndSurface { samples, seed } => {
            let points = from.sample_surface(samples, seed);
            let far = to.distances(&points)?.into_iter().fold(0.0f64, f64::max);
            on_vertices.max(far)
        }
    })
}
