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

use std::borrow::Cow;
use std::time::{Duration, Instant};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::{Laplacian, Normalization, WeightError, WeightScheme};
use rayon::prelude::*;

use crate::config::{Boundary, ImplicitSolver, Method, SmoothConfig};
use crate::duration::{Plan, resolve_duration};
use crate::error::SmoothError;
use crate::report::{SolveStats, SolverReport, StepStats};

use cg::Cg;
use direct::{Direct, FactorError};
use system::System;

/// Vertices per parallel work unit. Fixed, so that sums (and hence results) do not
/// depend on the number of threads.
const CHUNK: usize = 4096;

/// The vertices that never move: isolated ones, boundary vertices with a fixed
/// boundary, and the pinned ones (computed per vertex in parallel).
fn fixed_vertices(mesh: &HalfedgeMesh, config: &SmoothConfig) -> Vec<bool> {
    let fixed_boundary = config.boundary == Boundary::Fixed;
    let mut fixed: Vec<bool> = (0..mesh.n_vertices())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|i| {
            let v = VertexId::new(i as u32);
            mesh.is_isolated(v) || (fixed_boundary && mesh.is_boundary_vertex(v))
        })
        .collect();
    for v in &config.pinned {
        fixed[v.index()] = true;
    }
    fixed
}

/// The solver state before the first assembly: conjugate gradient as asked, or a
/// placeholder for Cholesky, which is analysed once the matrix is assembled.
fn initial_solver_state(solver: ImplicitSolver) -> SolverState {
    match solver {
        ImplicitSolver::ConjugateGradient {
            tolerance,
            max_iterations,
        } => SolverState::ConjugateGradient {
            cg: Cg::default(),
            tolerance,
            max_iterations,
        },
        ImplicitSolver::Cholesky => SolverState::ConjugateGradient {
            cg: Cg::default(),
            tolerance: 0.0,
            max_iterations: 0,
        },
    }
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

/// The implicit engine of a [`Smoother`](crate::Smoother) ([`Method::Implicit`]):
/// each step solves `(M − t L) x' = M x` for the three coordinates (see
/// [`Method::Implicit`] for the matrix, the Dirichlet rows and determinism).
pub(crate) struct Implicit<'a> {
    /// The mesh: borrowed, or given by value (then handed back by
    /// [`finish`](Self::finish)).
    mesh: Cow<'a, HalfedgeMesh>,
    scheme: &'a dyn WeightScheme,
    config: SmoothConfig,
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

impl std::fmt::Debug for Implicit<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Implicit")
            .field("scheme", &self.scheme.name())
            .field("config", &self.config)
            .field("iteration", &self.iteration)
            .finish_non_exhaustive()
    }
}

impl<'a> Implicit<'a> {
    /// Prepares a run on `positions` (copied when borrowed): computes the first
    /// weights, assembles the matrix and, for Cholesky, its symbolic analysis (the numeric factorisation
    /// happens in the first [`step`](Self::step)); `config` has been validated (see
    /// [`Smoother::new`](crate::Smoother::new)).
    ///
    /// # Errors
    /// [`SmoothError::Weights`] when the positions do not match the mesh or the scheme
    /// gives a non-finite weight; [`SmoothError::InvalidDuration`] when a time cannot
    /// be turned into steps; [`SmoothError::Factorization`] when the analysis cannot be
    /// done (out of memory).
    pub(crate) fn new(
        mesh: Cow<'a, HalfedgeMesh>,
        positions: Cow<'_, [DVec3]>,
        scheme: &'a dyn WeightScheme,
        config: SmoothConfig,
    ) -> Result<Self, SmoothError> {
        let Method::Implicit { solver } = config.method else {
            unreachable!("the implicit engine runs Method::Implicit only")
        };
        let mut config = config;
        let start = Instant::now();
        let laplacian = Laplacian::new(&mesh, &positions, scheme, config.laplacian)?;
        let largest = positions
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0_f64, f64::max);
        if largest != 0.0 && !crate::IMPLICIT_COORDINATES.contains(&largest) {
            return Err(SmoothError::ImplicitScale { largest });
        }
        let fixed = fixed_vertices(&mesh, &config);
        if let Some(duration) = config.duration {
            let moves: Vec<bool> = fixed.iter().map(|f| !f).collect();
            let plan = Plan {
                perm: None,
                positions: &positions,
                laplacian: &laplacian,
                moves: &moves,
                max_lambda: config.lambda,
                explicit: false,
            };
            let (lambda, iterations) = resolve_duration(&plan, duration.time())?;
            config.lambda = lambda;
            config.iterations = iterations;
        }
        let system = System::new(&laplacian, fixed, config.lambda);
        let mut smoother = Self {
            mesh,
            scheme,
            laplacian,
            system,
            solver: initial_solver_state(solver),
            next: vec![DVec3::ZERO; positions.len()],
            // Positions given by value become the smoother's own; borrowed ones are copied.
            positions: positions.into_owned(),
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
        if solver == ImplicitSolver::Cholesky {
            smoother.analyse()?;
        }
        Ok(smoother)
    }

