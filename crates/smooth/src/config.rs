//! What a smoothing run does: step, iterations, boundary, weight updates.

use beltrami_halfedge::VertexId;
use beltrami_weights::LaplacianOptions;

/// How boundary vertices move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Boundary {
    /// Boundary vertices never move; their coordinates stay bit-identical. The default:
    /// a measured patch keeps its outline, as in OpenMesh and pmp-library.
    #[default]
    Fixed,
    /// Boundary vertices are smoothed like interior ones, over their own (one-sided)
    /// one-ring with the scheme's weights. The patch shrinks inwards.
    Free,
    /// Boundary vertices move along the boundary polyline only: each is pulled towards
    /// its two boundary neighbours with 1-D weights
    /// ([`WeightScheme::curve_weight`](beltrami_weights::WeightScheme::curve_weight):
    /// 1 for uniform, `1/edge length` otherwise). Needs weight-sum normalisation.
    Curve,
}

/// When the weights are computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum WeightUpdate {
    /// Recomputed from the current positions before every iteration: the geometric flow
    /// (what the paper times). The default.
    #[default]
    Every,
    /// Computed once from the input positions and frozen: a linear filter (what
    /// OpenMesh's `JacobiLaplaceSmootherT` does).
    Once,
}

/// Whether the smoother renumbers the vertices internally for memory locality.
///
/// A Jacobi sweep reads every vertex's neighbours; when their indices are scattered (a
/// subdivided, scanned or shuffled mesh) each row waits on memory. With reordering the
/// [`Smoother`](crate::Smoother) works on the mesh renumbered in reverse
/// Cuthill–McKee order
/// ([`rcm_order`](beltrami_halfedge::reorder::rcm_order)) and gives everything back in
/// the caller's numbering: positions, observer positions, statistics, error indices and
/// the chosen step are bit-identical to a run without reordering (with
/// [`Summation::Scatter`], identical to rounding). It costs the
/// renumbering (O(V + E), sequential; about the time of 5–10 frozen-weight iterations
/// on a large mesh), the permutation both ways (8 bytes per vertex) and, for a mesh
/// lent to [`Smoother::new`](crate::Smoother::new), one copy of the connectivity; a
/// mesh given by value to [`Smoother::from_owned`](crate::Smoother::from_owned) is
/// renumbered in place instead (and numbered back at the end). Per iteration it costs nothing
/// more unless something is asked in the caller's numbering: a gather of the
/// displacements for the mean of [`StepStats`](crate::StepStats) (with
/// [`Statistics::EveryIteration`], or when asked), and a gather of the positions when
/// the observer calls [`IterationView::positions`](crate::IterationView::positions).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Reorder {
    /// Reorder when the mesh has at least [`Reorder::AUTO_MIN_VERTICES`] vertices, or,
    /// for a run summed element by element ([`Summation::Scatter`] where it applies;
    /// for cotangent weights, on a mesh of triangles),
    /// when two neighbours lie more than [`Reorder::SCATTER_MAX_BANDWIDTH`] indices
    /// apart ([`bandwidth`](beltrami_halfedge::reorder::bandwidth)): that sweep keeps
    /// the rows between an element's smallest and largest vertex open, and splits the
    /// rows among the threads only where that distance is small against the mesh. The
    /// default.
    #[default]
    Auto,
    /// Work in the caller's numbering.
    Never,
    /// Always reorder (whatever the size).
    Always,
}

impl Reorder {
    /// The vertex count from which [`Reorder::Auto`] reorders.
    pub const AUTO_MIN_VERTICES: usize = 50_000;

    /// The largest [`bandwidth`](beltrami_halfedge::reorder::bandwidth) at which
    /// [`Reorder::Auto`] leaves a smaller mesh summed element by element in its own
    /// order.
    pub const SCATTER_MAX_BANDWIDTH: usize = 128;

