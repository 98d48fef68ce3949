//! The symmetric Hausdorff distance between two surfaces, over vertices and samples.

use beltrami_halfedge::DVec3;

use super::index::SurfaceIndex;
use crate::MetricsError;
use crate::sum::Sum;

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
        HausdorffSampling::VerticesAndSurface { samples: 0, .. } => on_vertices,
        HausdorffSampling::VerticesAndSurface { samples, seed } => {
            on_vertices.max(sampled_distance(from, to, samples, seed)?.max)
        }
    })
}

/// The distances from points spread uniformly by area over one surface to another
/// (Metro's face sampling), summarised: estimates of the one-sided surface-to-surface
/// distances, in the positions' unit. Unlike statistics over the vertices they weigh
/// every part of the surface by its area, face interiors included, so a simplified mesh
/// whose vertices lie on the reference but whose faces cut below it is not judged by
/// its vertices alone.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SampledDistance {
    /// The largest sampled distance (a lower bound of the one-sided Hausdorff distance).
    pub max: f64,
    /// The mean distance, `Σ d / N`: Metro's mean error.
    pub mean: f64,
    /// The root mean square distance, `sqrt(Σ d² / N)`: Metro's RMS error, the
    /// area-weighted L2 distance of the surfaces.
    pub rms: f64,
    /// The number of samples `N`.
    pub samples: usize,
}

/// Measures the distance from `samples` points of `from`'s surface, spread uniformly by
/// area with [`SurfaceIndex::sample_surface`]`(samples, seed)`, to the surface of `to`.
///
/// The sums are compensated and sequential, so the result does not depend on the thread
/// count.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::distance::{SurfaceIndex, sampled_distance};
///
/// // A unit square 0.5 above a larger one: every point of it is 0.5 away.
/// let high = primitives::grid(1, 1);
/// let lifted: Vec<_> = high.positions.iter().map(|p| *p + glam::DVec3::Z * 0.5).collect();
/// let large = primitives::grid(2, 2);
/// let a = SurfaceIndex::new(&high.mesh()?, &lifted)?;
/// let b = SurfaceIndex::new(&large.mesh()?, &large.positions)?;
/// let d = sampled_distance(&a, &b, 1000, 7)?;
/// assert!((d.rms - 0.5).abs() < 1e-12 && (d.max - 0.5).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`MetricsError::InvalidParameter`] for `samples == 0`; otherwise the query errors of
/// [`SurfaceIndex::distances`] (none in practice: both indexes hold validated surfaces).
///
/// # References
/// Cignoni, Rocchini, Scopigno: *Metro: measuring error on simplified surfaces*. Computer
/// Graphics Forum 17(2), 1998.
pub fn sampled_distance(
    from: &SurfaceIndex,
    to: &SurfaceIndex,
    samples: usize,
    seed: u64,
) -> Result<SampledDistance, MetricsError> {
    if samples == 0 {
        return Err(MetricsError::InvalidParameter {
            name: "samples",
            reason: "must be at least 1",
        });
    }
    let distances = to.distances(&from.sample_surface(samples, seed))?;
    let mut sum = Sum::default();
    let mut squares = Sum::default();
    let mut max = 0.0f64;
    for &d in &distances {
        sum.add(d);
        squares.add(d * d);
        max = max.max(d);
    }
    let n = distances.len() as f64;
    Ok(SampledDistance {
        max,
        mean: sum.value() / n,
        rms: (squares.value() / n).sqrt(),
        samples: distances.len(),
    })
}

/// The distances between two surfaces both ways, as `beltrami compare` reports them: the
/// symmetric Hausdorff distance over the vertices and, with surface samples, over those
/// too, with the samples' statistics ([`surface_distance`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SurfaceDistance {
    /// The Hausdorff distances, from the vertices and the samples.
    pub hausdorff: HausdorffDistance,
    /// With samples: the distances of `from`'s samples to `to` and of `to`'s samples to
    /// `from`, in that order.
    pub sampled: Option<(SampledDistance, SampledDistance)>,
}

/// The Hausdorff distance between the surfaces of `from` and `to` over their vertices
/// and, when `samples > 0`, over `samples` area-uniform points of each
/// ([`sampled_distance`] with `seed`, whose statistics are returned too), for a caller
/// that already has the distances of `from`'s vertices to `to`
/// (`from_vertex_distances`, signed or unsigned; see
/// [`one_sided_hausdorff_from_vertex_distances`]). Each sample set is queried once.
///
/// # Errors
/// As for [`one_sided_hausdorff_from_vertex_distances`] and [`sampled_distance`].
pub fn surface_distance(
    from: &SurfaceIndex,
    from_vertex_distances: &[f64],
    to: &SurfaceIndex,
    samples: usize,
    seed: u64,
) -> Result<SurfaceDistance, MetricsError> {
    let vertices = HausdorffSampling::Vertices;
    let forward =
        one_sided_hausdorff_from_vertex_distances(from, from_vertex_distances, to, vertices)?;
    let backward = one_sided_hausdorff(to, from, vertices)?;
    let sampled = if samples == 0 {
        None
    } else {
        Some((
            sampled_distance(from, to, samples, seed)?,
            sampled_distance(to, from, samples, seed)?,
        ))
    };
    let (forward, backward) = match &sampled {
        None => (forward, backward),
        Some((there, back)) => (forward.max(there.max), backward.max(back.max)),
    };
    Ok(SurfaceDistance {
        hausdorff: HausdorffDistance::from_one_sided(forward, backward),
        sampled,
    })
}
