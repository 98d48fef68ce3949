//! The least-squares bivariate polynomial over the best-fit plane.

use beltrami_halfedge::DVec3;

use super::linalg::cholesky_solve_dyn;
use super::plane::fit_plane;
use super::{FitPoints, residual_summary};
use crate::MetricsError;
use crate::sum::Sum;

/// The highest degree [`fit_polynomial`] accepts.
pub const MAX_POLYNOMIAL_DEGREE: u32 = 6;

/// A fitted polynomial surface `w = P(u, v)` over the best-fit plane of the points.
///
/// `(u, v, w)` are coordinates in the frame of the plane: `u`, `v` along
/// [`u_axis`](Self::u_axis) and [`v_axis`](Self::v_axis) from [`origin`](Self::origin),
/// `w` along [`normal`](Self::normal).
#[derive(Clone, Debug, PartialEq)]
pub struct PolynomialFit {
    /// The total degree `N` of `P`.
    pub degree: u32,
    /// The weighted centroid of the points, the origin of the frame.
    pub origin: DVec3,
    /// The first in-plane axis: the projection of x onto the plane (see
    /// [`PlaneFit::in_plane_axes`](super::PlaneFit::in_plane_axes)).
    pub u_axis: DVec3,
    /// The second in-plane axis, `normal × u_axis`.
    pub v_axis: DVec3,
    /// The unit normal of the best-fit plane, with its largest-magnitude component
    /// positive.
    pub normal: DVec3,
    /// Weighted RMS of the orthogonal residuals (see [`PolynomialFit::residual`]).
    pub rms_residual: f64,
    /// Largest absolute orthogonal residual.
    pub max_residual: f64,
    /// Centre and half-width of the points' `u` and `v` ranges: `P` is a combination of
    /// Legendre products in `s = (u − c_u) / h_u`, `t = (v − c_v) / h_v`.
    centre: [f64; 2],
    half_width: [f64; 2],
    /// Coefficients of `L_i(s) L_j(t)`, in the order of [`exponents`].
    coefficients: Vec<f64>,
}

/// The exponent pairs `(i, j)` with `i + j ≤ degree`, by total degree, then by falling `i`.
fn exponents(degree: u32) -> impl Iterator<Item = (usize, usize)> {
    (0..=degree as usize).flat_map(|d| (0..=d).rev().map(move |i| (i, d - i)))
}

/// Legendre polynomials `L_0 … L_n` at `x` and their derivatives, by Bonnet's recursion
/// `(k + 1) L_{k+1} = (2k + 1) x L_k − k L_{k−1}` and `L'_{k+1} = L'_{k−1} + (2k + 1) L_k`.
fn legendre(n: usize, x: f64) -> ([f64; 7], [f64; 7]) {
    let mut value = [0.0; 7];
    let mut slope = [0.0; 7];
    value[0] = 1.0;
    if n >= 1 {
        value[1] = x;
        slope[1] = 1.0;
    }
    for k in 1..n {
        let kf = k as f64;
        value[k + 1] = ((2.0 * kf + 1.0) * x * value[k] - kf * value[k - 1]) / (kf + 1.0);
        slope[k + 1] = slope[k - 1] + (2.0 * kf + 1.0) * value[k];
    }
    (value, slope)
}

impl PolynomialFit {
    /// The frame coordinates `(u, v, w)` of `p`.
    #[must_use]
    pub fn to_frame(&self, p: DVec3) -> [f64; 3] {
        let d = p - self.origin;
        [d.dot(self.u_axis), d.dot(self.v_axis), d.dot(self.normal)]
    }

    /// `P(u, v)` and its partial derivatives `(∂P/∂u, ∂P/∂v)`.
    #[must_use]
    pub fn height(&self, u: f64, v: f64) -> (f64, [f64; 2]) {
        let n = self.degree as usize;
        let s = (u - self.centre[0]) / self.half_width[0];
        let t = (v - self.centre[1]) / self.half_width[1];
        let (ls, dls) = legendre(n, s);
        let (lt, dlt) = legendre(n, t);
        let (mut p, mut ps, mut pt) = (0.0, 0.0, 0.0);
        for ((i, j), &c) in exponents(self.degree).zip(&self.coefficients) {
            p += c * ls[i] * lt[j];
            ps += c * dls[i] * lt[j];
            pt += c * ls[i] * dlt[j];
        }
        (p, [ps / self.half_width[0], pt / self.half_width[1]])
    }