    /// Whether a mesh with `n_vertices` vertices is reordered (for a run summed element
    /// by element, [`Reorder::Auto`] may also reorder a smaller mesh, see there).
    ///
    /// # Examples
    /// ```
    /// use beltrami_smooth::Reorder;
    /// assert!(!Reorder::Auto.applies(1000));
    /// assert!(Reorder::Auto.applies(50_000));
    /// assert!(Reorder::Always.applies(3));
    /// ```
    #[must_use]
    pub fn applies(self, n_vertices: usize) -> bool {
        match self {
            Self::Auto => n_vertices >= Self::AUTO_MIN_VERTICES,
            Self::Never => false,
            Self::Always => true,
        }
    }
}

/// How an explicit sweep with weights recomputed every iteration sums each vertex's
/// weighted neighbours.
///
/// # Examples
/// ```
/// use beltrami_smooth::{SmoothConfig, Summation, smooth};
/// use beltrami_halfedge::primitives;
/// use beltrami_weights::Cotangent;
/// let sphere = primitives::icosphere(3);
/// let mesh = sphere.mesh().unwrap();
/// let rows = smooth(&mesh, &sphere.positions, &Cotangent, SmoothConfig::new(0.5, 5)).unwrap();
/// let config = SmoothConfig::new(0.5, 5).summation(Summation::Scatter);
/// let scattered = smooth(&mesh, &sphere.positions, &Cotangent, config).unwrap();
/// // The same smoothing to rounding.
/// assert_eq!(scattered.report.scattered_sweeps, 5);
/// for (a, b) in rows.positions.iter().zip(&scattered.positions) {
///     assert!((*a - *b).abs().max_element() < 1e-14);
/// }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Summation {
    /// Row by row: each vertex's weights and weighted neighbours are summed around its
    /// one-ring, edge by edge, exactly as
    /// [`Laplacian::laplacian_at`](beltrami_weights::Laplacian::laplacian_at) documents:
    /// OpenMesh's bits, and the same bits whatever the internal vertex order
    /// ([`Reorder`]). The default.
    #[default]
    Rows,
    /// Element by element, where it applies: each triangle's three cotangents (the
    /// built-in [`Cotangent`](beltrami_weights::Cotangent) scheme, negative weights
    /// kept, every face a triangle) or each edge's inverse distance (the built-in
    /// [`InverseDistance`](beltrami_weights::InverseDistance) scheme, any mesh) is
    /// computed once per iteration and scattered into the sums of its vertices' rows;
    /// no weight is stored. A triangle's cotangents take one cross product, one square
    /// root and one division instead of one of each per corner, and an edge's weight
    /// one square root and one division instead of one at each end. It needs weight-sum
    /// normalisation, weights recomputed every iteration ([`WeightUpdate::Every`]) and
    /// plain explicit diffusion ([`Method::Laplacian`] without volume preservation);
    /// [`SmoothConfig::scatter_unmet`] says what is missing. An iteration takes 22 to
    /// 47 % less time with inverse distances and 11 to 36 % less with cotangents on the
    /// paper's surfaces and the level-8 sphere (docs/performance.md, tenth round). The
    /// results are [`Rows`](Self::Rows)' to rounding, not bit for bit: each row is summed
    /// in another order (so the last bits also follow the internal vertex order,
    /// [`Reorder`]), and each cotangent rounds differently from the per-corner formula
    /// OpenMesh uses (an inverse-distance weight has the bits of the rows' weight). A
    /// run that amplifies rounding (negative weights on obtuse triangles over many
    /// iterations) can therefore end farther from OpenMesh's result than rounding.
    /// Other configurations are summed by rows whatever this says, and so are cotangent
    /// weights on meshes with faces other than triangles.
    Scatter,
}

/// Whether [`Smoother::run`](crate::Smoother::run) computes the displacement statistics
/// ([`StepStats`](crate::StepStats)) of every iteration.
///
/// They cost a square root per vertex and, with [`Reorder`], a gather of the
/// displacements into the caller's order (the mean is summed there, so that its bits do
/// not depend on the numbering); on a large mesh with cheap weights that is a large part
/// of an iteration. The positions are the same bits either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Statistics {
    /// Every iteration's statistics are computed during the sweep and kept in
    /// [`SmoothReport::steps`](crate::SmoothReport::steps). The default.
    #[default]
    EveryIteration,
    /// Computed only when the observer asks
    /// ([`IterationView::stats`](crate::IterationView::stats)), from the positions before and
    /// after the iteration (the same bits as [`EveryIteration`](Self::EveryIteration));
    /// [`SmoothReport::steps`](crate::SmoothReport::steps) stays empty. With
    /// [`SmoothConfig::until_change`] each iteration still finds its largest
    /// displacement (no square root per vertex, no gather). Stuck-vertex counts are
    /// always kept ([`SmoothReport::max_stuck_vertices`](crate::SmoothReport::max_stuck_vertices)).
    OnDemand,
}

