//! Implicit (backward Euler) diffusion: `(M − t L) x' = M x`, unconditionally stable.
//!
//! With area normalisation `L = M⁻¹ S` is the operator of the explicit smoother
//! (`S` the symmetric stiffness `S_ij = w_ij`, `S_ii = −Σ_j w_ij`, `M` the diagonal of
//! vertex areas), so one implicit step with a small `t` agrees with one explicit step
//! with `λ = t` to first order in `t`. With weight-sum normalisation `M = D =
//! diag(Σ_j w_ij)` and `M L = W − D`, which makes `(D − t (W − D))` symmetric for any
//! symmetric weights. `docs/implicit.md` has the formulas, the boundary treatment and
//! measured times.

mod cg;
mod direct;
mod system;

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::{Laplacian, LaplacianOptions, Normalization, WeightError, WeightScheme};
use rayon::prelude::*;

use crate::config::{Boundary, WeightUpdate};
use crate::error::SmoothError;
use crate::smoother::{Iteration, StepStats, StopReason};

use cg::Cg;
use direct::{Direct, FactorError};
use system::System;

/// Vertices per parallel work unit. Fixed, so that sums (and hence results) do not
/// depend on the number of threads.
const CHUNK: usize = 4096;

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
        /// without the tolerance is an error ([`SmoothError::NotConverged`]).
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

/// The parameters of an implicit smoothing run.
///
/// The mass matrix follows the normalisation in [`laplacian`](Self::laplacian):
/// [`Normalization::Area`]`(kind)` gives the lumped mass `M = diag(A_i)` with the same
/// vertex areas as the explicit smoother (barycentric or mixed Voronoi), and
/// [`Normalization::WeightSum`] gives `M = D = diag(Σ_j w_ij)`.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::VertexAreaKind;
/// use beltrami_smooth::{Boundary, ImplicitConfig, ImplicitSolver, WeightUpdate};
/// use beltrami_weights::{LaplacianOptions, Normalization};
///
/// let config = ImplicitConfig::new(1e-3, 5)
///     .boundary(Boundary::Free)
///     .update(WeightUpdate::Once)
///     .laplacian(LaplacianOptions {
///         normalization: Normalization::Area(VertexAreaKind::MixedVoronoi),
///         ..Default::default()
///     })
///     .solver(ImplicitSolver::conjugate_gradient());
/// assert_eq!(config.steps, 5);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ImplicitConfig {
    /// The time step `t` of each backward-Euler step, positive and finite, of any size.
    /// With area normalisation a diffusion time in length² (the positions' unit
    /// squared), comparable with the explicit λ; with weight-sum normalisation
    /// dimensionless (λ of the explicit step, but not limited to (0, 1]).
    pub time_step: f64,
    /// The number of steps.
    pub steps: usize,
    /// How boundary vertices move: [`Boundary::Fixed`] (Dirichlet rows, bit-identical)
    /// or [`Boundary::Free`]; [`Boundary::Curve`] is rejected.
    pub boundary: Boundary,
    /// When the weights (and the vertex areas) are computed. With
    /// [`WeightUpdate::Once`] the matrix is factorised once and every later step is a
    /// pair of triangular solves.
    pub update: WeightUpdate,
    /// Normalisation (which also chooses the mass matrix) and negative-weight policy.
    pub laplacian: LaplacianOptions,
    /// Vertices that never move (Dirichlet rows), whatever the boundary mode.
    pub pinned: Vec<VertexId>,
    /// How each step's system is solved.
    pub solver: ImplicitSolver,
}

impl Default for ImplicitConfig {
    /// `t = 1`, one step, fixed boundary, weights every step, weight-sum
    /// normalisation, negative weights kept, Cholesky.
    fn default() -> Self {
        Self::new(1.0, 1)
    }
}

