//! The least-squares cylinder.

use beltrami_halfedge::DVec3;

use super::linalg::{canonical_sign, orthogonal, symmetric_eigen3};
use super::lm::{Model, Normalised, cost, levenberg_marquardt};
use super::{FitOptions, FitPoints, covariance, kasa_circle, residual_summary};
use crate::MetricsError;

/// A fitted cylinder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CylinderFit {
    /// The point of the axis closest to the (weighted) centroid of the points: the middle
    /// of the measured stretch for evenly spread data.
    pub axis_point: DVec3,
    /// The unit axis direction, with its largest-magnitude component positive.
    pub axis: DVec3,
    /// The radius.
    pub radius: f64,
    /// Weighted RMS of the residuals (see [`CylinderFit::residual`]).
    pub rms_residual: f64,
    /// Largest absolute residual.
    pub max_residual: f64,
    /// Levenberg–Marquardt iterations done (for the start that was kept).
    pub iterations: usize,
    /// Whether the refinement met its tolerance.
    pub converged: bool,
}

impl CylinderFit {
    /// The signed orthogonal distance from `p` to the cylinder: its distance from the axis
    /// minus the radius (positive outside).
    #[must_use]
    pub fn residual(&self, p: DVec3) -> f64 {
        (p - self.axis_point).cross(self.axis).length() - self.radius
    }
}

/// The cylinder in normalised coordinates: `point` is on the axis and orthogonal to it
/// (the axis point nearest the centroid, which is the origin), `e1`, `e2` complete the
/// axis to an orthonormal frame.
#[derive(Clone, Copy, Debug)]
struct Cylinder {
    point: DVec3,
    axis: DVec3,
    radius: f64,
    e1: DVec3,
    e2: DVec3,
}

impl Cylinder {
    fn new(point: DVec3, axis: DVec3, radius: f64) -> Self {
        let e1 = orthogonal(axis);
        Self {
            point: point - axis * point.dot(axis),
            axis,
            radius,
            e1,
            e2: axis.cross(e1),
        }
    }
}

impl Model<5> for Cylinder {
    /// Steps: the axis point along `e1`, `e2`; the axis tilted towards `e1`, `e2`; the
    /// radius.
    fn residual(&self, q: DVec3) -> (f64, [f64; 5]) {
        let v = q - self.point;
        let w = v.cross(self.axis);
        let rho = w.length();
        let u = if rho > 0.0 { w / rho } else { DVec3::ZERO };
        (
            rho - self.radius,
            [
                -u.dot(self.e1.cross(self.axis)),
                -u.dot(self.e2.cross(self.axis)),
                u.dot(v.cross(self.e1)),
                u.dot(v.cross(self.e2)),
                -1.0,
            ],
        )
    }

    fn moved(&self, step: &[f64; 5]) -> Option<Self> {
        let point = self.point + self.e1 * step[0] + self.e2 * step[1];
        let axis = (self.axis + self.e1 * step[2] + self.e2 * step[3]).normalize();
        let radius = self.radius + step[4];
        (axis.is_finite() && point.length() < LIMIT && radius.abs() < LIMIT)
            .then(|| Self::new(point, axis, radius))
    }
}

/// Beyond this many RMS radii of the data, the points are closer to a plane than to any
/// cylinder.
const LIMIT: f64 = 1e8;

