//! The least-squares circle in 3-D: plane, then circle in the plane.

use beltrami_halfedge::DVec3;

use super::linalg::{canonical_sign, symmetric_eigen3};
use super::lm::{Model, Normalised, levenberg_marquardt};
use super::{FitOptions, FitPoints, covariance, kasa_circle, residual_summary};
use crate::MetricsError;
use crate::sum::Sum;

/// A fitted circle in space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircleFit {
    /// The centre.
    pub center: DVec3,
    /// The unit normal of the circle's plane, with its largest-magnitude component
    /// positive.
    pub axis: DVec3,
    /// The radius.
    pub radius: f64,
    /// Weighted RMS of the in-plane residuals (see [`CircleFit::residual`]).
    pub rms_residual: f64,
    /// Largest absolute in-plane residual.
    pub max_residual: f64,
    /// Weighted RMS distance of the points from the circle's plane (flatness of the data).
    pub plane_rms: f64,
    /// Levenberg–Marquardt iterations done (in-plane refinement).
    pub iterations: usize,
    /// Whether the refinement met its tolerance.
    pub converged: bool,
}

impl CircleFit {
    /// The signed in-plane residual of `p`: the distance from the axis through the centre,
    /// minus the radius (positive outside the circle). The out-of-plane part is
    /// `(p − center) · axis`.
    #[must_use]
    pub fn residual(&self, p: DVec3) -> f64 {
        let d = p - self.center;
        (d - self.axis * d.dot(self.axis)).length() - self.radius
    }

    /// The 3-D distance from `p` to the circle (curve), `sqrt(residual² + height²)`.
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        self.residual(p).hypot((p - self.center).dot(self.axis))
    }
}

/// A circle in the normalised plane coordinates (the third coordinate is unused).
#[derive(Clone, Copy, Debug)]
struct Circle {
    center: [f64; 2],
    radius: f64,
}

impl Model<3> for Circle {
    fn residual(&self, q: DVec3) -> (f64, [f64; 3]) {
        let (dx, dy) = (q.x - self.center[0], q.y - self.center[1]);
        let rho = dx.hypot(dy);
        let (ux, uy) = if rho > 0.0 {
            (dx / rho, dy / rho)
        } else {
            (0.0, 0.0)
        };
        (rho - self.radius, [-ux, -uy, -1.0])
    }

    fn moved(&self, step: &[f64; 3]) -> Option<Self> {
        let center = [self.center[0] + step[0], self.center[1] + step[1]];
        let radius = self.radius + step[2];
        (center[0].hypot(center[1]) < LIMIT && radius.abs() < LIMIT)
            .then_some(Self { center, radius })
    }
}

/// Beyond this many RMS radii of the data, the points are closer to a line than to a
/// circle.
const LIMIT: f64 = 1e8;

/// The least-squares circle through points in space, in two steps, as coordinate
/// metrology defines a circle measured in 3-D: the least-squares plane (through the
/// weighted centroid, normal to the eigenvector of the smallest eigenvalue of the weighted
/// covariance), then the least-squares circle of the points projected onto it (Kåsa's
/// algebraic start, Levenberg–Marquardt on the in-plane distances).
///
/// The reported residuals are in-plane radial deviations (roundness);
/// [`plane_rms`](CircleFit::plane_rms) reports the out-of-plane spread (flatness). For
/// points on a planar circle both steps are exact.
///
/// # Errors
/// - [`MetricsError::TooFewPoints`] for fewer than 3 points of positive weight;
/// - [`MetricsError::Degenerate`] when the points are collinear (or coincide);
/// - [`MetricsError::NoConvergence`] when the refinement runs off towards a line;
/// - [`MetricsError::NonFinite`] for a non-finite point, [`MetricsError::InvalidParameter`]
///   for invalid options.
///
/// # References
/// Kåsa 1976; Shakarji 1998 (planes by the singular vectors of the centred points;
/// circles by Levenberg–Marquardt).
pub fn fit_circle(input: &FitPoints<'_>, options: &FitOptions) -> Result<CircleFit, MetricsError> {
    const SHAPE: &str = "circle";
    options.check()?;
    let data = input.normalise(SHAPE, 3)?;
    let (values, vectors) = symmetric_eigen3(covariance(&data));
    if values[1] <= 1e-20 * values[2] {
        return Err(MetricsError::Degenerate {
            shape: SHAPE,
            reason: "the points are collinear",
        });
    }
    let normal = vectors[0];
    let e1 = vectors[2];
    let e2 = normal.cross(e1).normalize();
    let planar = Normalised {
        points: data
            .points
            .iter()
            .map(|q| DVec3::new(q.dot(e1), q.dot(e2), 0.0))
            .collect(),
        weights: data.weights.clone(),
        origin: data.origin,
        scale: data.scale,
    };
    let (a, b, r) = kasa_circle(
        planar
            .points
            .iter()
            .zip(&planar.weights)
            .map(|(q, &w)| (q.x, q.y, w)),
    )
    .ok_or(MetricsError::Degenerate {
        shape: SHAPE,
        reason: "the points do not determine a circle",
    })?;
    let start = Circle {
        center: [a, b],
        radius: r,
    };
    let outcome =
        levenberg_marquardt(&planar, start, options).map_err(|d| MetricsError::NoConvergence {
            shape: SHAPE,
            iterations: d.iterations,
        })?;
    let [cx, cy] = outcome.model.center;
    let center = data.origin + (e1 * cx + e2 * cy) * data.scale;
    let fit = CircleFit {
        center,
        axis: canonical_sign(normal),
        radius: outcome.model.radius.abs() * data.scale,
        rms_residual: 0.0,
        max_residual: 0.0,
        plane_rms: 0.0,
        iterations: outcome.iterations,
        converged: outcome.converged,
    };
    let (rms, max) = residual_summary(input, |p| fit.residual(p));
    let mut height = Sum::default();
    for (&q, &w) in data.points.iter().zip(&data.weights) {
        let h = q.dot(normal) * data.scale;
        height.add(w * h * h);
    }
    Ok(CircleFit {
        rms_residual: rms,
        max_residual: max,
        plane_rms: height.value().sqrt(),
        ..fit
    })
}