impl ImplicitConfig {
    /// The time step and the number of steps, every other setting at its default (see
    /// [`Default`]).
    #[must_use]
    pub fn new(time_step: f64, steps: usize) -> Self {
        Self {
            time_step,
            steps,
            boundary: Boundary::default(),
            update: WeightUpdate::default(),
            laplacian: LaplacianOptions::default(),
            pinned: Vec::new(),
            solver: ImplicitSolver::default(),
        }
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

    /// Sets the Laplacian options (normalisation, hence mass, and negative weights).
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

    /// Sets the solver.
    #[must_use]
    pub fn solver(mut self, solver: ImplicitSolver) -> Self {
        self.solver = solver;
        self
    }
}

/// Statistics of one implicit step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImplicitStepStats {
    /// How far vertices moved; `stuck_vertices` counts vertices held as Dirichlet rows
    /// because the operator could not move them (weights summing to ≤ 0, zero area).
    pub displacement: StepStats,
    /// Whether this step factorised the matrix numerically (Cholesky only).
    pub factorized: bool,
    /// Conjugate-gradient iterations of this step, summed over the three coordinates
    /// (0 for Cholesky).
    pub cg_iterations: usize,
    /// The relative residual `‖b − A x‖₂ / ‖b‖₂` reached, worst coordinate
    /// (conjugate gradient; `None` for Cholesky, exact to rounding).
    pub residual: Option<f64>,
}

/// What an implicit run did.
#[derive(Clone, Debug, PartialEq)]
pub struct ImplicitReport {
    /// The scheme's name.
    pub scheme: String,
    /// The configuration used.
    pub config: ImplicitConfig,
    /// Steps done.
    pub iterations: usize,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Per-step statistics.
    pub steps: Vec<ImplicitStepStats>,
    /// The largest number of stuck vertices in any step.
    pub max_stuck_vertices: usize,
    /// Symbolic analyses done (Cholesky: 1, reused by every numeric factorisation).
    pub symbolic_factorizations: usize,
    /// Numeric factorisations done (Cholesky: 1 while the operator is frozen, one per
    /// step when the weights are recomputed).
    pub numeric_factorizations: usize,
    /// The number of non-zeros of the Cholesky factor (0 for conjugate gradient).
    pub factor_nonzeros: usize,
    /// Conjugate-gradient iterations over the run, all coordinates.
    pub cg_iterations: usize,
    /// Wall time computing weights, vertex areas and matrix entries.
    pub assembly_time: Duration,
    /// Wall time of the symbolic analysis (ordering and factor structure).
    pub analysis_time: Duration,
    /// Wall time of the numeric factorisations.
    pub factorization_time: Duration,
    /// Wall time of the right-hand sides and solves (triangular solves or conjugate
    /// gradient) and the position updates.
    pub solve_time: Duration,
}

/// Positions after an implicit run and its report.
#[derive(Clone, Debug, PartialEq)]
pub struct ImplicitSmoothed {
    /// The positions after the run, one per vertex, in the input order.
    pub positions: Vec<DVec3>,
    /// What the run did.
    pub report: ImplicitReport,
}

/// The solver state.
#[derive(Debug)]
enum SolverState {
    Cholesky(Box<Direct>),
    ConjugateGradient {
        cg: Cg,
        tolerance: f64,
        max_iterations: usize,
    },
}