/// How each iteration moves the vertices.
///
/// Every method is built from the same Jacobi sweep `x ← x + s·L x` (see
/// [`Smoother`](crate::Smoother)); they differ in the steps `s` and in what happens
/// between sweeps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub enum Method {
    /// One sweep with step λ per iteration: plain diffusion (the paper's method). Shrinks.
    #[default]
    Laplacian,
    /// Taubin's λ|μ filter (Taubin 1995, "A signal processing approach to fair surface
    /// design"): each iteration is two sweeps, first with λ > 0, then with `mu` < −λ.
    ///
    /// With weight-sum normalisation and non-negative weights, the operator `K = −L` has
    /// eigenvalues `k ∈ [0, 2]` and one iteration multiplies the mode `k` by
    /// `f(k) = (1 − λk)(1 − μk)`. `f(0) = f(k_PB) = 1` at the pass-band frequency
    /// `k_PB = 1/λ + 1/μ`, which must be positive (`μ < −λ`): low frequencies (the form)
    /// pass with a gain between 1 and `1 + (λ + μ)² / (−4λμ)`, high frequencies
    /// (`k > k_PB`, the noise) are damped. Stability of the highest mode needs
    /// `f(2) > −1`, i.e. `(1 − 2λ)(1 − 2μ) > −1`; both conditions are checked. Typical:
    /// `k_PB` between 0.01 and 0.1, e.g. λ = 0.33, μ = −0.34.
    Taubin {
        /// The negative (inflating) step μ, < −λ.
        mu: f64,
    },
    /// The HC algorithm (Vollmer, Mencl, Müller 1999, "Improved Laplacian smoothing of
    /// noisy surface meshes"): after each sweep from `q` to `p`, every moving vertex is
    /// pushed back by `b_i = p_i − (α o_i + (1 − α) q_i)` (`o` the input positions):
    /// `p_i ← p_i − (β b_i + (1 − β) b̄_i)`, with `b̄_i` the plain average of `b` over
    /// the one-ring. A local correction, so it works on open
    /// patches, where a global volume rescale is undefined. Typical α = 0.1, β = 0.6.
    Hc {
        /// The pull towards the input positions, in [0, 1].
        alpha: f64,
        /// The weight of a vertex's own correction against its neighbours', in [0, 1].
        beta: f64,
    },
    /// Implicit (backward Euler) diffusion: each iteration solves
    /// `(M − λ L) x' = M x` for the three coordinates, so λ (the time step) can be many
    /// times the explicit stability limit.
    ///
    /// - **Matrix.** `A = M + λ K` with `K_ij = −w̄_ij`, `K_ii = Σ_j w̄_ij` and `w̄_ij =
    ///   ½ (w_ij + w_ji)` after the negative-weight policy. Symmetric schemes (uniform,
    ///   inverse distance, cotangent) keep their weights bit for bit; a scheme of your
    ///   own with `w_ij ≠ w_ji` is symmetrised this way, which the explicit step does
    ///   not do. Mass: vertex areas (area normalisation, `L = M⁻¹ S`, so one step with a
    ///   small λ agrees with one explicit step to first order) or `Σ_j w̄_ij` (weight
    ///   sum).
    /// - **Dirichlet rows.** Fixed boundary, pinned and isolated vertices, and vertices
    ///   the operator cannot move (*stuck*: weights summing to ≤ 0, zero area) get an
    ///   identity row; their columns move to the right-hand side, so `A` stays
    ///   symmetric positive definite. Their positions stay bit-identical.
    /// - **Definiteness.** Cotangent weights make `K` the finite-element stiffness
    ///   matrix, positive semi-definite even with negative weights, so `A` is positive
    ///   definite; so is any scheme with non-negative weights. A scheme whose kept
    ///   negative weights make `A` indefinite is reported as
    ///   [`SmoothError::NotPositiveDefinite`](crate::SmoothError::NotPositiveDefinite)
    ///   rather than factorised with pivoting: such a step would amplify a mode.
    /// - **Determinism.** The factorisation is sequential; assembly, right-hand sides
    ///   and conjugate gradient use fixed chunks, so results do not depend on the
    ///   thread count.
    /// - **Settings.** [`Boundary::Curve`] and
    ///   [`preserve_volume`](SmoothConfig::preserve_volume) are refused;
    ///   [`reorder`](SmoothConfig::reorder) is ignored (the Cholesky factorisation
    ///   orders the unknowns itself). With [`WeightUpdate::Once`] the matrix is
    ///   factorised once and every later step is a pair of triangular solves.
    ///
    /// References: M. Desbrun, M. Meyer, P. Schröder, A. Barr, "Implicit fairing of
    /// irregular meshes using diffusion and curvature flow", SIGGRAPH 1999; M. Botsch,
    /// L. Kobbelt, M. Pauly, P. Alliez, B. Lévy, "Polygon Mesh Processing", A K Peters
    /// 2010, chapter 4. `docs/implicit.md` has the formulas and measured times.
    Implicit {
        /// How each step's linear system is solved.
        solver: ImplicitSolver,
    },
}

