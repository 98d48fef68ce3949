//! Errors of `beltrami-smooth`.

use beltrami_weights::WeightError;

/// Why a smoothing run could not start or had to stop.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SmoothError {
    /// λ outside its valid range.
    #[error("lambda must be {range}, got {}", beltrami_halfedge::exact_number(*.lambda))]
    InvalidLambda {
        /// The value given.
        lambda: f64,
        /// The valid range in words.
        range: &'static str,
    },
    /// An explicit area-normalised step too large for the mesh: `λ · max_i W_i / A_i`
    /// exceeds 1 (weight sum over vertex area), so the highest frequencies would grow
    /// (see [`Smoother::stable_step_limit`](crate::Smoother::stable_step_limit); the
    /// smoother itself runs any step it is given).
    #[error(
        "lambda {} is not a stable explicit step with area normalisation on this mesh: the largest stable step is {} (length²); take a smaller --lambda, give --time or --cutoff (which choose a stable step), or use --method implicit",
        Short(*lambda),
        Short(*max_stable)
    )]
    UnstableStep {
        /// The step given, a time per iteration in length².
        lambda: f64,
        /// The largest stable step, `1 / max_i (W_i / A_i)`, in length².
        max_stable: f64,
    },
    /// A boundary mode that does not combine with the normalisation.
    #[error("boundary mode 'curve' needs weight-sum normalisation")]
    CurveNeedsWeightSum,
    /// A pinned vertex that does not exist.
    #[error("pinned vertex {vertex} does not exist (the mesh has {n_vertices} vertices)")]
    PinnedOutOfRange {
        /// The vertex.
        vertex: u32,
        /// The number of vertices.
        n_vertices: usize,
    },
    /// An input position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite input position")]
    NonFiniteInput {
        /// The vertex.
        vertex: u32,
    },
    /// A position became NaN or infinite (the step is too large for the operator).
    #[error(
        "vertex {vertex} became non-finite in iteration {iteration}; the step is too large for this operator"
    )]
    NonFinite {
        /// The vertex.
        vertex: u32,
        /// The iteration (1-based).
        iteration: usize,
    },
    /// Taubin's μ violates the pass-band or stability condition (see
    /// [`Method::Taubin`](crate::Method::Taubin)).
    #[error("Taubin's mu = {} with lambda = {} is invalid: {reason}", Short(*mu), Short(*lambda))]
    InvalidTaubin {
        /// λ.
        lambda: f64,
        /// μ.
        mu: f64,
        /// The violated condition in words.
        reason: &'static str,
    },
    /// An HC parameter outside [0, 1].
    #[error("HC parameters must lie in [0, 1], got alpha = {alpha}, beta = {beta}")]
    InvalidHc {
        /// α.
        alpha: f64,
        /// β.
        beta: f64,
    },
    /// Volume preservation asked of a mesh with a boundary.
    #[error(
        "volume preservation needs a closed mesh, this one has {boundary_loops} boundary {}; use the HC or Taubin method on open patches",
        if *boundary_loops == 1 { "loop" } else { "loops" }
    )]
    VolumeNeedsClosedMesh {
        /// The number of boundary loops.
        boundary_loops: usize,
    },
    /// Volume preservation together with pinned vertices (the rescale would move them).
    #[error("volume preservation cannot be combined with pinned vertices")]
    VolumeWithPinned,
    /// The enclosed volume is zero, negative or not finite, so it cannot be preserved.
    #[error(
        "the enclosed volume is {volume} in iteration {iteration}; volume preservation needs a positive, finite volume: outward-oriented faces, and coordinates within about 1e-100 to 1e100 (a volume is a cube of lengths)"
    )]
    DegenerateVolume {
        /// The signed volume.
        volume: f64,
        /// The iteration (0 for the input).
        iteration: usize,
    },
    /// A diffusion time or cut-off that is negative or not finite, or one given for a
    /// method other than plain diffusion.
    #[error("invalid diffusion time: {reason}")]
    InvalidDuration {
        /// The problem in words.
        reason: String,
    },
    /// A convergence threshold that is negative or not finite.
    #[error("the convergence threshold must be positive and finite, got {}", beltrami_halfedge::exact_number(*.value))]
    InvalidUntilChange {
        /// The value given.
        value: f64,
    },
    /// The conjugate-gradient settings are not usable.
    #[error(
        "conjugate gradient needs a positive finite tolerance below 1 and at least one iteration, got tolerance {tolerance} and {max_iterations} iterations"
    )]
    InvalidSolverSettings {
        /// The relative residual tolerance given.
        tolerance: f64,
        /// The iteration limit given.
        max_iterations: usize,
    },
    /// Volume preservation asked of an implicit run.
    #[error("volume preservation is not available for implicit smoothing")]
    VolumeNotImplicit,
    /// The mesh is too far from unit size for the implicit step, which computes
    /// squared lengths (vertex areas, the solver's norms): beyond coordinates of about
    /// 2^±500 those leave the range of numbers, and the step would be wrong or refused
    /// as not positive definite. The largest coordinate must lie in
    /// [`IMPLICIT_COORDINATES`](crate::IMPLICIT_COORDINATES) (2⁻⁴⁸⁰ to 2⁴⁸⁰, about
    /// 10^±144); the explicit methods have no such limit.
    #[error(
        "implicit smoothing needs the largest coordinate between 2^-480 and 2^480 (about 3.2e-145 and 3.1e144) in absolute value, as its areas are squared lengths; this mesh's is {}: express it in another unit",
        Short(*.largest)
    )]
    ImplicitScale {
        /// The largest absolute coordinate of the mesh.
        largest: f64,
    },
    /// The implicit smoother has no curve boundary mode.
    #[error(
        "boundary mode 'curve' is not available for implicit smoothing (use 'fixed' or 'free')"
    )]
    CurveNotImplicit,
    /// The implicit system `M − t L` is not (numerically) positive definite, so the
    /// backward-Euler step is not a smoothing step. Weights that are negative without
    /// being an energy (a scheme of your own with negative weights kept) cause this —
    /// cotangent weights give a positive definite system even where they are negative —
    /// and so does a mesh so degenerate (collapsed triangles, near-zero areas against
    /// huge weights) that the system is singular to rounding.
    #[error(
        "the implicit system of iteration {iteration} is not positive definite (negative weights, or a degenerate mesh with this time step); clamp negative weights (NegativeWeights::Clamp, --cotangent-negative clamp) or take a smaller step"
    )]
    NotPositiveDefinite {
        /// The iteration (1-based).
        iteration: usize,
    },
    /// Conjugate gradient did not reach its tolerance within its iteration limit.
    #[error(
        "conjugate gradient did not converge in iteration {iteration}: relative residual {residual:e} after {iterations} iterations (tolerance {tolerance:e})"
    )]
    NotConverged {
        /// The smoothing iteration (1-based).
        iteration: usize,
        /// The conjugate-gradient iterations done (the limit).
        iterations: usize,
        /// The relative residual reached, `‖b − A x‖ / ‖b‖`, worst coordinate.
        residual: f64,
        /// The tolerance asked for.
        tolerance: f64,
    },
    /// The sparse factorisation could not be computed (out of memory, index overflow).
    #[error("the sparse factorisation failed: {reason}")]
    Factorization {
        /// What the solver reported.
        reason: String,
    },
    /// The weights could not be computed.
    #[error(transparent)]
    Weights(#[from] WeightError),
}

/// A number in a message: six significant digits without trailing zeros, scientific
/// notation below 1e-4 and from 1e6 on (`0.0190315`, `-0.869565`, `1e300`).
pub(crate) struct Short(pub(crate) f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() {
            return write!(f, "{x}");
        }
        let trim = |t: &str| -> String {
            if t.contains('.') {
                t.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                t.to_string()
            }
        };
        let magnitude = x.abs();
        if (1e-4..1e6).contains(&magnitude) {
            #[allow(clippy::cast_possible_truncation, reason = "a small exponent")]
            let exponent = magnitude.log10().floor() as i32;
            let decimals = usize::try_from((5 - exponent).max(0)).unwrap_or(0);
            f.write_str(&trim(&format!("{x:.decimals$}")))
        } else {
            let text = format!("{x:.5e}");
            match text.split_once('e') {
                Some((mantissa, exponent)) => write!(f, "{}e{exponent}", trim(mantissa)),
                None => f.write_str(&text),
            }
        }
    }
}
