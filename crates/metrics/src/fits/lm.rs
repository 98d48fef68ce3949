//! Levenberg–Marquardt for orthogonal-distance fits on normalised data.

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use glam::DVec3;

use super::FitOptions;
use super::linalg::cholesky_solve;
use crate::sum::Sum;

/// Points centred on their weighted centroid and divided by their weighted RMS distance
/// from it, with weights that sum to 1: the fits iterate in these coordinates, where every
/// parameter is of order one.
#[derive(Clone, Debug)]
pub(crate) struct Normalised {
    /// The normalised points, `(p − origin) / scale`.
    pub(crate) points: Vec<DVec3>,
    /// Weights summing to 1 (positive weights only; zero-weight points are dropped).
    pub(crate) weights: Vec<f64>,
    /// The weighted centroid of the input.
    pub(crate) origin: DVec3,
    /// The weighted RMS distance of the input from `origin`.
    pub(crate) scale: f64,
}

/// A model whose parameters are moved by steps of `N` local coordinates.
pub(crate) trait Model<const N: usize>: Copy {
    /// The signed residual of normalised point `q` and its derivatives with respect to the
    /// step coordinates.
    fn residual(&self, q: DVec3) -> (f64, [f64; N]);
    /// The model after `step`, or `None` when it leaves the sane range (a radius running
    /// off towards infinity: the data are closer to a plane or a line).
    fn moved(&self, step: &[f64; N]) -> Option<Self>;
}

/// The result of [`levenberg_marquardt`].
pub(crate) struct Outcome<M> {
    pub(crate) model: M,
    pub(crate) iterations: usize,
    pub(crate) converged: bool,
}

/// Why [`levenberg_marquardt`] gave up.
pub(crate) struct Diverged {
    pub(crate) iterations: usize,
}

/// The weighted sum of squared residuals.
pub(crate) fn cost<const N: usize>(model: &impl Model<N>, data: &Normalised) -> f64 {
    let mut sum = Sum::default();
    for (&q, &w) in data.points.iter().zip(&data.weights) {
        let (r, _) = model.residual(q);
        sum.add(w * r * r);
    }
    sum.value()
}

/// Minimises `Σ w_i r_i²` from `start` by Levenberg–Marquardt with Marquardt's diagonal
/// scaling: each iteration solves `(JᵀWJ + λ diag(JᵀWJ)) δ = −JᵀWr` and accepts the step
/// when the cost does not increase (then `λ` shrinks tenfold), otherwise retries with `λ`
/// ten times larger.
///
/// Converged when an accepted step is below `options.tolerance` in every coordinate (in
/// normalised units, where the data's RMS distance from their centroid is 1), or when no step of any damping lowers the cost (a minimum to working
/// precision). Not converged when the iteration limit is reached first. Diverged when the
/// only steps that lower the cost leave the model's sane range.
///
/// # References
/// D. W. Marquardt: *An algorithm for least-squares estimation of nonlinear parameters*.
/// SIAM J. Appl. Math. 11(2), 1963; C. M. Shakarji: *Least-squares fitting algorithms of
/// the NIST algorithm testing system*. J. Res. NIST 103(6), 1998.
pub(crate) fn levenberg_marquardt<M: Model<N>, const N: usize>(
    data: &Normalised,
    start: M,
    options: &FitOptions,
) -> Result<Outcome<M>, Diverged> {
    let mut model = start;
    let mut current = cost(&model, data);
    let mut lambda = 1e-3;
    for iteration in 1..=options.max_iterations {
        // Normal equations, summed sequentially (reproducible).
        let mut jtj = [[0.0; N]; N];
        let mut jtr = [0.0; N];
        for (&q, &w) in data.points.iter().zip(&data.weights) {
            let (r, g) = model.residual(q);
            for i in 0..N {
                jtr[i] += w * g[i] * r;
                for j in 0..=i {
                    jtj[i][j] += w * g[i] * g[j];
                }
            }
        }
        for i in 0..N {
            for j in 0..i {
                jtj[j][i] = jtj[i][j];
            }
        }
        let rhs = jtr.map(|x| -x);
        let floor = (0..N).map(|i| jtj[i][i]).fold(0.0, f64::max) * 1e-15;
        let mut blocked = false;
        loop {
            if lambda > 1e16 {
                // No damping lowers the cost: a minimum to working precision, unless the
                // only improving steps left the sane range.
                return if blocked {
                    Err(Diverged {
                        iterations: iteration,
                    })
                } else {
                    Ok(Outcome {
                        model,
                        iterations: iteration,
                        converged: true,
                    })
                };
            }
            let mut a = jtj;
            for (i, row) in a.iter_mut().enumerate() {
                row[i] += lambda * (jtj[i][i] + floor);
            }
            let Some(step) = cholesky_solve(a, rhs) else {
                lambda *= 10.0;
                continue;
            };
            let Some(candidate) = model.moved(&step) else {
                blocked = true;
                lambda *= 10.0;
                continue;
            };
            let next = cost(&candidate, data);
            if next <= current {
                model = candidate;
                current = next;
                lambda = (lambda * 0.1).max(1e-12);
                let size = step.iter().fold(0.0f64, |m, s| m.max(s.abs()));
                if size <= options.tolerance {
                    return Ok(Outcome {
                        model,
                        iterations: iteration,
                        converged: true,
                    });
                }
                break;
            }
            lambda *= 10.0;
        }
    }
    Ok(Outcome {
        model,
        iterations: options.max_iterations,
        converged: false,
    })
}