/// The default step λ of plain diffusion, HC and implicit runs: 0.8, the paper's.
pub const DEFAULT_LAMBDA: f64 = 0.8;

/// Taubin's classic step λ = 0.6307, which with μ = −0.6732 gives the pass band
/// `1/λ + 1/μ` = [`TAUBIN_PASS_BAND`] (Taubin 1995): the default λ of a Taubin run.
pub const TAUBIN_LAMBDA: f64 = 0.6307;

/// Taubin's classic pass-band frequency `k_pb = 1/λ + 1/μ` = 0.1 (Taubin 1995): a Taubin
/// run without μ gets the μ of this pass band (see [`Method::taubin_or_pass_band`]).
pub const TAUBIN_PASS_BAND: f64 = 0.1;

/// The published default α of the HC algorithm (Vollmer et al. 1999): 0.1.
pub const HC_ALPHA: f64 = 0.1;

/// The published default β of the HC algorithm (Vollmer et al. 1999): 0.6.
pub const HC_BETA: f64 = 0.6;

impl Method {
    /// Taubin's filter with `mu`, or, without it, with the μ of the classic pass band
    /// [`TAUBIN_PASS_BAND`] for the step `lambda` (see
    /// [`taubin_pass_band`](Self::taubin_pass_band)).
    ///
    /// # Examples
    /// ```
    /// use beltrami_smooth::{Method, TAUBIN_LAMBDA, TAUBIN_PASS_BAND};
    /// assert_eq!(Method::taubin_or_pass_band(0.5, Some(-0.53)), Method::Taubin { mu: -0.53 });
    /// let Method::Taubin { mu } = Method::taubin_or_pass_band(TAUBIN_LAMBDA, None) else { unreachable!() };
    /// assert!((1.0 / TAUBIN_LAMBDA + 1.0 / mu - TAUBIN_PASS_BAND).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn taubin_or_pass_band(lambda: f64, mu: Option<f64>) -> Self {
        match mu {
            Some(mu) => Self::Taubin { mu },
            None => Self::taubin_pass_band(lambda, TAUBIN_PASS_BAND),
        }
    }

    /// The HC algorithm with `alpha` and `beta`, each [`HC_ALPHA`] or [`HC_BETA`] when not
    /// given.
    #[must_use]
    pub fn hc_or_default(alpha: Option<f64>, beta: Option<f64>) -> Self {
        Self::Hc {
            alpha: alpha.unwrap_or(HC_ALPHA),
            beta: beta.unwrap_or(HC_BETA),
        }
    }

    /// Taubin's filter with μ chosen for a pass-band frequency `k_pb`:
    /// `μ = 1 / (k_pb − 1/λ)`.
    ///
    /// # Examples
    /// ```
    /// use beltrami_smooth::Method;
    /// let Method::Taubin { mu } = Method::taubin_pass_band(0.33, 0.1) else { unreachable!() };
    /// assert!((1.0 / 0.33 + 1.0 / mu - 0.1).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn taubin_pass_band(lambda: f64, k_pb: f64) -> Self {
        Self::Taubin {
            mu: 1.0 / (k_pb - 1.0 / lambda),
        }
    }

    /// The HC algorithm with the published defaults α = 0.1, β = 0.6.
    #[must_use]
    pub fn hc() -> Self {
        Self::hc_or_default(None, None)
    }

    /// Implicit diffusion with the given solver.
    #[must_use]
    pub fn implicit(solver: ImplicitSolver) -> Self {
        Self::Implicit { solver }
    }

    /// A short name: `laplacian`, `taubin`, `hc` or `implicit`.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Laplacian => "laplacian",
            Self::Taubin { .. } => "taubin",
            Self::Hc { .. } => "hc",
            Self::Implicit { .. } => "implicit",
        }
    }
}

