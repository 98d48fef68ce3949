//! What a study of one given surface runs: schemes, methods, iteration range.

use std::sync::Arc;

use beltrami_smooth::{Boundary, ImplicitSolver, Method, WeightUpdate};
use beltrami_weights::{WeightRegistry, WeightScheme};

use crate::error::StudyError;

/// One way of smoothing that [`run_scan`](crate::run_scan) tries with every scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ScanMethod {
    /// Plain explicit diffusion `x ← x + λ L x` with the configured λ (`smooth`'s
    /// default method).
    Plain,
    /// Taubin's λ|μ filter with λ = 0.6307, μ = −0.6732 (pass band k_PB = 0.1, as in
    /// the study's counter-measures), whatever the configured λ.
    Taubin,
    /// The HC push-back (α = 0.1, β = 0.6) after each plain step with the configured λ.
    Hc,
    /// One implicit (backward-Euler) step per configured time step
    /// ([`ScanConfig::implicit_steps`]), solved by sparse Cholesky factorisation.
    Implicit,
}

impl ScanMethod {
    /// Every method, in the order of the report.
    pub const ALL: [Self; 4] = [Self::Plain, Self::Taubin, Self::Hc, Self::Implicit];

    /// The label of tables, CSV and file names: `plain`, `taubin`, `hc`, `implicit`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Plain => "plain",
            Self::Taubin => "taubin",
            Self::Hc => "hc",
            Self::Implicit => "implicit",
        }
    }

    /// The method named by [`label`](Self::label).
    ///
    /// # Errors
    /// [`StudyError::Config`] for any other name, listing the valid ones.
    pub fn from_label(label: &str) -> Result<Self, StudyError> {
        Self::ALL
            .into_iter()
            .find(|m| m.label() == label)
            .ok_or_else(|| {
                StudyError::Config(format!(
                    "unknown method '{label}'; valid: plain, taubin, hc, implicit"
                ))
            })
    }

    /// The step of an explicit method: the configured λ, or Taubin's fixed λ.
    pub(crate) fn explicit_step(self, lambda: f64) -> f64 {
        match self {
            Self::Taubin => TAUBIN_LAMBDA,
            _ => lambda,
        }
    }

    /// The smoother's method.
    pub(crate) fn method(self) -> Method {
        match self {
            Self::Plain => Method::Laplacian,
            Self::Taubin => Method::Taubin { mu: TAUBIN_MU },
            Self::Hc => Method::hc(),
            Self::Implicit => Method::implicit(ImplicitSolver::Cholesky),
        }
    }
}

/// Taubin's λ (pass band k_PB = 0.1 with [`TAUBIN_MU`]).
pub const TAUBIN_LAMBDA: f64 = 0.6307;
/// Taubin's μ.
pub const TAUBIN_MU: f64 = -0.6732;

/// The implicit time steps tried by default (dimensionless with weight-sum
/// normalisation: a step of 1 smooths about as much as 1.25 explicit steps of λ = 0.8
/// at low frequencies).
pub const DEFAULT_IMPLICIT_STEPS: [f64; 8] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];

/// Every explicit iteration up to this one is observed; beyond it every
/// [`OBSERVE_STRIDE`]-th.
pub const OBSERVE_EVERY_UP_TO: usize = 20;
/// The spacing of the observed iterations beyond [`OBSERVE_EVERY_UP_TO`].
pub const OBSERVE_STRIDE: usize = 5;

/// The configuration of [`run_scan`](crate::run_scan): a study of one given surface
/// (a scan), optionally against a clean reference.
///
/// The defaults are `smooth`'s (λ = 0.8, fixed boundary, weights recomputed every
/// iteration, weight-sum normalisation) with every built-in scheme, every method, up to
/// 100 explicit iterations and the implicit steps of [`DEFAULT_IMPLICIT_STEPS`].
///
/// ```
/// use beltrami_study::{ScanConfig, ScanMethod};
/// let config = ScanConfig::default().max_iterations(30).methods(vec![ScanMethod::Plain]);
/// assert_eq!(config.observed_iterations().last(), Some(&30));
/// ```
#[derive(Clone)]
#[non_exhaustive]
pub struct ScanConfig {
    /// The weight schemes, in the report's order.
    pub schemes: Vec<Arc<dyn WeightScheme>>,
    /// The methods, in the report's order.
    pub methods: Vec<ScanMethod>,
    /// The explicit step λ of plain and HC smoothing, in (0, 1].
    pub lambda: f64,
    /// The last explicit iteration observed (at least 1).
    pub max_iterations: usize,
    /// The implicit time steps, each run as one backward-Euler step (positive, finite).
    pub implicit_steps: Vec<f64>,
    /// How boundary vertices move (fixed, as `smooth` does by default).
    pub boundary: Boundary,
    /// When weights are computed.
    pub update: WeightUpdate,
}

impl std::fmt::Debug for ScanConfig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScanConfig")
            .field(
                "schemes",
                &self.schemes.iter().map(|s| s.name()).collect::<Vec<_>>(),
            )
            .field("methods", &self.methods)
            .field("lambda", &self.lambda)
            .field("max_iterations", &self.max_iterations)
            .field("implicit_steps", &self.implicit_steps)
            .field("boundary", &self.boundary)
            .field("update", &self.update)
            .finish()
    }
}

