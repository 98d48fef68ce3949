//! Least-squares plane, sphere, circle and cylinder fits (orthogonal distance
//! regression) and polynomial forms over a plane, on points or area-weighted over a mesh.
//!
//! The plane is closed-form (principal-component analysis); a polynomial form is linear
//! least squares in the plane's frame. Each other fit starts from an algebraic solution
//! (Kåsa's linear fit, after a principal-axis analysis where an orientation is needed) and
//! refines it by Levenberg–Marquardt on the orthogonal distances, the method of the NIST
//! Algorithm Testing System (Shakarji 1998). Iterations run on data centred on their
//! weighted centroid and scaled to unit RMS radius, so points far from the origin (a part
//! in machine coordinates) lose no digits.
//!
//! # Quick start
//!
//! ```
//! use beltrami_halfedge::primitives;
//! use beltrami_metrics::fits::{FitOptions, FitPoints, fit_sphere};
//!
//! let sphere = primitives::icosphere(3); // vertices on the unit sphere
//! let fit = fit_sphere(&FitPoints::new(&sphere.positions), &FitOptions::default())?;
//! assert!((fit.radius - 1.0).abs() < 1e-12 && fit.center.length() < 1e-12);
//! assert!(fit.converged && fit.rms_residual < 1e-12);
//!
//! // Area-weighted over the surface (barycentric vertex areas as weights).
//! let mesh = sphere.mesh()?;
//! let weighted = fit_sphere(&FitPoints::area_weighted(&mesh, &sphere.positions)?, &FitOptions::default())?;
//! assert!((weighted.radius - 1.0).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Conventions
//!
//! - Lengths in the positions' unit. Residuals are signed orthogonal distances (positive
//!   outside the sphere or cylinder, or beyond the circle's radius in its plane); with
//!   weights, the RMS residual is `sqrt(Σ w_i d_i² / Σ w_i)` and the maximum is over points
//!   of positive weight.
//! - Axes are unit vectors whose component of largest magnitude is positive.
//! - `converged` is false when the iteration limit stopped the refinement; the parameters
//!   are then the best found. An error is returned only when no meaningful fit exists.
//!
//! # References
//! - I. Kåsa: *A circle fitting procedure and its error analysis*. IEEE Transactions on
//!   Instrumentation and Measurement 25(1), 1976.
//! - V. Pratt: *Direct least-squares fitting of algebraic surfaces*. SIGGRAPH 1987.
//! - C. M. Shakarji: *Least-squares fitting algorithms of the NIST algorithm testing
//!   system*. Journal of Research of NIST 103(6), 1998.

mod circle;
mod cylinder;
mod linalg;
mod lm;
mod plane;
mod polynomial;
mod sphere;

use std::borrow::Cow;

use beltrami_halfedge::{DVec3, HalfedgeMesh};

pub use circle::{CircleFit, fit_circle};
pub use cylinder::{CylinderFit, fit_cylinder};
pub(crate) use plane::in_plane_axes;
pub use plane::{PlaneFit, fit_plane};
pub use polynomial::{MAX_POLYNOMIAL_DEGREE, PolynomialFit, fit_polynomial};
pub use sphere::{SphereFit, fit_sphere};

use crate::MetricsError;
use crate::sum::Sum;
use lm::Normalised;

/// Points to fit, each with an optional non-negative weight.
///
/// Weights scale each point's squared residual. Over a mesh,
/// [`area_weighted`](Self::area_weighted) uses barycentric vertex areas, so that the sum
/// `Σ A_i d_i²` approximates the surface integral `∫ d² dA` and dense patches of vertices do
/// not dominate the fit; with the plain vertex set, each vertex counts once.
#[derive(Clone, Debug)]
pub struct FitPoints<'a> {
    points: &'a [DVec3],
    weights: Option<Cow<'a, [f64]>>,
}

impl<'a> FitPoints<'a> {
    /// Unweighted points.
    #[must_use]
    pub fn new(points: &'a [DVec3]) -> Self {
        Self {
            points,
            weights: None,
        }
    }