/// An implicit (backward Euler) diffusion smoother that the caller can drive step by
/// step.
///
/// Each [`step`](Self::step) solves `(M − t L) x' = M x` for the three coordinates,
/// where `L` is the operator of the explicit [`Smoother`](crate::Smoother) made
/// symmetric (see below): unconditionally stable, so `t` can be many times the
/// explicit stability limit.
///
/// - **Matrix.** `A = M + t K` with `K_ij = −w̄_ij`, `K_ii = Σ_j w̄_ij` and `w̄_ij =
///   ½ (w_ij + w_ji)` after the negative-weight policy. Symmetric schemes (uniform,
///   inverse distance, cotangent) keep their weights bit for bit; a scheme of your own
///   with `w_ij ≠ w_ji` is symmetrised this way, which the explicit step does not do.
///   Mass: vertex areas (area normalisation) or `Σ_j w̄_ij` (weight sum).
/// - **Dirichlet rows.** Fixed boundary, pinned and isolated vertices, and vertices
///   the operator cannot move (*stuck*: weights summing to ≤ 0, zero area) get an
///   identity row; their columns move to the right-hand side, so `A` stays symmetric
///   positive definite. Their positions stay bit-identical.
/// - **Definiteness.** Cotangent weights make `K` the finite-element stiffness matrix,
///   positive semi-definite even with negative weights, so `A` is positive definite;
///   so is any scheme with non-negative weights. A scheme whose kept negative weights
///   make `A` indefinite is reported as [`SmoothError::NotPositiveDefinite`] rather
///   than factorised with pivoting: such a step would amplify a mode, not smooth it.
/// - **Determinism.** The factorisation is sequential; assembly, right-hand sides
///   and conjugate gradient use fixed chunks, so results do not depend on the thread
///   count.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{ImplicitConfig, ImplicitSmoother, WeightUpdate};
/// use beltrami_weights::Cotangent;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh().unwrap();
/// let config = ImplicitConfig::new(10.0, 3).update(WeightUpdate::Once);
/// let mut smoother = ImplicitSmoother::new(&mesh, &sphere.positions, &Cotangent, config)?;
/// let stats = smoother.step()?;
/// assert!(stats.factorized && stats.displacement.max_displacement > 0.0);
/// // The operator is frozen: the next step reuses the factorisation.
/// assert!(!smoother.step()?.factorized);
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
///
/// # References
/// - M. Desbrun, M. Meyer, P. Schröder, A. Barr, "Implicit fairing of irregular meshes
///   using diffusion and curvature flow", SIGGRAPH 1999.
/// - M. Botsch, L. Kobbelt, M. Pauly, P. Alliez, B. Lévy, "Polygon Mesh Processing",
///   A K Peters 2010, chapter 4.
pub struct ImplicitSmoother<'a> {
    mesh: &'a HalfedgeMesh,
    scheme: &'a dyn WeightScheme,
    config: ImplicitConfig,
    laplacian: Laplacian,
    system: System,
    solver: SolverState,
    positions: Vec<DVec3>,
    next: Vec<DVec3>,
    /// Scratch: how far each vertex moved in the current step.
    distances: Vec<f64>,
    /// Vertex areas (area normalisation), reused across assemblies.
    areas: Vec<f64>,
    iteration: usize,
    weights_fresh: bool,
    assembly_error: Option<u32>,
    symbolic_factorizations: usize,
    numeric_factorizations: usize,
    cg_iterations: usize,
    assembly_time: Duration,
    analysis_time: Duration,
    factorization_time: Duration,
    solve_time: Duration,
}

impl std::fmt::Debug for ImplicitSmoother<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImplicitSmoother")
            .field("scheme", &self.scheme.name())
            .field("config", &self.config)
            .field("iteration", &self.iteration)
            .finish_non_exhaustive()
    }
}