impl Default for ScanConfig {
    fn default() -> Self {
        Self {
            schemes: WeightRegistry::with_builtins().iter().cloned().collect(),
            methods: ScanMethod::ALL.to_vec(),
            lambda: 0.8,
            max_iterations: 100,
            implicit_steps: DEFAULT_IMPLICIT_STEPS.to_vec(),
            boundary: Boundary::Fixed,
            update: WeightUpdate::Every,
        }
    }
}

impl ScanConfig {
    /// Sets [`schemes`](Self::schemes).
    #[must_use]
    pub fn schemes(mut self, schemes: Vec<Arc<dyn WeightScheme>>) -> Self {
        self.schemes = schemes;
        self
    }

    /// Sets [`methods`](Self::methods).
    #[must_use]
    pub fn methods(mut self, methods: Vec<ScanMethod>) -> Self {
        self.methods = methods;
        self
    }

    /// Sets [`lambda`](Self::lambda).
    #[must_use]
    pub fn lambda(mut self, lambda: f64) -> Self {
        self.lambda = lambda;
        self
    }

    /// Sets [`max_iterations`](Self::max_iterations).
    #[must_use]
    pub fn max_iterations(mut self, max_iterations: usize) -> Self {
        self.max_iterations = max_iterations;
        self
    }

    /// Sets [`implicit_steps`](Self::implicit_steps).
    #[must_use]
    pub fn implicit_steps(mut self, steps: Vec<f64>) -> Self {
        self.implicit_steps = steps;
        self
    }

    /// Sets [`boundary`](Self::boundary).
    #[must_use]
    pub fn boundary(mut self, boundary: Boundary) -> Self {
        self.boundary = boundary;
        self
    }

    /// Sets [`update`](Self::update).
    #[must_use]
    pub fn update(mut self, update: WeightUpdate) -> Self {
        self.update = update;
        self
    }

    /// The explicit iterations observed: every one from 1 to [`OBSERVE_EVERY_UP_TO`],
    /// then every [`OBSERVE_STRIDE`]-th, and the last.
    #[must_use]
    pub fn observed_iterations(&self) -> Vec<usize> {
        let mut out: Vec<usize> = (1..=self.max_iterations)
            .filter(|&i| i <= OBSERVE_EVERY_UP_TO || i % OBSERVE_STRIDE == 0)
            .collect();
        if out.last() != Some(&self.max_iterations) && self.max_iterations > 0 {
            out.push(self.max_iterations);
        }
        out
    }

    /// The explicit iterations at which the removed residual and the mesh quality are
    /// measured too: [`REPORT_ITERATIONS`](crate::REPORT_ITERATIONS) up to the limit,
    /// and the limit. (Each run's best count is measured in full as well.)
    #[must_use]
    pub fn detailed_iterations(&self) -> Vec<usize> {
        let mut out: Vec<usize> = crate::scan::REPORT_ITERATIONS
            .iter()
            .copied()
            .filter(|&i| i <= self.max_iterations)
            .collect();
        if out.last() != Some(&self.max_iterations) {
            out.push(self.max_iterations);
        }
        out
    }

    /// Checks the configuration.
    ///
    /// # Errors
    /// [`StudyError::Config`] naming the first invalid setting: no scheme or method, a
    /// repeated one, λ outside (0, 1], no iteration or more than
    /// [`MAX_STUDY_ITERATIONS`](crate::MAX_STUDY_ITERATIONS), an implicit step that is not
    /// positive and finite, or the implicit method without a step.
    pub fn validate(&self) -> Result<(), StudyError> {
        let bad = |m: String| Err(StudyError::Config(m));
        if self.schemes.is_empty() {
            return bad("no weight scheme to run".into());
        }
        if self.methods.is_empty() {
            return bad("no method to run".into());
        }
        for (i, s) in self.schemes.iter().enumerate() {
            if self.schemes[..i].iter().any(|t| t.name() == s.name()) {
                return bad(format!("weight scheme '{}' given twice", s.name()));
            }
        }
        for (i, m) in self.methods.iter().enumerate() {
            if self.methods[..i].contains(m) {
                return bad(format!("method '{}' given twice", m.label()));
            }
        }
        if !(self.lambda > 0.0 && self.lambda <= 1.0) {
            return bad(format!(
                "lambda must be in (0, 1], got {}",
                beltrami_halfedge::exact_number(self.lambda)
            ));
        }
        if self.max_iterations == 0 {
            return bad("the iteration limit must be at least 1".into());
        }
        if self.max_iterations > crate::MAX_STUDY_ITERATIONS {
            return bad(format!(
                "the iteration limit must be at most {}, got {}",
                crate::MAX_STUDY_ITERATIONS,
                self.max_iterations
            ));
        }
        if let Some(t) = self
            .implicit_steps
            .iter()
            .find(|t| !(t.is_finite() && **t > 0.0))
        {
            return bad(format!(
                "implicit time steps must be positive and finite, got {}",
                beltrami_halfedge::exact_number(*t)
            ));
        }
        if self.methods.contains(&ScanMethod::Implicit) && self.implicit_steps.is_empty() {
            return bad("the implicit method needs at least one time step".into());
        }
        Ok(())
    }
}
