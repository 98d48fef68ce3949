//! Comparing profiles: total length, deviation of one profile from another.

use beltrami_halfedge::DVec3;
use rayon::prelude::*;

use super::Polyline;
use crate::MetricsError;
use crate::distortion::robust_length;

/// The total length of a profile: the sum of [`Polyline::length`] over its polylines, in
/// the unit of the positions.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::profile::{cross_section, profile_length, Plane};
///
/// let grid = primitives::grid(3, 2);
/// let mesh = grid.mesh()?;
/// let plane = Plane::new(DVec3::new(0.0, 0.5, 0.0), DVec3::Y)?;
/// let section = cross_section(&Geometry::new(&mesh, &grid.positions)?, &plane)?;
/// assert!((profile_length(&section) - 3.0).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn profile_length(profile: &[Polyline]) -> f64 {
    profile.iter().map(Polyline::length).sum()
}

/// The deviation of a profile from a reference profile: for every point of `profile`,
/// the distance to the nearest segment of `reference`; the statistics of these distances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileDeviation {
    /// The number of points of the profile.
    pub count: usize,
    /// The mean distance.
    pub mean: f64,
    /// The root mean square distance, `sqrt(Σ d² / count)`.
    pub rms: f64,
    /// The largest distance (the one-sided Hausdorff distance from the profile's points to
    /// the reference polylines).
    pub max: f64,
}

/// The deviation of `profile` from `reference`: for each point `p` of `profile`, the
/// Euclidean distance `d(p) = min_s |p − s|` to the nearest point `s` on any segment of
/// `reference` (closing segments of closed polylines included; a single-point polyline
/// counts as a point); then the mean, RMS and maximum of `d` over all points of
/// `profile`, in the unit of the positions.
///
/// The measure is one-sided: swap the arguments for the other direction (the maximum of
/// both is the symmetric Hausdorff distance between the point sets and the polylines).
/// It is unsigned and three-dimensional; for profiles of the same plane it is the
/// in-plane distance.
///
/// # Errors
/// - [`MetricsError::Empty`] when `profile` or `reference` has no point
///   (`what = "profile"` or `"reference profile"`);
/// - [`MetricsError::NonFinite`] with `what = "profile point"` or
///   `"reference profile point"` and the index of the point, counted through the
///   polylines in order.
///
/// # Complexity
/// O(|profile| × |reference|) distance evaluations, in parallel over the points of
/// `profile`; the statistics are summed in order, so the result does not depend on the
/// number of threads.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::profile::{cross_section, profile_deviation, Plane};
///
/// // The same grid at z = 0 and lifted to z = 0.25, cut by the same plane.
/// let grid = primitives::grid(3, 3);
/// let mesh = grid.mesh()?;
/// let lifted: Vec<DVec3> = grid.positions.iter().map(|&p| p + DVec3::new(0.0, 0.0, 0.25)).collect();
/// let plane = Plane::new(DVec3::new(1.5, 0.0, 0.0), DVec3::X)?;
/// let a = cross_section(&Geometry::new(&mesh, &lifted)?, &plane)?;
/// let b = cross_section(&Geometry::new(&mesh, &grid.positions)?, &plane)?;
/// let deviation = profile_deviation(&a, &b)?;
/// assert!((deviation.rms - 0.25).abs() < 1e-15 && (deviation.max - 0.25).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn profile_deviation(
    profile: &[Polyline],
    reference: &[Polyline],
) -> Result<ProfileDeviation, MetricsError> {
    let points = finite_points(profile, "profile", "profile point")?;
    finite_points(reference, "reference profile", "reference profile point")?;
    let segments: Vec<(DVec3, DVec3)> = reference
        .iter()
        .flat_map(|line| match line.points.as_slice() {
            [only] => vec![(only.position, only.position)],
            _ => line.segments().collect(),
        })
        .collect();
    let distances: Vec<f64> = points
        .par_iter()
        .map(|&p| {
            segments
                .iter()
                .map(|&(a, b)| distance_to_segment(p, a, b))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let count = distances.len();
    let n = count as f64;
    let (sum, sum_sq, max) = distances.iter().fold((0.0, 0.0, 0.0f64), |(s, q, m), &d| {
        (s + d, q + d * d, m.max(d))
    });
    Ok(ProfileDeviation {
        count,
        mean: sum / n,
        rms: (sum_sq / n).sqrt(),
        max,
    })
}

/// All point positions of `lines`, checked to be finite and non-empty.
fn finite_points(
    lines: &[Polyline],
    empty: &'static str,
    point: &'static str,
) -> Result<Vec<DVec3>, MetricsError> {
    let positions: Vec<DVec3> = lines.iter().flat_map(Polyline::positions).collect();
    if positions.is_empty() {
        return Err(MetricsError::Empty { what: empty });
    }
    if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
        return Err(MetricsError::NonFinite { what: point, index });
    }
    Ok(positions)
}

/// The distance from `p` to the segment `[a, b]` (to `a` when the segment is a point).
fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let ap = p - a;
    let len_sq = ab.length_squared();
    // A NaN quotient (products overflowing at extreme coordinates) counts as 0.
    let q = if len_sq > 0.0 {
        ap.dot(ab) / len_sq
    } else {
        0.0
    };
    let t = if q.is_nan() { 0.0 } else { q.clamp(0.0, 1.0) };
    // The closest point measured from the nearer end keeps the rounding small at t ≈ 1.
    if t <= 0.5 {
        robust_length(ap - t * ab)
    } else {
        robust_length((p - b) + (1.0 - t) * ab)
    }
}
