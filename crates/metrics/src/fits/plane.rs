//! The least-squares plane.

use beltrami_halfedge::DVec3;

use super::linalg::{canonical_sign, orthogonal, symmetric_eigen3};
use super::{FitPoints, covariance, residual_summary};
use crate::MetricsError;

/// A fitted plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFit {
    /// The weighted centroid of the points, a point of the plane.
    pub point: DVec3,
    /// The unit normal, with its largest-magnitude component positive.
    pub normal: DVec3,
    /// Weighted RMS of the residuals `(p − point) · normal` (the flatness of the data).
    pub rms_residual: f64,
    /// Largest absolute residual.
    pub max_residual: f64,
}

impl PlaneFit {
    /// The signed orthogonal distance from `p` to the plane, `(p − point) · normal`
    /// (positive on the side the normal points to).
    #[must_use]
    pub fn residual(&self, p: DVec3) -> f64 {
        (p - self.point).dot(self.normal)
    }

    /// Two unit vectors that make `(u, v, normal)` a right-handed orthonormal frame, with
    /// `u` the projection of the x axis onto the plane (of the y axis when the plane is
    /// within about 6° of orthogonal to x): the in-plane axes that parameters measured in
    /// the plane (a texture direction, a polynomial form) refer to.
    #[must_use]
    pub fn in_plane_axes(&self) -> (DVec3, DVec3) {
        in_plane_axes(self.normal)
    }
}

/// `(u, v)` completing the unit `normal` to a right-handed frame, `u` along the
/// projection of x (or y, when x is nearly along the normal).
pub(crate) fn in_plane_axes(normal: DVec3) -> (DVec3, DVec3) {
    let project = |a: DVec3| a - normal * a.dot(normal);
    let x = project(DVec3::X);
    let u = if x.length() > 0.1 {
        x.normalize()
    } else {
        let y = project(DVec3::Y);
        if y.length() > 0.1 {
            y.normalize()
        } else {
            orthogonal(normal)
        }
    };
    (u, normal.cross(u))
}

/// The least-squares plane through `points`: the point `c` and unit normal `n`
/// minimising `Σ w_i ((p_i − c) · n)²`, the sum of squared orthogonal distances.
///
/// The solution is closed-form: `c` is the weighted centroid and `n` the eigenvector of
/// the smallest eigenvalue of the weighted covariance `Σ w_i (p_i − c)(p_i − c)ᵀ`
/// (principal-component analysis, computed by Jacobi rotations); the smallest eigenvalue
/// divided by `Σ w_i` is the squared RMS residual. Lengths are in the points' unit.
///
/// # Errors
/// - [`MetricsError::TooFewPoints`] for fewer than 3 points of positive weight;
/// - [`MetricsError::Degenerate`] when the points are collinear (or coincide), so that no
///   plane is determined;
/// - [`MetricsError::NonFinite`] for a non-finite point.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::fits::{FitPoints, fit_plane};
///
/// // A grid tilted about the y axis: z = 0.5 x.
/// let grid = primitives::grid(4, 4);
/// let tilted: Vec<DVec3> = grid.positions.iter().map(|p| DVec3::new(p.x, p.y, 0.5 * p.x)).collect();
/// let plane = fit_plane(&FitPoints::new(&tilted))?;
/// assert!((plane.normal - DVec3::new(-0.5, 0.0, 1.0).normalize()).length() < 1e-12);
/// assert!(plane.rms_residual < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// C. M. Shakarji: *Least-squares fitting algorithms of the NIST algorithm testing
/// system*. Journal of Research of NIST 103(6), 1998 (§ planes: the centroid and the
/// direction of least variance).
pub fn fit_plane(input: &FitPoints<'_>) -> Result<PlaneFit, MetricsError> {
    const SHAPE: &str = "plane";
    let data = input.normalise(SHAPE, 3)?;
    let (values, vectors) = symmetric_eigen3(covariance(&data));
    if values[1] <= 1e-20 * values[2] {
        return Err(MetricsError::Degenerate {
            shape: SHAPE,
            reason: "the points are collinear",
        });
    }
    let fit = PlaneFit {
        point: data.origin,
        normal: canonical_sign(vectors[0]),
        rms_residual: 0.0,
        max_residual: 0.0,
    };
    let (rms, max) = residual_summary(input, |p| fit.residual(p));
    Ok(PlaneFit {
        rms_residual: rms,
        max_residual: max,
        ..fit
    })
}