    /// The point of the polynomial surface closest to `p` (its orthogonal projection), by
    /// Gauss–Newton iterations on `(u, v)` from the point's own `(u, v)`: each step solves
    /// `JᵀJ δ = −Jᵀ(q − p)` with `q = (u, v, P(u, v))` and `J = ∂q/∂(u, v)`. The iteration
    /// converges (linearly, at a rate of the surface's curvature times the distance) for
    /// points closer to the surface than its radii of curvature, the case of a texture on
    /// a form; after 100 iterations the last iterate is returned.
    #[must_use]
    pub fn foot_point(&self, p: DVec3) -> DVec3 {
        let [u0, v0, w0] = self.to_frame(p);
        let (mut u, mut v) = (u0, v0);
        let tolerance = 1e-15 * self.half_width[0].max(self.half_width[1]);
        for _ in 0..100 {
            let (w, [pu, pv]) = self.height(u, v);
            let e = [u - u0, v - v0, w - w0];
            let g = [e[0] + pu * e[2], e[1] + pv * e[2]];
            let (a, b, c) = (1.0 + pu * pu, pu * pv, 1.0 + pv * pv);
            let det = a * c - b * b; // ≥ 1: JᵀJ is always invertible
            let du = -(c * g[0] - b * g[1]) / det;
            let dv = -(a * g[1] - b * g[0]) / det;
            u += du;
            v += dv;
            if du.abs().max(dv.abs()) <= tolerance {
                break;
            }
        }
        let (w, _) = self.height(u, v);
        self.origin + self.u_axis * u + self.v_axis * v + self.normal * w
    }

    /// The signed orthogonal distance from `p` to the polynomial surface: `|p − q|` with
    /// `q` the [`foot_point`](Self::foot_point), positive when `p` lies on the side
    /// [`normal`](Self::normal) points to (above the surface in the frame).
    #[must_use]
    pub fn residual(&self, p: DVec3) -> f64 {
        let q = self.foot_point(p);
        let [u, v, _] = self.to_frame(q);
        let (_, [pu, pv]) = self.height(u, v);
        let up = (self.normal - self.u_axis * pu - self.v_axis * pv).normalize();
        (p - q).dot(up)
    }
}