/// How the linear system of a step is solved.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub enum ImplicitSolver {
    /// Sparse Cholesky factorisation `A = L Lᵀ` (faer, approximate minimum degree
    /// ordering): the sparsity analysis once per run, the numeric factorisation once
    /// while the operator is frozen and again whenever the weights are recomputed; each
    /// step is then two triangular solves. Exact to rounding. The library's default
    /// (the command line's `--solver` defaults to conjugate gradient instead, the faster
    /// first step on large meshes; see `docs/implicit.md`, "Which solver").
    #[default]
    Cholesky,
    /// Conjugate gradient with a Jacobi (diagonal) preconditioner, started from the
    /// current positions, per coordinate: no factorisation, memory linear in the mesh,
    /// for meshes too large to factorise. Stops when `‖b − A x‖₂ ≤ tolerance ‖b‖₂`.
    ConjugateGradient {
        /// The relative residual to reach, in (0, 1).
        tolerance: f64,
        /// The iteration limit per coordinate and step (at least 1); reaching it
        /// without the tolerance is an error ([`SmoothError::NotConverged`](crate::SmoothError::NotConverged)).
        max_iterations: usize,
    },
}

impl ImplicitSolver {
    /// Conjugate gradient with a relative tolerance of 1e-10 and at most 1000 iterations.
    #[must_use]
    pub fn conjugate_gradient() -> Self {
        Self::ConjugateGradient {
            tolerance: 1e-10,
            max_iterations: 1000,
        }
    }
}

/// How long to diffuse, in physical units, instead of λ × iterations.
///
/// The heat equation `∂x/∂t = Δx` run for a time `t` convolves with a Gaussian of
/// variance `σ² = 2t` per axis. Matching the ISO 16610 Gaussian filter (50 % amplitude
/// transmission at the cut-off wavelength λc) gives `σ = 0.18739 λc` and
/// `t = ln 2 · λc² / (4π²) = 0.017558 λc²`.
///
/// The [`Smoother`](crate::Smoother) turns a duration into iterations and a step:
/// - area normalisation (`L = M⁻¹ Σ w_ij (x_j − x_i)`, the cotangent Laplace–Beltrami
///   operator with [`Cotangent`](beltrami_weights::Cotangent)): λ is a time per
///   iteration; `n = ⌈t / τ⌉` iterations of `λ = t / n`, where
///   `τ = min(λ_config, 0.5 / max_i (W_i / A_i))` keeps every vertex's own coefficient
///   at least ½ (stable for non-negative weights);
/// - weight-sum normalisation: a normalised row applied to `½|x − x_i|²` gives half the
///   weighted mean squared edge length `⟨ℓ²⟩_i = Σ_j w_ij ℓ_ij² / Σ_j w_ij`, and `Δ` of
///   that function is 2, so the row approximates `(⟨ℓ²⟩_i / 4) Δ` (on a regular mesh
///   with edge length ℓ every normalised operator equals `(ℓ²/4) Δ`). One iteration
///   with step λ advances the time by `λ ⟨ℓ²⟩ / 4`, with `⟨ℓ²⟩` the mean of `⟨ℓ²⟩_i`
///   over the moving vertices, weighted with the scheme's input weights;
///   `n = ⌈4t / (λ_config ⟨ℓ²⟩)⌉` iterations of `λ = 4t / (n ⟨ℓ²⟩)`. Exact on regular
///   meshes; on irregular ones the local time varies with `⟨ℓ²⟩_i` (use area
///   normalisation there).
///
/// An implicit run ([`Method::Implicit`]) converts the time the same way, with λ the
/// largest step and no stability cap (backward Euler is stable at any step): more,
/// smaller steps follow the Gaussian more closely, fewer are cheaper.
///
/// Either way the result no longer depends on the mesh density or the scale of the
/// coordinates, only on `t` (length²) or λc (length).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum DiffusionTime {
    /// A diffusion time `t`, in length² (e.g. mm²).
    Time(f64),
    /// A Gaussian-filter cut-off wavelength λc, in length (e.g. mm): `t = 0.017558 λc²`.
    Cutoff(f64),
}