/// The least-squares cylinder through `points`: the axis (a point `x₀` and a unit
/// direction `a`) and radius `r` minimising `Σ w_i (|(p_i − x₀) × a| − r)²`, over five
/// parameters (two for the direction, two for the axis point in the plane through the
/// centroid orthogonal to the axis, one for the radius).
///
/// Starts: the supplied `axis_guess`, or else each principal axis of the weighted
/// covariance in turn (the long direction of a long cylinder, but the axis of a short one
/// or of a partial arc can be any of them). For each start, the points are projected onto
/// the plane orthogonal to it and Kåsa's circle gives the axis point and radius; then
/// Levenberg–Marquardt refines all five parameters. The refined start with the smallest
/// residual cost is kept.
///
/// # Errors
/// - [`MetricsError::TooFewPoints`] for fewer than 5 points of positive weight;
/// - [`MetricsError::Degenerate`] when the points are collinear, no start gives a
///   circle, or the least-squares plane fits them better than the best cylinder found
///   (a flat patch);
/// - [`MetricsError::NoConvergence`] when every refinement runs off towards a plane;
/// - [`MetricsError::NonFinite`] for a non-finite point,
///   [`MetricsError::InvalidParameter`] for a zero or non-finite `axis_guess` or invalid
///   options.
///
/// # References
/// Shakarji 1998 (§ cylinders: the parametrisation and Levenberg–Marquardt); Kåsa 1976.
pub fn fit_cylinder(
    input: &FitPoints<'_>,
    axis_guess: Option<DVec3>,
    options: &FitOptions,
) -> Result<CylinderFit, MetricsError> {
    const SHAPE: &str = "cylinder";
    options.check()?;
    if let Some(guess) = axis_guess
        && !(guess.is_finite() && guess.length() > 0.0)
    {
        return Err(MetricsError::InvalidParameter {
            name: "axis_guess",
            reason: "must be a finite non-zero vector",
        });
    }
    let data = input.normalise(SHAPE, 5)?;
    let (values, vectors) = symmetric_eigen3(covariance(&data));
    if values[1] <= 1e-20 * values[2] {
        return Err(MetricsError::Degenerate {
            shape: SHAPE,
            reason: "the points are collinear",
        });
    }
    let starts: Vec<DVec3> = match axis_guess {
        Some(guess) => vec![guess.normalize()],
        None => vec![vectors[2], vectors[0], vectors[1]],
    };
    let mut best: Option<(f64, super::lm::Outcome<Cylinder>)> = None;
    let mut diverged = None;
    for axis in starts {
        let Some(start) = start_from(&data, axis) else {
            continue;
        };
        match levenberg_marquardt(&data, start, options) {
            Ok(outcome) => {
                let c = cost(&outcome.model, &data);
                if best.as_ref().is_none_or(|(b, _)| c < *b) {
                    best = Some((c, outcome));
                }
            }
            Err(d) => diverged = Some(d.iterations),
        }
    }
    // A plane is the limit of cylinders of growing radius: a best cylinder whose
    // residual exceeds the least-squares plane's is a local minimum worse than that
    // limit (a flat patch fitted by a cylinder standing on it), not the fit.
    // (Points on a circle lie on both exactly: rounding decides nothing there.)
    if let Some((c, _)) = &best
        && *c > values[0] + 1e-12 * (values[0] + values[1] + values[2])
    {
        return Err(MetricsError::Degenerate {
            shape: SHAPE,
            reason: "no cylinder found fits the points better than their least-squares plane (a flat patch); fit a plane instead",
        });
    }
    let Some((_, outcome)) = best else {
        return Err(match diverged {
            Some(iterations) => MetricsError::NoConvergence {
                shape: SHAPE,
                iterations,
            },
            None => MetricsError::Degenerate {
                shape: SHAPE,
                reason: "the points do not determine a cylinder",
            },
        });
    };
    let model = outcome.model;
    let fit = CylinderFit {
        axis_point: data.origin + model.point * data.scale,
        axis: canonical_sign(model.axis),
        radius: model.radius.abs() * data.scale,
        rms_residual: 0.0,
        max_residual: 0.0,
        iterations: outcome.iterations,
        converged: outcome.converged,
    };
    let (rms, max) = residual_summary(input, |p| fit.residual(p));
    Ok(CylinderFit {
        rms_residual: rms,
        max_residual: max,
        ..fit
    })
}

/// The start for a candidate axis: Kåsa's circle of the points projected onto the plane
/// orthogonal to it.
fn start_from(data: &Normalised, axis: DVec3) -> Option<Cylinder> {
    let e1 = orthogonal(axis);
    let e2 = axis.cross(e1);
    let (a, b, r) = kasa_circle(
        data.points
            .iter()
            .zip(&data.weights)
            .map(|(q, &w)| (q.dot(e1), q.dot(e2), w)),
    )?;
    let point = e1 * a + e2 * b;
    (point.length() < LIMIT && r < LIMIT).then(|| Cylinder::new(point, axis, r))
}