impl<'a> ImplicitSmoother<'a> {
    /// Prepares a run on `positions` (copied): computes the first weights, assembles
    /// the matrix and, for Cholesky, its symbolic analysis (the numeric factorisation
    /// happens in the first [`step`](Self::step)).
    ///
    /// # Errors
    /// [`SmoothError::InvalidTimeStep`]; [`SmoothError::InvalidSolverSettings`];
    /// [`SmoothError::CurveNotImplicit`]; [`SmoothError::PinnedOutOfRange`];
    /// [`SmoothError::NonFiniteInput`]; [`SmoothError::Weights`] when the positions do
    /// not match the mesh or the scheme gives a non-finite weight;
    /// [`SmoothError::Factorization`] when the analysis cannot be done (out of memory).
    pub fn new(
        mesh: &'a HalfedgeMesh,
        positions: &[DVec3],
        scheme: &'a dyn WeightScheme,
        config: ImplicitConfig,
    ) -> Result<Self, SmoothError> {
        let t = config.time_step;
        if !(t > 0.0 && t.is_finite()) {
            return Err(SmoothError::InvalidTimeStep { time_step: t });
        }
        if let ImplicitSolver::ConjugateGradient {
            tolerance,
            max_iterations,
        } = config.solver
        {
            if !(tolerance > 0.0 && tolerance < 1.0) || max_iterations == 0 {
                return Err(SmoothError::InvalidSolverSettings {
                    tolerance,
                    max_iterations,
                });
            }
        }
        if config.boundary == Boundary::Curve {
            return Err(SmoothError::CurveNotImplicit);
        }
        if let Some(v) = config
            .pinned
            .iter()
            .find(|v| v.index() >= mesh.n_vertices())
        {
            return Err(SmoothError::PinnedOutOfRange {
                vertex: v.raw(),
                n_vertices: mesh.n_vertices(),
            });
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(SmoothError::NonFiniteInput { vertex: i as u32 });
        }
        let start = Instant::now();
        let laplacian = Laplacian::new(mesh, positions, scheme, config.laplacian)?;
        let mut fixed: Vec<bool> = mesh
            .vertices()
            .map(|v| {
                mesh.is_isolated(v)
                    || (mesh.is_boundary_vertex(v) && config.boundary == Boundary::Fixed)
            })
            .collect();
        for v in &config.pinned {
            fixed[v.index()] = true;
        }
        let system = System::new(mesh, &laplacian, fixed, t);
        let mut smoother = Self {
            mesh,
            scheme,
            laplacian,
            system,
            solver: match config.solver {
                ImplicitSolver::ConjugateGradient {
                    tolerance,
                    max_iterations,
                } => SolverState::ConjugateGradient {
                    cg: Cg::default(),
                    tolerance,
                    max_iterations,
                },
                // Analysed below, once the matrix is assembled.
                ImplicitSolver::Cholesky => SolverState::ConjugateGradient {
                    cg: Cg::default(),
                    tolerance: 0.0,
                    max_iterations: 0,
                },
            },
            positions: positions.to_vec(),
            next: vec![DVec3::ZERO; positions.len()],
            distances: Vec::new(),
            areas: Vec::new(),
            iteration: 0,
            weights_fresh: true,
            assembly_error: None,
            symbolic_factorizations: 0,
            numeric_factorizations: 0,
            cg_iterations: 0,
            assembly_time: Duration::ZERO,
            analysis_time: Duration::ZERO,
            factorization_time: Duration::ZERO,
            solve_time: Duration::ZERO,
            config,
        };
        smoother.assemble()?;
        smoother.assembly_time += start.elapsed();
        if smoother.config.solver == ImplicitSolver::Cholesky {
            let start = Instant::now();
            let direct = Direct::analyse(&smoother.system).map_err(|e| match e {
                FactorError::NotPositiveDefinite => {
                    SmoothError::NotPositiveDefinite { iteration: 1 }
                }
                FactorError::Other(reason) => SmoothError::Factorization { reason },
            })?;
            smoother.solver = SolverState::Cholesky(Box::new(direct));
            smoother.symbolic_factorizations += 1;
            smoother.analysis_time += start.elapsed();
        }
        Ok(smoother)
    }

    /// Fills the matrix from the operator at the current positions (vertex areas for
    /// area normalisation). A matrix entry that overflows is remembered and reported by
    /// the next step.
    fn assemble(&mut self) -> Result<(), SmoothError> {
        let areas = match self.config.laplacian.normalization {
            Normalization::Area(kind) => {
                let geometry =
                    Geometry::new(self.mesh, &self.positions).map_err(WeightError::from)?;
                if kind == VertexAreaKind::MixedVoronoi && !self.mesh.is_triangle_mesh() {
                    // The error (the operator's update reports it first).
                    geometry.vertex_areas(kind).map_err(WeightError::from)?;
                }
                // Vertex by vertex as `Geometry::vertex_areas`, in parallel.
                self.areas.resize(self.positions.len(), 0.0);
                self.areas
                    .par_chunks_mut(CHUNK)
                    .enumerate()
                    .for_each(|(c, areas)| {
                        for (k, a) in areas.iter_mut().enumerate() {
                            *a = geometry.vertex_area(VertexId::new((c * CHUNK + k) as u32), kind);
                        }
                    });
                Some(self.areas.as_slice())
            }
            // Weight sum: the mass is the weight sum.
            _ => None,
        };
        self.assembly_error = self
            .system
            .assemble(&self.laplacian, areas)
            .err()
            .map(|e| e.vertex);
        if let SolverState::Cholesky(direct) = &mut self.solver {
            // The matrix changed: the factor is stale.
            direct.invalidate();
        }
        Ok(())
    }