impl DiffusionTime {
    /// The duration of a run given a time `t` or a cut-off wavelength (the cut-off when
    /// both are given); `None`, a fixed iteration count, when neither is.
    ///
    /// # Examples
    /// ```
    /// use beltrami_smooth::DiffusionTime;
    /// assert_eq!(DiffusionTime::from_options(Some(0.5), None), Some(DiffusionTime::Time(0.5)));
    /// assert_eq!(DiffusionTime::from_options(None, Some(2.0)), Some(DiffusionTime::Cutoff(2.0)));
    /// assert_eq!(DiffusionTime::from_options(None, None), None);
    /// ```
    #[must_use]
    pub fn from_options(time: Option<f64>, cutoff: Option<f64>) -> Option<Self> {
        cutoff.map(Self::Cutoff).or(time.map(Self::Time))
    }

    /// The diffusion time in length²: `t`, or `ln 2 · λc² / (4π²)`.
    ///
    /// # Examples
    /// ```
    /// use beltrami_smooth::DiffusionTime;
    /// assert!((DiffusionTime::Cutoff(1.0).time() - 0.017558).abs() < 1e-6);
    /// ```
    #[must_use]
    pub fn time(self) -> f64 {
        match self {
            Self::Time(t) => t,
            Self::Cutoff(lc) => {
                std::f64::consts::LN_2 * lc * lc / (4.0 * std::f64::consts::PI.powi(2))
            }
        }
    }

    /// The Gaussian's standard deviation per axis, `σ = √(2t)`, in length.
    #[must_use]
    pub fn sigma(self) -> f64 {
        (2.0 * self.time()).sqrt()
    }
}

