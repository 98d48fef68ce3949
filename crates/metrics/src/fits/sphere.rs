//! The least-squares sphere.

use beltrami_halfedge::DVec3;

use super::linalg::{cholesky_solve, symmetric_eigen3};
use super::lm::{Model, levenberg_marquardt};
use super::{FitOptions, FitPoints, covariance, residual_summary};
use crate::MetricsError;

/// A fitted sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereFit {
    /// The centre.
    pub center: DVec3,
    /// The radius.
    pub radius: f64,
    /// Weighted RMS of the residuals `|p − center| − radius`.
    pub rms_residual: f64,
    /// Largest absolute residual.
    pub max_residual: f64,
    /// Levenberg–Marquardt iterations done.
    pub iterations: usize,
    /// Whether the refinement met its tolerance (see the [module docs](super)).
    pub converged: bool,
}

impl SphereFit {
    /// The signed orthogonal distance from `p` to the sphere, `|p − center| − radius`
    /// (positive outside).
    #[must_use]
    pub fn residual(&self, p: DVec3) -> f64 {
        (p - self.center).length() - self.radius
    }
}

/// The sphere in normalised coordinates.
#[derive(Clone, Copy, Debug)]
struct Sphere {
    center: DVec3,
    radius: f64,
}

impl Model<4> for Sphere {
    fn residual(&self, q: DVec3) -> (f64, [f64; 4]) {
        let d = q - self.center;
        let rho = d.length();
        let u = if rho > 0.0 { d / rho } else { DVec3::ZERO };
        (rho - self.radius, [-u.x, -u.y, -u.z, -1.0])
    }

    fn moved(&self, step: &[f64; 4]) -> Option<Self> {
        let center = self.center + DVec3::new(step[0], step[1], step[2]);
        let radius = self.radius + step[3];
        (center.length() < LIMIT && radius.abs() < LIMIT).then_some(Self { center, radius })
    }
}

/// Beyond this many RMS radii of the data, a centre or radius means the points are closer
/// to a plane than to any sphere.
const LIMIT: f64 = 1e8;

/// The least-squares sphere through `points`: the centre `c` and radius `r` minimising
/// `Σ w_i (|p_i − c| − r)²`.
///
/// Kåsa's algebraic fit (`2 c · p + d = |p|²` in the least-squares sense, `r² = d + |c|²`)
/// gives the start; Levenberg–Marquardt on the orthogonal distances (Jacobian row
/// `[−(p_i − c)ᵀ / |p_i − c|, −1]`) refines it. At the optimum the radius is the weighted
/// mean distance from the centre. The algebraic start is biased on partial caps with
/// noise; the geometric refinement removes that bias.
///
/// # Errors
/// - [`MetricsError::TooFewPoints`] for fewer than 4 points of positive weight;
/// - [`MetricsError::Degenerate`] when the points are coplanar (or coincide);
/// - [`MetricsError::NoConvergence`] when the refinement runs off towards a plane;
/// - [`MetricsError::NonFinite`] for a non-finite point, [`MetricsError::InvalidParameter`]
///   for invalid options.
///
/// # References
/// Kåsa 1976; Pratt 1987; Shakarji 1998 (§ spheres).
pub fn fit_sphere(input: &FitPoints<'_>, options: &FitOptions) -> Result<SphereFit, MetricsError> {
    const SHAPE: &str = "sphere";
    options.check()?;
    let data = input.normalise(SHAPE, 4)?;
    let (values, _) = symmetric_eigen3(covariance(&data));
    if values[0] <= 1e-20 * values[2] {
        return Err(MetricsError::Degenerate {
            shape: SHAPE,
            reason: "the points are coplanar",
        });
    }
    // Kåsa: unknowns (c, d) with rows [2q, 1] · (c, d) = |q|².
    let mut m = [[0.0; 4]; 4];
    let mut rhs = [0.0; 4];
    for (&q, &w) in data.points.iter().zip(&data.weights) {
        let u = [2.0 * q.x, 2.0 * q.y, 2.0 * q.z, 1.0];
        let z = q.length_squared();
        for i in 0..4 {
            rhs[i] += w * u[i] * z;
            for j in 0..4 {
                m[i][j] += w * u[i] * u[j];
            }
        }
    }
    let start = cholesky_solve(m, rhs)
        .map(|[x, y, z, d]| {
            let center = DVec3::new(x, y, z);
            Sphere {
                center,
                radius: (d + center.length_squared()).max(0.0).sqrt(),
            }
        })
        .filter(|s| s.radius > 0.0 && s.center.length() < LIMIT)
        .ok_or(MetricsError::Degenerate {
            shape: SHAPE,
            reason: "the points do not determine a sphere",
        })?;
    let outcome =
        levenberg_marquardt(&data, start, options).map_err(|d| MetricsError::NoConvergence {
            shape: SHAPE,
            iterations: d.iterations,
        })?;
    let center = data.origin + outcome.model.center * data.scale;
    let radius = outcome.model.radius.abs() * data.scale;
    let fit = SphereFit {
        center,
        radius,
        rms_residual: 0.0,
        max_residual: 0.0,
        iterations: outcome.iterations,
        converged: outcome.converged,
    };
    let (rms, max) = residual_summary(input, |p| fit.residual(p));
    Ok(SphereFit {
        rms_residual: rms,
        max_residual: max,
        ..fit
    })
}