    /// Whether the weights must be recomputed before the next step.
    fn weights_stale(&self) -> bool {
        match self.config.update {
            WeightUpdate::Once => false,
            WeightUpdate::Every => {
                !self.weights_fresh
                    && (self.scheme.depends_on_positions()
                        || self.config.laplacian.normalization != Normalization::WeightSum)
            }
        }
    }

    /// Does one backward-Euler step and returns its statistics.
    ///
    /// # Errors
    /// [`SmoothError::Weights`] when recomputed weights are not finite;
    /// [`SmoothError::NotPositiveDefinite`] when the matrix is not positive definite
    /// (only with negative weights kept that are not an energy, see the type's
    /// documentation); [`SmoothError::NotConverged`] when conjugate gradient does not
    /// reach its tolerance; [`SmoothError::Factorization`] when the factorisation
    /// cannot be computed; [`SmoothError::NonFinite`] when a matrix entry or a position
    /// would become NaN or infinite. The positions are then left as they were before
    /// the step.
    pub fn step(&mut self) -> Result<ImplicitStepStats, SmoothError> {
        if self.weights_stale() {
            let start = Instant::now();
            self.laplacian
                .update(self.mesh, &self.positions, self.scheme)?;
            self.assemble()?;
            self.assembly_time += start.elapsed();
        }
        self.weights_fresh = false;
        let iteration = self.iteration + 1;
        if let Some(vertex) = self.assembly_error {
            return Err(SmoothError::NonFinite { vertex, iteration });
        }
        let mut stats = ImplicitStepStats::default();
        if let SolverState::Cholesky(direct) = &mut self.solver {
            if !direct.is_factored() {
                let start = Instant::now();
                let result = direct.factorize(&self.system);
                self.factorization_time += start.elapsed();
                self.numeric_factorizations += 1;
                stats.factorized = true;
                result.map_err(|e| match e {
                    FactorError::NotPositiveDefinite => {
                        SmoothError::NotPositiveDefinite { iteration }
                    }
                    FactorError::Other(reason) => SmoothError::Factorization { reason },
                })?;
            }
        }

        let start = Instant::now();
        match &mut self.solver {
            SolverState::Cholesky(direct) => {
                self.system.rhs(&self.positions, &mut self.next);
                direct.solve(&mut self.next);
            }
            SolverState::ConjugateGradient {
                cg,
                tolerance,
                max_iterations,
            } => {
                let outcome = cg.solve_coordinates(
                    &self.system,
                    &self.positions,
                    &mut self.next,
                    *tolerance,
                    *max_iterations,
                );
                stats.cg_iterations = outcome.iterations;
                self.cg_iterations += outcome.iterations;
                stats.residual = Some(outcome.residual);
                if outcome.indefinite {
                    self.solve_time += start.elapsed();
                    return Err(SmoothError::NotPositiveDefinite { iteration });
                }
                if outcome.residual.is_nan() || outcome.residual > *tolerance {
                    self.solve_time += start.elapsed();
                    return Err(SmoothError::NotConverged {
                        iteration,
                        iterations: outcome.longest,
                        residual: outcome.residual,
                        tolerance: *tolerance,
                    });
                }
            }
        }
        // Dirichlet rows keep their exact bits, whatever the solver's rounding. The
        // distances in parallel, their sum in vertex order.
        let free = &self.system.free;
        self.distances.resize(self.positions.len(), 0.0);
        let chunks: Vec<(f64, Option<u32>)> = self
            .next
            .par_chunks_mut(CHUNK)
            .zip(self.positions.par_chunks(CHUNK))
            .zip(self.distances.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, ((next, positions), distances))| {
                let mut max: f64 = 0.0;
                let mut bad = None;
                for (k, ((new, old), d)) in
                    next.iter_mut().zip(positions).zip(distances).enumerate()
                {
                    let i = c * CHUNK + k;
                    if !free[i] {
                        *new = *old;
                    }
                    if !new.is_finite() && bad.is_none() {
                        bad = Some(i as u32);
                    }
                    *d = beltrami_halfedge::geometry::distance(*old, *new);
                    max = max.max(*d);
                }
                (max, bad)
            })
            .collect();
        let mut sum = 0.0;
        for d in &self.distances {
            sum += d;
        }
        let max = chunks.iter().fold(0.0, |m: f64, &(c, _)| m.max(c));
        let bad = chunks.iter().find_map(|&(_, b)| b);
        self.solve_time += start.elapsed();
        if let Some(vertex) = bad {
            return Err(SmoothError::NonFinite { vertex, iteration });
        }
        let n = self.positions.len();
        stats.displacement = StepStats {
            max_displacement: max,
            mean_displacement: if n == 0 { 0.0 } else { sum / n as f64 },
            stuck_vertices: self.system.stuck,
        };
        self.iteration = iteration;
        std::mem::swap(&mut self.positions, &mut self.next);
        Ok(stats)
    }

    /// Runs the configured number of steps, calling `observer` after each one with the
    /// step's displacement statistics; the observer stops the run early by returning
    /// `ControlFlow::Break(())`.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn run<F>(mut self, mut observer: F) -> Result<ImplicitSmoothed, SmoothError>
    where
        F: FnMut(&Iteration<'_>) -> ControlFlow<()>,
    {
        let mut steps = Vec::with_capacity(self.config.steps);
        let mut stop = StopReason::Completed;
        while self.iteration < self.config.steps {
            let stats = self.step()?;
            steps.push(stats);
            let it = Iteration {
                index: self.iteration,
                positions: &self.positions,
                stats: stats.displacement,
            };
            if observer(&it).is_break() {
                stop = StopReason::Observer;
                break;
            }
        }
        let report = ImplicitReport {
            scheme: self.scheme.name().to_string(),
            iterations: self.iteration,
            stop,
            max_stuck_vertices: steps
                .iter()
                .map(|s| s.displacement.stuck_vertices)
                .max()
                .unwrap_or(0),
            steps,
            symbolic_factorizations: self.symbolic_factorizations,
            numeric_factorizations: self.numeric_factorizations,
            factor_nonzeros: self.factor_nonzeros(),
            cg_iterations: self.cg_iterations,
            assembly_time: self.assembly_time,
            analysis_time: self.analysis_time,
            factorization_time: self.factorization_time,
            solve_time: self.solve_time,
            config: self.config,
        };
        Ok(ImplicitSmoothed {
            positions: self.positions,
            report,
        })
    }

    /// The number of non-zeros of the Cholesky factor (0 for conjugate gradient).
    #[must_use]
    pub fn factor_nonzeros(&self) -> usize {
        match &self.solver {
            SolverState::Cholesky(direct) => direct.factor_nnz(),
            SolverState::ConjugateGradient { .. } => 0,
        }
    }

    /// The current positions.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The number of steps done.
    #[must_use]
    pub fn iteration(&self) -> usize {
        self.iteration
    }

    /// The operator as last assembled (before symmetrisation).
    #[must_use]
    pub fn laplacian(&self) -> &Laplacian {
        &self.laplacian
    }

    /// Numeric factorisations done so far.
    #[must_use]
    pub fn numeric_factorizations(&self) -> usize {
        self.numeric_factorizations
    }
}

/// Smooths `positions` with implicit steps of `scheme` as `config` says, in one call.
///
/// # Errors
/// As [`ImplicitSmoother::new`] and [`ImplicitSmoother::step`].
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{smooth_implicit, ImplicitConfig};
/// use beltrami_weights::Uniform;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh().unwrap();
/// // A step 100 times beyond what the explicit weight-sum step allows.
/// let out = smooth_implicit(&mesh, &sphere.positions, &Uniform, ImplicitConfig::new(100.0, 2))?;
/// assert!(out.positions.iter().all(|p| p.is_finite() && p.length() < 1.0));
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
pub fn smooth_implicit(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn WeightScheme,
    config: ImplicitConfig,
) -> Result<ImplicitSmoothed, SmoothError> {
    ImplicitSmoother::new(mesh, positions, scheme, config)?.run(|_| ControlFlow::Continue(()))
}