/// The least-squares polynomial surface of total degree `degree` (1 to
/// [`MAX_POLYNOMIAL_DEGREE`]) over the best-fit plane of `points`: the F-operator that
/// removes a free-form of low order.
///
/// First the plane ([`fit_plane`](super::fit_plane)) gives a frame `(u, v, w)`; then the
/// coefficients of `w = P(u, v) = Σ_{i+j≤N} c_ij L_i(s) L_j(t)` minimise
/// `Σ w_k (w_k − P(u_k, v_k))²`, the weighted squared deviations along the plane's
/// normal (linear least squares, solved by Cholesky on the normal equations). `L_i` are
/// Legendre polynomials in the coordinates scaled to `[−1, 1]` over the points' range,
/// which keeps the normal equations well conditioned up to degree 6. Degree 1 is the
/// best-fit plane itself. The [`residual`](PolynomialFit::residual) is then the signed
/// orthogonal distance to the fitted surface; for a form of small slope in its plane the
/// deviation along the normal and the orthogonal distance differ by the second order in
/// the slope.
///
/// Lengths are in the points' unit.
///
/// # Errors
/// - [`MetricsError::InvalidParameter`] for a degree outside 1 to 6;
/// - [`MetricsError::TooFewPoints`] for fewer points of positive weight than
///   coefficients, `(N + 1)(N + 2) / 2`;
/// - [`MetricsError::Degenerate`] when the points are collinear, or their projections on
///   the plane do not determine a polynomial of this degree (they lie on a few lines);
/// - [`MetricsError::NonFinite`] for a non-finite point.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::fits::{FitPoints, fit_polynomial};
///
/// // A paraboloid cap z = 0.01 (x² + y²) over a 10 × 10 grid centred on its axis (so
/// // that its best-fit plane is z = constant).
/// let grid = primitives::grid(10, 10);
/// let cap: Vec<DVec3> = grid.positions.iter()
///     .map(|p| {
///         let (x, y) = (p.x - 5.0, p.y - 5.0);
///         DVec3::new(x, y, 0.01 * (x * x + y * y))
///     })
///     .collect();
/// let fit = fit_polynomial(&FitPoints::new(&cap), 2)?;
/// assert!(fit.max_residual < 1e-12);
/// // 0.1 above the vertex of the paraboloid: 0.1 away, on the normal's side.
/// assert!((fit.residual(DVec3::new(0.0, 0.0, 0.1)) - 0.1).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// - ISO 25178-2:2012, clause 3.1 (general terms: the F-operation, which removes the
///   nominal form, and the scale-limited surface) and ISO 16610-1:2015 (its place in the
///   filtration chain).
/// - R. Leach (ed.): *Characterisation of Areal Surface Texture*. Springer, 2013, the
///   chapter *Areal filtering methods* (J. Seewig: form removal by least-squares
///   polynomials before the S- and L-filters).
pub fn fit_polynomial(input: &FitPoints<'_>, degree: u32) -> Result<PolynomialFit, MetricsError> {
    if !(1..=MAX_POLYNOMIAL_DEGREE).contains(&degree) {
        return Err(MetricsError::InvalidParameter {
            name: "polynomial degree",
            reason: "must be 1 to 6",
        });
    }
    let n_terms = exponents(degree).count();
    let used = weighted_points(input, n_terms)?;
    let plane = reference_plane(input)?;
    let (u_axis, v_axis) = plane.in_plane_axes();
    let frame = PlaneFrame {
        origin: plane.point,
        u_axis,
        v_axis,
        normal: plane.normal,
    };
    let (centre, half_width) = frame.extent(input, &used);
    let undetermined = MetricsError::Degenerate {
        shape: SHAPE,
        reason: "the points' projections do not determine a polynomial of this degree",
    };
    if !(half_width[0] > 0.0 && half_width[1] > 0.0) {
        return Err(undetermined);
    }
    let (gram, rhs) = frame.normal_equations(input, &used, degree, centre, half_width);
    let coefficients = cholesky_solve_dyn(&gram, &rhs).ok_or(undetermined)?;
    let fit = PolynomialFit {
        degree,
        origin: plane.point,
        u_axis,
        v_axis,
        normal: plane.normal,
        rms_residual: 0.0,
        max_residual: 0.0,
        centre,
        half_width,
        coefficients,
    };
    let (rms, max) = residual_summary(input, |p| fit.residual(p));
    Ok(PolynomialFit {
        rms_residual: rms,
        max_residual: max,
        ..fit
    })
}

/// The shape named in the errors of [`fit_polynomial`].
const SHAPE: &str = "polynomial";

/// The indices of the points of positive weight.
///
/// # Errors
/// [`MetricsError::TooFewPoints`] when there are fewer than `n_terms`.
fn weighted_points(input: &FitPoints<'_>, n_terms: usize) -> Result<Vec<usize>, MetricsError> {
    let weight = |i: usize| input.weights().map_or(1.0, |w| w[i]);
    let used: Vec<usize> = (0..input.points().len())
        .filter(|&i| weight(i) > 0.0)
        .collect();
    if used.len() < n_terms {
        return Err(MetricsError::TooFewPoints {
            shape: SHAPE,
            needed: n_terms,
            got: used.len(),
        });
    }
    Ok(used)
}