/// The parameters of a smoothing run, explicit or implicit: the step and count, and
/// what every method shares (boundary, weight updates, normalisation, pinned
/// vertices, duration, convergence, statistics); the [`method`](Self::method) says
/// how each iteration moves the vertices.
///
/// # Examples
/// ```
/// use beltrami_smooth::{Boundary, ImplicitSolver, Method, SmoothConfig, WeightUpdate};
/// let config = SmoothConfig::new(0.8, 100).boundary(Boundary::Free).update(WeightUpdate::Once);
/// assert_eq!(config.lambda, 0.8);
/// // The same settings, as backward-Euler steps of time 5 solved by conjugate gradient.
/// let implicit = config
///     .lambda(5.0)
///     .method(Method::implicit(ImplicitSolver::conjugate_gradient()));
/// assert_eq!(implicit.method.name(), "implicit");
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SmoothConfig {
    /// The step λ. With weight-sum normalisation, a fraction in (0, 1]: each iteration
    /// moves a vertex that fraction of the way to its weighted neighbour average. With
    /// area normalisation, a diffusion time per iteration in length² (> 0, small). With
    /// [`Method::Implicit`], the time step of each backward-Euler step, positive and
    /// finite, of any size (dimensionless with weight-sum normalisation, length² with
    /// area normalisation).
    pub lambda: f64,
    /// The number of iterations (implicit steps).
    pub iterations: usize,
    /// How boundary vertices move.
    pub boundary: Boundary,
    /// When weights are computed.
    pub update: WeightUpdate,
    /// Normalisation and negative-weight policy of the Laplacian.
    pub laplacian: LaplacianOptions,
    /// Vertices that never move, whatever the boundary mode.
    pub pinned: Vec<VertexId>,
    /// How each iteration moves the vertices (plain diffusion, Taubin, HC).
    pub method: Method,
    /// After every iteration, rescale the mesh about its surface centroid by
    /// `β = (V₀/V)^(1/3)` so that the enclosed volume stays the input's (Desbrun et al.
    /// 1999). Needs a closed mesh and no pinned vertices; not with
    /// [`Method::Implicit`].
    pub preserve_volume: bool,
    /// Diffuse for this physical time instead of [`iterations`](Self::iterations)
    /// steps of [`lambda`](Self::lambda); then `lambda` is the largest step allowed and
    /// the smoother chooses the iteration count (see [`DiffusionTime`]). Only with
    /// [`Method::Laplacian`] and [`Method::Implicit`].
    pub duration: Option<DiffusionTime>,
    /// Stop early, with [`StopReason::Converged`](crate::StopReason::Converged), once an
    /// iteration moves no vertex farther than this distance (in the positions' unit);
    /// `iterations` stays the upper limit.
    pub until_change: Option<f64>,
    /// Whether the vertices are renumbered internally for speed (see [`Reorder`]); the
    /// results are the same bits either way (with [`Summation::Scatter`], the same to
    /// rounding).
    pub reorder: Reorder,
    /// Whether [`Smoother::run`](crate::Smoother::run) computes every iteration's
    /// displacement statistics (see [`Statistics`]).
    pub statistics: Statistics,
    /// How a sweep with weights recomputed every iteration sums each row (see
    /// [`Summation`]).
    pub summation: Summation,
}

impl Default for SmoothConfig {
    /// The paper's step (λ = 0.8), 10 iterations, fixed boundary, weights recomputed
    /// every iteration, weight-sum normalisation, negative weights kept.
    fn default() -> Self {
        Self::new(0.8, 10)
    }
}

impl SmoothConfig {
    /// Whether the operator changes from one iteration to the next, so that a run must
    /// recompute it: weights recomputed every iteration, and positions that matter to
    /// them (a scheme that reads positions, area normalisation, or a curve boundary).
    /// The one rule both engines follow.
    pub(crate) fn operator_changes(&self, scheme: &dyn beltrami_weights::WeightScheme) -> bool {
        self.update == WeightUpdate::Every
            && (scheme.depends_on_positions()
                || self.laplacian.normalization != beltrami_weights::Normalization::WeightSum
                || self.boundary == Boundary::Curve)
    }

    /// λ and the iteration count, every other setting at its default.
    #[must_use]
    pub fn new(lambda: f64, iterations: usize) -> Self {
        Self {
            lambda,
            iterations,
            boundary: Boundary::default(),
            update: WeightUpdate::default(),
            laplacian: LaplacianOptions::default(),
            pinned: Vec::new(),
            method: Method::Laplacian,
            preserve_volume: false,
            duration: None,
            until_change: None,
            reorder: Reorder::default(),
            statistics: Statistics::default(),
            summation: Summation::default(),
        }
    }

    /// Sets the step λ (see [`lambda`](Self::lambda)).
    #[must_use]
    pub fn lambda(mut self, lambda: f64) -> Self {
        self.lambda = lambda;
        self
    }

    /// Sets the number of iterations.
    #[must_use]
    pub fn iterations(mut self, iterations: usize) -> Self {
        self.iterations = iterations;
        self
    }