    /// The symbolic analysis of the direct solver, once the matrix is assembled.
    fn analyse(&mut self) -> Result<(), SmoothError> {
        let start = Instant::now();
        let direct =
            Direct::analyse(&self.system.matrix(&self.laplacian)).map_err(|e| match e {
                FactorError::NotPositiveDefinite => {
                    SmoothError::NotPositiveDefinite { iteration: 1 }
                }
                FactorError::Other(reason) => SmoothError::Factorization { reason },
            })?;
        self.solver = SolverState::Cholesky(Box::new(direct));
        self.symbolic_factorizations += 1;
        self.analysis_time += start.elapsed();
        Ok(())
    }

    /// Fills the matrix from the operator at the current positions (vertex areas for
    /// area normalisation). A matrix entry that overflows is remembered and reported by
    /// the next step.
    fn assemble(&mut self) -> Result<(), SmoothError> {
        let areas = match self.config.laplacian.normalization {
            Normalization::Area(kind) => {
                let geometry =
                    Geometry::new(&self.mesh, &self.positions).map_err(WeightError::from)?;
                self.areas.resize(self.positions.len(), 0.0);
                geometry
                    .vertex_areas_into(kind, &mut self.areas)
                    .map_err(WeightError::from)?;
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
        !self.weights_fresh && self.config.operator_changes(self.scheme)
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
    pub(crate) fn step(&mut self) -> Result<StepStats, SmoothError> {
        if self.weights_stale() {
            let start = Instant::now();
            self.laplacian
                .update(&self.mesh, &self.positions, self.scheme)?;
            self.assemble()?;
            self.assembly_time += start.elapsed();
        }
        self.weights_fresh = false;
        let iteration = self.iteration + 1;
        if let Some(vertex) = self.assembly_error {
            return Err(SmoothError::NonFinite { vertex, iteration });
        }
        let mut stats = SolveStats::default();
        self.factorize(iteration, &mut stats)?;
        let start = Instant::now();
        let solved = self.solve(iteration, &mut stats);
        if solved.is_err() {
            self.solve_time += start.elapsed();
        }
        solved?;
        let (max, sum, bad) = self.settle();
        self.solve_time += start.elapsed();
        if let Some(vertex) = bad {
            return Err(SmoothError::NonFinite { vertex, iteration });
        }
        let n = self.positions.len();
        self.iteration = iteration;
        std::mem::swap(&mut self.positions, &mut self.next);
        Ok(StepStats {
            max_displacement: max,
            mean_displacement: if n == 0 { 0.0 } else { sum / n as f64 },
            stuck_vertices: self.system.stuck,
            solve: Some(stats),
        })
    }

    /// Factorises the system for the direct solver when it is not factored yet.
    fn factorize(&mut self, iteration: usize, stats: &mut SolveStats) -> Result<(), SmoothError> {
        if let SolverState::Cholesky(direct) = &mut self.solver
            && !direct.is_factored()
        {
            let start = Instant::now();
            let result = direct.factorize(&self.system.matrix(&self.laplacian));
            self.factorization_time += start.elapsed();
            self.numeric_factorizations += 1;
            stats.factorized = true;
            result.map_err(|e| match e {
                FactorError::NotPositiveDefinite => SmoothError::NotPositiveDefinite { iteration },
                FactorError::Other(reason) => SmoothError::Factorization { reason },
            })?;
        }
        Ok(())
    }

    /// Solves the step's system into `next`, by the direct or the iterative solver.
    fn solve(&mut self, iteration: usize, stats: &mut SolveStats) -> Result<(), SmoothError> {
        match &mut self.solver {
            SolverState::Cholesky(direct) => {
                let matrix = self.system.matrix(&self.laplacian);
                matrix.rhs(&self.positions, &mut self.next);
                direct.solve(&mut self.next);
            }
            SolverState::ConjugateGradient {
                cg,
                tolerance,
                max_iterations,
            } => {
                let outcome = cg.solve_coordinates(
                    &self.system.matrix(&self.laplacian),
                    &self.positions,
                    &mut self.next,
                    *tolerance,
                    *max_iterations,
                );
                stats.cg_iterations = outcome.iterations;
                self.cg_iterations += outcome.iterations;
                stats.residual = Some(outcome.residual);
                if outcome.indefinite {
                    return Err(SmoothError::NotPositiveDefinite { iteration });
                }
                if outcome.residual.is_nan() || outcome.residual > *tolerance {
                    return Err(SmoothError::NotConverged {
                        iteration,
                        iterations: outcome.longest,
                        residual: outcome.residual,
                        tolerance: *tolerance,
                    });
                }
            }
        }
        Ok(())
    }

    /// Gives the fixed (Dirichlet) rows of `next` back their exact positions and
    /// measures the displacements: the largest, their sum (in vertex order) and the
    /// first vertex whose new position is not finite.
    fn settle(&mut self) -> (f64, f64, Option<u32>) {
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
        (max, sum, bad)
    }

    /// The scheme's name, for the report.
    pub(crate) fn scheme_name(&self) -> String {
        self.scheme.name().to_string()
    }

    /// The positions before the last step (after a step, `next` holds them).
    pub(crate) fn before(&self) -> &[DVec3] {
        &self.next
    }

    /// Ends the run: the positions, the configuration, the wall times and what the
    /// solver did.
    pub(crate) fn finish(self) -> crate::smoother::Finished {
        let solver = SolverReport {
            symbolic_factorizations: self.symbolic_factorizations,
            numeric_factorizations: self.numeric_factorizations,
            factor_nonzeros: self.factor_nonzeros(),
            cg_iterations: self.cg_iterations,
            analysis_time: self.analysis_time,
            factorization_time: self.factorization_time,
        };
        crate::smoother::Finished {
            positions: self.positions,
            mesh: match self.mesh {
                Cow::Owned(mesh) => Some(mesh),
                Cow::Borrowed(_) => None,
            },
            config: self.config,
            weight_time: self.assembly_time,
            update_time: self.solve_time,
            solver: Some(solver),
            scattered_sweeps: 0,
        }
    }

    /// The configuration; with a duration, `lambda` and `iterations` are the step and
    /// count chosen.
    pub(crate) fn config(&self) -> &SmoothConfig {
        &self.config
    }

    /// The number of non-zeros of the Cholesky factor (0 for conjugate gradient).
    pub(crate) fn factor_nonzeros(&self) -> usize {
        match &self.solver {
            SolverState::Cholesky(direct) => direct.factor_nnz(),
            SolverState::ConjugateGradient { .. } => 0,
        }
    }

    /// The current positions.
    pub(crate) fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The number of steps done.
    pub(crate) fn iteration(&self) -> usize {
        self.iteration
    }

    /// The operator as last assembled (before symmetrisation).
    pub(crate) fn laplacian(&self) -> &Laplacian {
        &self.laplacian
    }
}