/// The best-fit plane, the reference of the polynomial; its errors name the
/// polynomial.
fn reference_plane(input: &FitPoints<'_>) -> Result<super::PlaneFit, MetricsError> {
    fit_plane(input).map_err(|e| match e {
        MetricsError::TooFewPoints { needed, got, .. } => MetricsError::TooFewPoints {
            shape: SHAPE,
            needed,
            got,
        },
        MetricsError::Degenerate { reason, .. } => MetricsError::Degenerate {
            shape: SHAPE,
            reason,
        },
        e => e,
    })
}

/// The frame of the reference plane: a point on it, two in-plane axes and the normal.
struct PlaneFrame {
    origin: DVec3,
    u_axis: DVec3,
    v_axis: DVec3,
    normal: DVec3,
}

impl PlaneFrame {
    /// `p` in the frame: `[u, v, height above the plane]`.
    #[inline]
    fn local(&self, p: DVec3) -> [f64; 3] {
        let d = p - self.origin;
        [d.dot(self.u_axis), d.dot(self.v_axis), d.dot(self.normal)]
    }

    /// The centre and half widths of the `used` points' in-plane bounding box.
    fn extent(&self, input: &FitPoints<'_>, used: &[usize]) -> ([f64; 2], [f64; 2]) {
        let (mut low, mut high) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &i in used {
            let [u, v, _] = self.local(input.points()[i]);
            for (k, x) in [u, v].into_iter().enumerate() {
                low[k] = low[k].min(x);
                high[k] = high[k].max(x);
            }
        }
        let centre = [0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1])];
        let half_width = [0.5 * (high[0] - low[0]), 0.5 * (high[1] - low[1])];
        (centre, half_width)
    }

    /// The normal equations Σ w φ φᵀ c = Σ w φ w_k of the Legendre products φ of
    /// `degree` over the box (`centre`, `half_width`), summed over the `used` points in
    /// order with normalised weights: the lower triangle of the Gram matrix (row-major)
    /// and the right-hand side.
    fn normal_equations(
        &self,
        input: &FitPoints<'_>,
        used: &[usize],
        degree: u32,
        centre: [f64; 2],
        half_width: [f64; 2],
    ) -> (Vec<f64>, Vec<f64>) {
        let weight = |i: usize| input.weights().map_or(1.0, |w| w[i]);
        let n_terms = exponents(degree).count();
        let total = {
            let mut s = Sum::default();
            used.iter().for_each(|&i| s.add(weight(i)));
            s.value()
        };
        let mut gram = vec![0.0; n_terms * n_terms];
        let mut rhs = vec![0.0; n_terms];
        let mut phi = vec![0.0; n_terms];
        let n = degree as usize;
        for &i in used {
            let [u, v, w] = self.local(input.points()[i]);
            let (ls, _) = legendre(n, (u - centre[0]) / half_width[0]);
            let (lt, _) = legendre(n, (v - centre[1]) / half_width[1]);
            for (slot, (a, b)) in phi.iter_mut().zip(exponents(degree)) {
                *slot = ls[a] * lt[b];
            }
            let wk = weight(i) / total;
            for r in 0..n_terms {
                let x = wk * phi[r];
                rhs[r] += x * w;
                for c in 0..=r {
                    gram[r * n_terms + c] += x * phi[c];
                }
            }
        }
        (gram, rhs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legendre_values_and_slopes() {
        let x = 0.3;
        let (l, d) = legendre(6, x);
        assert!((l[2] - 0.5 * (3.0 * x * x - 1.0)).abs() < 1e-15);
        assert!((l[3] - 0.5 * (5.0 * x * x * x - 3.0 * x)).abs() < 1e-15);
        assert!((d[3] - 0.5 * (15.0 * x * x - 3.0)).abs() < 1e-15);
        // Central differences of L_6.
        let h = 1e-6;
        let slope = (legendre(6, x + h).0[6] - legendre(6, x - h).0[6]) / (2.0 * h);
        assert!((d[6] - slope).abs() < 1e-8);
        assert_eq!(
            exponents(2).collect::<Vec<_>>(),
            [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
        );
    }
}