    /// Points with one weight each.
    ///
    /// # Errors
    /// [`MetricsError::FieldLength`] when the lengths differ; [`MetricsError::NonFinite`]
    /// (`"weight"`) for a non-finite weight; [`MetricsError::InvalidParameter`] for a
    /// negative one.
    pub fn weighted(points: &'a [DVec3], weights: &'a [f64]) -> Result<Self, MetricsError> {
        check_weights(points, weights)?;
        Ok(Self {
            points,
            weights: Some(Cow::Borrowed(weights)),
        })
    }

    /// The vertices of a mesh weighted by their barycentric areas (a third of the area of
    /// each incident triangle, `1/k` of a `k`-gon): the weighted sums approximate surface
    /// integrals, exactly for integrands linear over each face. Isolated vertices get
    /// weight 0 and do not take part.
    ///
    /// # Errors
    /// [`MetricsError::Topology`] when `positions` does not match the mesh;
    /// [`MetricsError::NonFinite`] for a non-finite position; [`MetricsError::Empty`] for a
    /// mesh without vertices.
    pub fn area_weighted(
        mesh: &HalfedgeMesh,
        positions: &'a [DVec3],
    ) -> Result<Self, MetricsError> {
        let areas = crate::distance::vertex_areas(mesh, positions)?;
        Ok(Self {
            points: positions,
            weights: Some(Cow::Owned(areas)),
        })
    }

    /// The points.
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        self.points
    }

    /// The weights, `None` when unweighted.
    #[must_use]
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }

    /// The weight of point `i`.
    fn weight(&self, i: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[i])
    }

    /// Checks the points, counts those of positive weight (at least `needed`) and
    /// normalises them.
    fn normalise(&self, shape: &'static str, needed: usize) -> Result<Normalised, MetricsError> {
        for (index, p) in self.points.iter().enumerate() {
            if !p.is_finite() {
                return Err(MetricsError::NonFinite {
                    what: "point",
                    index,
                });
            }
        }
        let used: Vec<usize> = (0..self.points.len())
            .filter(|&i| self.weight(i) > 0.0)
            .collect();
        if used.len() < needed {
            return Err(MetricsError::TooFewPoints {
                shape,
                needed,
                got: used.len(),
            });
        }
        // Weighted centroid and RMS radius, compensated and in a fixed order.
        let mut total = Sum::default();
        let mut moment = [Sum::default(), Sum::default(), Sum::default()];
        for &i in &used {
            let (w, p) = (self.weight(i), self.points[i]);
            total.add(w);
            for k in 0..3 {
                moment[k].add(w * p[k]);
            }
        }
        let total = total.value();
        if !(total > 0.0 && total.is_finite()) {
            return Err(MetricsError::InvalidParameter {
                name: "weights",
                reason: "their sum must be positive and finite",
            });
        }
        let origin = DVec3::new(moment[0].value(), moment[1].value(), moment[2].value()) / total;
        let mut spread = Sum::default();
        for &i in &used {
            spread.add(self.weight(i) * (self.points[i] - origin).length_squared());
        }
        let scale = (spread.value() / total).sqrt();
        if scale.is_infinite() || !origin.is_finite() {
            // The squared distances overflow: name the largest coordinate.
            let (index, value) = used
                .iter()
                .flat_map(|&i| {
                    [
                        (i, self.points[i].x),
                        (i, self.points[i].y),
                        (i, self.points[i].z),
                    ]
                })
                .fold((0, 0.0f64), |best, (i, c)| {
                    if c.abs() > best.1.abs() { (i, c) } else { best }
                });
            return Err(MetricsError::CoordinateTooLarge {
                what: "point",
                index,
                value,
                limit: MAX_FIT_COORDINATE,
            });
        }
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(MetricsError::Degenerate {
                shape,
                reason: "all points coincide",
            });
        }
        Ok(Normalised {
            points: used
                .iter()
                .map(|&i| (self.points[i] - origin) / scale)
                .collect(),
            weights: used.iter().map(|&i| self.weight(i) / total).collect(),
            origin,
            scale,
        })
    }
}