    /// Sets the method (plain diffusion, Taubin, HC, implicit).
    #[must_use]
    pub fn method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }

    /// Switches the volume-preserving rescale on or off.
    #[must_use]
    pub fn preserve_volume(mut self, yes: bool) -> Self {
        self.preserve_volume = yes;
        self
    }

    /// Diffuses for a physical time or cut-off wavelength instead of a fixed count.
    #[must_use]
    pub fn duration(mut self, duration: DiffusionTime) -> Self {
        self.duration = Some(duration);
        self
    }

    /// Stops once an iteration moves no vertex farther than `eps` (positions' unit).
    #[must_use]
    pub fn until_change(mut self, eps: f64) -> Self {
        self.until_change = Some(eps);
        self
    }

    /// Sets the internal vertex reordering (see [`Reorder`]).
    #[must_use]
    pub fn reorder(mut self, reorder: Reorder) -> Self {
        self.reorder = reorder;
        self
    }

    /// Sets when displacement statistics are computed (see [`Statistics`]).
    #[must_use]
    pub fn statistics(mut self, statistics: Statistics) -> Self {
        self.statistics = statistics;
        self
    }

    /// Sets how a sweep with weights recomputed every iteration sums each row (see
    /// [`Summation`]).
    #[must_use]
    pub fn summation(mut self, summation: Summation) -> Self {
        self.summation = summation;
        self
    }

    /// What [`Summation::Scatter`] needs that this configuration lacks with `scheme`,
    /// in words, the first of: `"cotangent or inverse-distance weights"` (the built-in
    /// [`Cotangent`](beltrami_weights::Cotangent) or
    /// [`InverseDistance`](beltrami_weights::InverseDistance)), `"weights recomputed
    /// every iteration"`, `"weight-sum normalisation"`, `"negative weights kept"` (for
    /// cotangents), `"plain explicit diffusion"`, `"no volume preservation"`; `None`
    /// when it applies. The
    /// summation asked for does not matter. A front end that takes the summation from
    /// its user can refuse a request that would change nothing.
    ///
    /// # Examples
    /// ```
    /// use beltrami_smooth::{SmoothConfig, WeightUpdate};
    /// use beltrami_weights::{Cotangent, Uniform};
    /// let config = SmoothConfig::new(0.5, 10);
    /// assert_eq!(config.scatter_unmet(&Cotangent), None);
    /// assert_eq!(
    ///     config.scatter_unmet(&Uniform),
    ///     Some("cotangent or inverse-distance weights")
    /// );
    /// let once = config.update(WeightUpdate::Once);
    /// assert_eq!(
    ///     once.scatter_unmet(&Cotangent),
    ///     Some("weights recomputed every iteration")
    /// );
    /// ```
    #[must_use]
    pub fn scatter_unmet(
        &self,
        scheme: &dyn beltrami_weights::WeightScheme,
    ) -> Option<&'static str> {
        let any: &dyn std::any::Any = scheme;
        let distance = any.is::<beltrami_weights::InverseDistance>();
        [
            (
                any.is::<beltrami_weights::Cotangent>() || distance,
                "cotangent or inverse-distance weights",
            ),
            (
                self.update == WeightUpdate::Every,
                "weights recomputed every iteration",
            ),
            (
                self.laplacian.normalization == beltrami_weights::Normalization::WeightSum,
                "weight-sum normalisation",
            ),
            (
                distance || self.laplacian.negative == beltrami_weights::NegativeWeights::Keep,
                "negative weights kept",
            ),
            (self.method == Method::Laplacian, "plain explicit diffusion"),
            (!self.preserve_volume, "no volume preservation"),
        ]
        .into_iter()
        .find(|(met, _)| !met)
        .map(|(_, needed)| needed)
    }

    /// Sets the boundary mode.
    #[must_use]
    pub fn boundary(mut self, boundary: Boundary) -> Self {
        self.boundary = boundary;
        self
    }

    /// Sets the weight-update policy.
    #[must_use]
    pub fn update(mut self, update: WeightUpdate) -> Self {
        self.update = update;
        self
    }

    /// Sets the Laplacian options.
    #[must_use]
    pub fn laplacian(mut self, laplacian: LaplacianOptions) -> Self {
        self.laplacian = laplacian;
        self
    }

    /// Sets the pinned vertices.
    #[must_use]
    pub fn pinned(mut self, pinned: Vec<VertexId>) -> Self {
        self.pinned = pinned;
        self
    }
}