/// The magnitude of coordinates beyond which the squared distances of a fit may
/// overflow (the square root of the largest `f64`, divided by the point count's
/// headroom).
const MAX_FIT_COORDINATE: f64 = 1e150;

/// Iteration controls of the geometric refinement.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FitOptions {
    /// The most Levenberg–Marquardt iterations (default 100; a few usually suffice).
    pub max_iterations: usize,
    /// Convergence threshold on the parameter step, in units of the data's RMS distance
    /// from their centroid (default `1e-12`).
    pub tolerance: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            tolerance: 1e-12,
        }
    }
}

impl FitOptions {
    /// Sets [`max_iterations`](Self::max_iterations): the most Levenberg–Marquardt iterations.
    #[must_use]
    pub fn max_iterations(mut self, max_iterations: usize) -> Self {
        self.max_iterations = max_iterations;
        self
    }

    /// Sets [`tolerance`](Self::tolerance): the convergence threshold on the parameter step.
    #[must_use]
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    fn check(&self) -> Result<(), MetricsError> {
        if self.max_iterations == 0 {
            return Err(MetricsError::InvalidParameter {
                name: "max_iterations",
                reason: "must be at least 1",
            });
        }
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return Err(MetricsError::InvalidParameter {
                name: "tolerance",
                reason: "must be positive and finite",
            });
        }
        Ok(())
    }
}

/// Weighted RMS and maximum absolute value of `residuals` (one per input point) over the
/// points of positive weight.
fn residual_summary(input: &FitPoints<'_>, residual: impl Fn(DVec3) -> f64) -> (f64, f64) {
    let mut squares = Sum::default();
    let mut total = Sum::default();
    let mut max = 0.0f64;
    for (i, &p) in input.points.iter().enumerate() {
        let w = input.weight(i);
        if w > 0.0 {
            let d = residual(p);
            squares.add(w * d * d);
            total.add(w);
            max = max.max(d.abs());
        }
    }
    ((squares.value() / total.value()).sqrt(), max)
}

fn check_weights(points: &[DVec3], weights: &[f64]) -> Result<(), MetricsError> {
    if weights.len() != points.len() {
        return Err(MetricsError::FieldLength {
            what: "weights",
            got: weights.len(),
            expected: points.len(),
        });
    }
    for (index, &w) in weights.iter().enumerate() {
        if !w.is_finite() {
            return Err(MetricsError::NonFinite {
                what: "weight",
                index,
            });
        }
        if w < 0.0 {
            return Err(MetricsError::InvalidParameter {
                name: "weights",
                reason: "must not be negative",
            });
        }
    }
    Ok(())
}

/// The weighted covariance `Σ w q qᵀ` of normalised points (centred at the origin).
fn covariance(data: &Normalised) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for (&q, &w) in data.points.iter().zip(&data.weights) {
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] += w * q[i] * q[j];
            }
        }
    }
    c
}

/// Kåsa's algebraic circle through 2-D points `(x, y)` with weights: the least-squares
/// solution of `2 a x + 2 b y + c = x² + y²`, giving the centre `(a, b)` and the radius
/// `sqrt(c + a² + b²)`; `None` when the system is singular (collinear points).
fn kasa_circle(points: impl Iterator<Item = (f64, f64, f64)>) -> Option<(f64, f64, f64)> {
    let mut m = [[0.0; 3]; 3];
    let mut rhs = [0.0; 3];
    for (x, y, w) in points {
        let u = [2.0 * x, 2.0 * y, 1.0];
        let z = x * x + y * y;
        for i in 0..3 {
            rhs[i] += w * u[i] * z;
            for j in 0..3 {
                m[i][j] += w * u[i] * u[j];
            }
        }
    }
    let [a, b, c] = linalg::cholesky_solve(m, rhs)?;
    let r2 = c + a * a + b * b;
    (r2 > 0.0).then(|| (a, b, r2.sqrt()))
}
