//! The smoother: one type for explicit and implicit runs, driven step by step or by
//! [`Smoother::run`] with an observer, and [`smooth`] for one call.

use std::borrow::Cow;
use std::ops::ControlFlow;
use std::time::Duration;

use beltrami_halfedge::reorder::VertexPermutation;
use beltrami_halfedge::{DVec3, HalfedgeMesh, PolygonList, TopologyError};
use beltrami_weights::{Laplacian, Normalization, WeightScheme};

use crate::config::{Boundary, DiffusionTime, ImplicitSolver, Method, SmoothConfig, Statistics};
use crate::error::{Short, SmoothError};
use crate::explicit::{Explicit, Want};
use crate::implicit::Implicit;
use crate::report::{IterationView, SmoothReport, Smoothed, SolverReport, StepStats, StopReason};

/// A diffusion smoother that the caller can drive step by step: explicit Jacobi
/// iterations (plain diffusion, Taubin, HC, with an optional volume rescale) or
/// implicit backward-Euler steps, chosen by [`SmoothConfig::method`].
///
/// An explicit [`step`](Self::step) is one Jacobi iteration: every new position is
/// computed from the previous iterate, `x_i ← x_i + λ L x_i` (see
/// [`Laplacian::laplacian_at`] for the exact arithmetic), so results do not depend on
/// vertex order or thread count. An implicit step solves `(M − λ L) x' = M x` (see
/// [`Method::Implicit`]).
///
/// Large meshes (and, for [`Summation::Scatter`](crate::Summation::Scatter), meshes in a
/// poor vertex order) are renumbered internally for memory locality (see
/// [`Reorder`](crate::Reorder)); everything the smoother returns is in the caller's
/// numbering and bit-identical to a run without reordering (with
/// [`Summation::Scatter`](crate::Summation::Scatter), identical to rounding).
///
/// [`Smoother::new`] borrows the mesh and copies the positions (and, when it renumbers,
/// copies the mesh too); [`Smoother::from_owned`] takes both by value, renumbers the
/// mesh in place and gives it back from [`Smoother::run_owned`]: the way to smooth a
/// large mesh with one copy of its connectivity and two position buffers in memory.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{ImplicitSolver, Method, SmoothConfig, Smoother, WeightUpdate};
/// use beltrami_weights::Cotangent;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh().unwrap();
/// let mut smoother = Smoother::new(&mesh, &sphere.positions, &Cotangent, SmoothConfig::new(0.5, 3))?;
/// let stats = smoother.step()?;
/// assert!(stats.max_displacement > 0.0);
///
/// // Implicit steps: the operator is frozen, so the second step reuses the factor.
/// let config = SmoothConfig::new(10.0, 3)
///     .update(WeightUpdate::Once)
///     .method(Method::implicit(ImplicitSolver::Cholesky));
/// let mut smoother = Smoother::new(&mesh, &sphere.positions, &Cotangent, config)?;
/// assert!(smoother.step()?.solve.unwrap().factorized);
/// assert!(!smoother.step()?.solve.unwrap().factorized);
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
#[derive(Debug)]
pub struct Smoother<'a> {
    engine: Engine<'a>,
    /// The buffer for the observer's positions in the caller's numbering (reordering
    /// only; allocated on the first call of [`IterationView::positions`], then reused).
    view: Vec<DVec3>,
}

/// The two ways a step moves the vertices.
#[derive(Debug)]
enum Engine<'a> {
    Explicit(Box<Explicit<'a>>),
    Implicit(Box<Implicit<'a>>),
}

/// The connectivity a smoother made by [`Smoother::from_owned`] hands back from
/// [`Smoother::run_owned_faces`], in the caller's numbering.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum OwnedFaces {
    /// The half-edge mesh as given (a renumbered mesh numbered back in place).
    Mesh(HalfedgeMesh),
    /// The triangles of a run that went on without the mesh: three vertex indices per
    /// face, in the mesh's face order, each face from its first vertex — the indices
    /// of [`HalfedgeMesh::to_polygons`] (12 bytes per face).
    Triangles(Vec<u32>),
}

impl OwnedFaces {
    /// The faces as a [`PolygonList`]: [`HalfedgeMesh::to_polygons`] of the mesh, or
    /// the triangles with their offsets; the same list either way.
    #[must_use]
    pub fn to_polygons(&self) -> PolygonList {
        match self {
            Self::Mesh(mesh) => mesh.to_polygons(),
            Self::Triangles(t) => t.chunks_exact(3).collect(),
        }
    }

    /// The half-edge mesh: as given, or rebuilt from the triangles with
    /// [`HalfedgeMesh::from_polygons`] on `n_vertices` vertices.
    ///
    /// # Errors
    /// Those of [`HalfedgeMesh::from_polygons`] (none for the triangles of a mesh on
    /// `n_vertices` vertices).
    pub fn into_mesh(self, n_vertices: usize) -> Result<HalfedgeMesh, TopologyError> {
        match self {
            Self::Mesh(mesh) => Ok(mesh),
            Self::Triangles(t) => HalfedgeMesh::from_polygons(n_vertices, t.chunks_exact(3)),
        }
    }
}

/// What an engine hands back at the end of a run.
pub(crate) struct Finished {
    /// The positions, in the caller's numbering.
    pub(crate) positions: Vec<DVec3>,
    /// The mesh in the caller's numbering, when the caller gave it by value.
    pub(crate) mesh: Option<HalfedgeMesh>,
    /// The configuration, with the step and count chosen for a duration.
    pub(crate) config: SmoothConfig,
    pub(crate) weight_time: Duration,
    pub(crate) update_time: Duration,
    pub(crate) solver: Option<SolverReport>,
    /// Iterations swept element by element.
    pub(crate) scattered_sweeps: usize,
}

impl<'a> Smoother<'a> {
    /// Prepares a run on `positions` (copied): computes the first weights and, for an
    /// implicit run, assembles the matrix and analyses it (Cholesky; the numeric
    /// factorisation happens in the first [`step`](Self::step)).
    ///
    /// # Errors
    /// [`SmoothError::InvalidLambda`] for λ outside (0, 1] (explicit, weight sum) or
    /// not positive and finite (area normalisation, implicit);
    /// [`SmoothError::CurveNeedsWeightSum`]; [`SmoothError::CurveNotImplicit`];
    /// [`SmoothError::VolumeNotImplicit`]; [`SmoothError::InvalidTaubin`];
    /// [`SmoothError::InvalidHc`]; [`SmoothError::InvalidSolverSettings`];
    /// [`SmoothError::VolumeNeedsClosedMesh`]; [`SmoothError::VolumeWithPinned`];
    /// [`SmoothError::DegenerateVolume`]; [`SmoothError::InvalidDuration`];
    /// [`SmoothError::InvalidUntilChange`]; [`SmoothError::PinnedOutOfRange`];
    /// [`SmoothError::NonFiniteInput`]; [`SmoothError::Weights`] when the positions do
    /// not match the mesh or the scheme gives a non-finite weight;
    /// [`SmoothError::ImplicitScale`] for an implicit run on a mesh whose largest
    /// coordinate lies outside [`IMPLICIT_COORDINATES`](crate::IMPLICIT_COORDINATES);
    /// [`SmoothError::Factorization`] when the implicit analysis cannot be done (out
    /// of memory).
    pub fn new(
        mesh: &'a HalfedgeMesh,
        positions: &[DVec3],
        scheme: &'a dyn WeightScheme,
        config: SmoothConfig,
    ) -> Result<Self, SmoothError> {
        validate(&config, mesh, positions)?;
        Self::with_engine(
            Cow::Borrowed(mesh),
            Cow::Borrowed(positions),
            scheme,
            config,
        )
    }

    /// [`new`](Self::new) for a mesh and positions given by value: the smoother keeps
    /// them instead of copying them. When it renumbers the vertices for locality (see
    /// [`Reorder`](crate::Reorder)) it renumbers this mesh in place instead of building
    /// a renumbered copy, and replaces the positions by their renumbered copy: a large
    /// run holds one half-edge mesh and two position buffers, where with
    /// [`new`](Self::new) the caller and the smoother together hold two meshes and
    /// three position buffers. [`run_owned`](Self::run_owned) hands the mesh back, in
    /// the caller's numbering.
    ///
    /// Every result is the same bits as with [`new`](Self::new).
    ///
    /// # Errors
    /// As [`new`](Self::new); the mesh and the positions are then dropped.
    ///
    /// # Examples
    /// ```
    /// use std::ops::ControlFlow;
    /// use beltrami_halfedge::primitives;
    /// use beltrami_smooth::{smooth, Reorder, SmoothConfig, Smoother};
    /// use beltrami_weights::Cotangent;
    ///
    /// let sphere = primitives::icosphere(3);
    /// let mesh = sphere.mesh().unwrap();
    /// // Renumbered for locality (by default from 50 000 vertices on): in place here.
    /// let config = SmoothConfig::new(0.5, 4).reorder(Reorder::Always);
    /// let borrowed = smooth(&mesh, &sphere.positions, &Cotangent, config.clone())?;
    ///
    /// let smoother =
    ///     Smoother::from_owned(mesh.clone(), sphere.positions.clone(), &Cotangent, config)?;
    /// let (owned, given_back) = smoother.run_owned(|_| ControlFlow::Continue(()))?;
    /// assert_eq!(owned.positions, borrowed.positions);
    /// assert_eq!(given_back, Some(mesh));
    /// # Ok::<(), beltrami_smooth::SmoothError>(())
    /// ```
    pub fn from_owned(
        mesh: HalfedgeMesh,
        positions: Vec<DVec3>,
        scheme: &'a dyn WeightScheme,
        config: SmoothConfig,
    ) -> Result<Self, SmoothError> {
        validate(&config, &mesh, &positions)?;
        Self::with_engine(Cow::Owned(mesh), Cow::Owned(positions), scheme, config)
    }

    /// The engine `config.method` asks for, on a validated `config`.
    fn with_engine(
        mesh: Cow<'a, HalfedgeMesh>,
        positions: Cow<'_, [DVec3]>,
        scheme: &'a dyn WeightScheme,
        config: SmoothConfig,
    ) -> Result<Self, SmoothError> {
        let engine = match config.method {
            Method::Implicit { .. } => {
                Engine::Implicit(Box::new(Implicit::new(mesh, positions, scheme, config)?))
            }
            _ => Engine::Explicit(Box::new(Explicit::new(mesh, positions, scheme, config)?)),
        };
        Ok(Self {
            engine,
            view: Vec::new(),
        })
    }

    /// Does one iteration and returns its statistics.
    ///
    /// # Errors
    /// [`SmoothError::Weights`] when recomputed weights are not finite;
    /// [`SmoothError::NonFinite`] when a position would become NaN or infinite; for an
    /// implicit step also [`SmoothError::NotPositiveDefinite`] (negative weights that
    /// are not an energy, see [`Method::Implicit`]), [`SmoothError::NotConverged`]
    /// (conjugate gradient) and [`SmoothError::Factorization`]. The positions are then
    /// left as they were before the step.
    pub fn step(&mut self) -> Result<StepStats, SmoothError> {
        self.iterate(Want::Full)
    }

    /// Does one iteration like [`step`](Self::step) but computes no displacement
    /// statistics where that saves work (a square root per vertex and, with
    /// reordering, a gather): the fast way to drive explicit iterations. The positions
    /// are the same bits as with `step`.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn advance(&mut self) -> Result<(), SmoothError> {
        self.iterate(Want::Nothing).map(|_| ())
    }

    fn iterate(&mut self, want: Want) -> Result<StepStats, SmoothError> {
        match &mut self.engine {
            Engine::Explicit(e) => e.iterate(want),
            Engine::Implicit(e) => e.step(),
        }
    }

    /// Runs the configured number of iterations, calling `observer` after each one; the
    /// observer stops the run early by returning `ControlFlow::Break(())`.
    ///
    /// With [`Statistics::EveryIteration`] (the default) every iteration's statistics
    /// are computed and kept in the report; with [`Statistics::OnDemand`] only when the
    /// observer calls [`IterationView::stats`] (and the largest displacement when
    /// [`SmoothConfig::until_change`] needs it). An implicit step computes its
    /// statistics anyway (they cost little beside a solve); the report keeps them as
    /// the setting says.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn run<F>(self, observer: F) -> Result<Smoothed, SmoothError>
    where
        F: FnMut(&IterationView<'_>) -> ControlFlow<()>,
    {
        self.run_owned(observer).map(|(smoothed, _)| smoothed)
    }

    /// [`run`](Self::run), handing back the mesh of a smoother made by
    /// [`from_owned`](Self::from_owned), in the caller's numbering (the mesh as given:
    /// a renumbered mesh is numbered back in place); `None` for a smoother that
    /// borrows its mesh.
    ///
    /// A run that went on without the mesh ([`OwnedFaces::Triangles`], see
    /// [`run_owned_faces`](Self::run_owned_faces)) rebuilds it from its triangles with
    /// [`HalfedgeMesh::from_polygons`]: the mesh as given when it was built from its
    /// faces that way (as every mesh read from a file is), the same faces and vertices
    /// otherwise.
    ///
    /// # Errors
    /// As [`step`](Self::step); the mesh is then dropped.
    pub fn run_owned<F>(self, observer: F) -> Result<(Smoothed, Option<HalfedgeMesh>), SmoothError>
    where
        F: FnMut(&IterationView<'_>) -> ControlFlow<()>,
    {
        let (smoothed, faces) = self.run_owned_faces(observer)?;
        let n = smoothed.positions.len();
        let mesh = faces
            .map(|faces| faces.into_mesh(n))
            .transpose()
            .map_err(|e| SmoothError::from(beltrami_weights::WeightError::from(e)))?;
        Ok((smoothed, mesh))
    }

    /// [`run_owned`](Self::run_owned) without rebuilding a mesh the run did not keep:
    /// the connectivity of a smoother made by [`from_owned`](Self::from_owned) as the
    /// run held it at the end — the mesh as given ([`OwnedFaces::Mesh`]), or, when the
    /// explicit engine went on without it, its triangles ([`OwnedFaces::Triangles`]);
    /// `None` for a smoother that borrows its mesh. For a caller that only writes the
    /// faces out, so that no half-edge mesh is held after the run.
    ///
    /// The explicit engine goes on without the mesh once the operator is built when
    /// the mesh was given by value, every face is a triangle, no two vertices are
    /// joined by more than one edge, and the scheme is a built-in one
    /// ([`Uniform`](beltrami_weights::Uniform),
    /// [`InverseDistance`](beltrami_weights::InverseDistance),
    /// [`Cotangent`](beltrami_weights::Cotangent)): it keeps the triangle list (24
    /// bytes per vertex) instead of the mesh (104), with the same results bit for bit.
    /// Other runs (polygon faces, multiple edges, a scheme of your own, the implicit
    /// method) keep the mesh.
    ///
    /// # Errors
    /// As [`step`](Self::step); the mesh or faces are then dropped.
    ///
    /// # Examples
    /// ```
    /// use std::ops::ControlFlow;
    /// use beltrami_halfedge::primitives;
    /// use beltrami_smooth::{OwnedFaces, SmoothConfig, Smoother};
    /// use beltrami_weights::Cotangent;
    ///
    /// let sphere = primitives::icosphere(2);
    /// let mesh = sphere.mesh().unwrap();
    /// let polygons = mesh.to_polygons();
    /// let smoother =
    ///     Smoother::from_owned(mesh, sphere.positions.clone(), &Cotangent, SmoothConfig::new(0.5, 3))?;
    /// let (smoothed, faces) = smoother.run_owned_faces(|_| ControlFlow::Continue(()))?;
    /// assert_eq!(smoothed.positions.len(), sphere.positions.len());
    /// assert_eq!(faces.unwrap().to_polygons(), polygons);
    /// # Ok::<(), beltrami_smooth::SmoothError>(())
    /// ```
    pub fn run_owned_faces<F>(
        mut self,
        mut observer: F,
    ) -> Result<(Smoothed, Option<OwnedFaces>), SmoothError>
    where
        F: FnMut(&IterationView<'_>) -> ControlFlow<()>,
    {
        let config = self.config();
        let every = config.statistics == Statistics::EveryIteration;
        let want = if every {
            Want::Full
        } else if config.until_change.is_some() {
            Want::Max
        } else {
            Want::Nothing
        };
        let (planned, until_change) = (config.iterations, config.until_change);
        let implicit = matches!(self.engine, Engine::Implicit(_));
        let mut steps = Vec::with_capacity(if every { planned } else { 0 });
        let mut max_stuck = 0;
        let mut stop = StopReason::Completed;
        while self.iteration() < planned {
            let stats = self.iterate(want)?;
            if every {
                steps.push(stats);
            }
            max_stuck = max_stuck.max(stats.stuck_vertices);
            let spare = std::mem::take(&mut self.view);
            let (after, before, perm) = match &self.engine {
                Engine::Explicit(e) => (e.internal_positions(), e.before(), e.permutation()),
                Engine::Implicit(e) => (e.positions(), e.before(), None),
            };
            let known = (every || implicit).then_some(stats);
            let it = IterationView::new(
                self.iteration(),
                after,
                before,
                perm,
                spare,
                known,
                stats.stuck_vertices,
            );
            let flow = observer(&it);
            self.view = it.into_buffer();
            if flow.is_break() {
                stop = StopReason::Observer;
                break;
            }
            if until_change.is_some_and(|eps| stats.max_displacement <= eps) {
                stop = StopReason::Converged;
                break;
            }
        }
        let iterations = self.iteration();
        let scheme = self.scheme_name();
        let (finished, triangles) = match self.engine {
            Engine::Explicit(e) => e.finish(),
            Engine::Implicit(e) => (e.finish(), None),
        };
        let report = SmoothReport {
            scheme,
            config: finished.config,
            iterations,
            stop,
            steps,
            max_stuck_vertices: max_stuck,
            weight_time: finished.weight_time,
            update_time: finished.update_time,
            solver: finished.solver,
            scattered_sweeps: finished.scattered_sweeps,
        };
        let smoothed = Smoothed {
            positions: finished.positions,
            report,
        };
        let faces = match (finished.mesh, triangles) {
            (Some(mesh), _) => Some(OwnedFaces::Mesh(mesh)),
            (None, Some(triangles)) => Some(OwnedFaces::Triangles(triangles)),
            (None, None) => None,
        };
        Ok((smoothed, faces))
    }

    fn scheme_name(&self) -> String {
        match &self.engine {
            Engine::Explicit(e) => e.scheme_name(),
            Engine::Implicit(e) => e.scheme_name(),
        }
    }

    /// The largest stable explicit step of an area-normalised operator on the current
    /// positions, in length² (a time per iteration): `1 / max_i (W_i / A_i)` over the
    /// moving vertices, with `W_i` the weight sum and `A_i` the vertex area. The step
    /// `x + λ M⁻¹ L x` has the eigenvalues of `λ M⁻¹ L` in `[−2 λ r, 0]` by
    /// Gershgorin's theorem (non-negative weights), so `λ ≤ 1 / r` keeps every
    /// frequency from growing. `None` with weight-sum normalisation (whose stable range
    /// is λ ≤ 1), for an implicit run (stable at any step) or when no vertex moves.
    /// Weights recomputed every iteration move the limit a little as the mesh changes.
    ///
    /// A step from [`DiffusionTime`] is chosen below half this limit; a step given
    /// directly is the caller's to check, e.g. to fail with
    /// [`SmoothError::UnstableStep`].
    #[must_use]
    pub fn stable_step_limit(&self) -> Option<f64> {
        match &self.engine {
            Engine::Explicit(e) => e.stable_step_limit(),
            Engine::Implicit(_) => None,
        }
    }

    /// Refuses an explicit area-normalised run whose steps, given directly, would let the
    /// highest frequencies grow: λ above [`stable_step_limit`](Self::stable_step_limit)
    /// `L` ([`SmoothError::UnstableStep`]), or a Taubin pair with `(1 − 2λ/L)(1 − 2μ/L) ≤
    /// −1` ([`SmoothError::InvalidTaubin`]; the test weight-sum pairs pass at
    /// construction, with `L = 1`). `Ok` with weight-sum rows, for a run planned for a
    /// [`duration`](SmoothConfig::duration) (which chooses its own stable step), an
    /// implicit run, or when no vertex moves.
    ///
    /// # Errors
    /// As above.
    pub fn check_stable_steps(&self) -> Result<(), SmoothError> {
        let config = self.config();
        let Some(limit) = self.stable_step_limit() else {
            return Ok(());
        };
        if config.duration.is_some() {
            return Ok(());
        }
        let lambda = config.lambda;
        if lambda > limit {
            return Err(SmoothError::UnstableStep {
                lambda,
                max_stable: limit,
            });
        }
        if let Method::Taubin { mu } = config.method
            && (1.0 - 2.0 * lambda / limit) * (1.0 - 2.0 * mu / limit) <= -1.0
        {
            return Err(SmoothError::InvalidTaubin {
                lambda,
                mu,
                reason: "the highest frequency would grow: with area normalisation (1 - 2 lambda/L)(1 - 2 mu/L) must exceed -1, L the largest stable explicit step",
            });
        }
        Ok(())
    }

    /// The configuration of the run; with a [`duration`](SmoothConfig::duration),
    /// `lambda` and `iterations` are the step and count the smoother chose.
    #[must_use]
    pub fn config(&self) -> &SmoothConfig {
        match &self.engine {
            Engine::Explicit(e) => e.config(),
            Engine::Implicit(e) => e.config(),
        }
    }

    /// The current positions, in the caller's numbering: borrowed when the smoother
    /// works in that numbering, a restored copy (O(V) time and memory) when it reorders
    /// (see [`Reorder`](crate::Reorder) and [`permutation`](Self::permutation)).
    #[must_use]
    pub fn positions(&self) -> Cow<'_, [DVec3]> {
        match &self.engine {
            Engine::Explicit(e) => e.positions(),
            Engine::Implicit(e) => Cow::Borrowed(e.positions()),
        }
    }

    /// The internal vertex numbering, when the smoother reorders: internal vertex `i`
    /// is the caller's vertex `new_to_old()[i]`. `None` when it works in the caller's
    /// numbering (always for an implicit run).
    #[must_use]
    pub fn permutation(&self) -> Option<&VertexPermutation> {
        match &self.engine {
            Engine::Explicit(e) => e.permutation(),
            Engine::Implicit(_) => None,
        }
    }

    /// The number of iterations done.
    #[must_use]
    pub fn iteration(&self) -> usize {
        match &self.engine {
            Engine::Explicit(e) => e.iteration(),
            Engine::Implicit(e) => e.iteration(),
        }
    }

    /// The operator as last assembled, in the internal numbering: its row `i` and its
    /// neighbour ids are internal vertex ids (the caller's when
    /// [`permutation`](Self::permutation) is `None`; map them with it otherwise). An
    /// implicit run symmetrises it when it assembles its matrix.
    #[must_use]
    pub fn laplacian(&self) -> &Laplacian {
        match &self.engine {
            Engine::Explicit(e) => e.laplacian(),
            Engine::Implicit(e) => e.laplacian(),
        }
    }
}

/// Checks every setting of `config` against the mesh and the positions, before any
/// work.
fn validate(
    config: &SmoothConfig,
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
) -> Result<(), SmoothError> {
    let weight_sum = config.laplacian.normalization == Normalization::WeightSum;
    let lambda = config.lambda;
    let (valid, range) = match config.method {
        Method::Implicit { .. } => (
            lambda > 0.0 && lambda.is_finite(),
            "positive and finite for an implicit step",
        ),
        _ if weight_sum => (
            lambda > 0.0 && lambda <= 1.0,
            "in (0, 1] with weight-sum normalisation",
        ),
        _ => (lambda > 0.0 && lambda.is_finite(), "positive and finite"),
    };
    if !valid {
        return Err(SmoothError::InvalidLambda { lambda, range });
    }
    if let Method::Implicit { .. } = config.method {
        if config.boundary == Boundary::Curve {
            return Err(SmoothError::CurveNotImplicit);
        }
        if config.preserve_volume {
            return Err(SmoothError::VolumeNotImplicit);
        }
    } else if config.boundary == Boundary::Curve && !weight_sum {
        return Err(SmoothError::CurveNeedsWeightSum);
    }
    validate_method(config, mesh, weight_sum)?;
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
    Ok(())
}

/// Checks the method, volume, duration and convergence settings of `config`.
fn validate_method(
    config: &SmoothConfig,
    mesh: &HalfedgeMesh,
    weight_sum: bool,
) -> Result<(), SmoothError> {
    let lambda = config.lambda;
    match config.method {
        Method::Laplacian => {}
        Method::Implicit { solver } => {
            if let ImplicitSolver::ConjugateGradient {
                tolerance,
                max_iterations,
            } = solver
                && (!(tolerance > 0.0 && tolerance < 1.0) || max_iterations == 0)
            {
                return Err(SmoothError::InvalidSolverSettings {
                    tolerance,
                    max_iterations,
                });
            }
        }
        Method::Taubin { mu } => {
            let invalid = |reason| SmoothError::InvalidTaubin { lambda, mu, reason };
            if !(mu.is_finite() && mu < -lambda) {
                return Err(invalid(
                    "the pass band 1/lambda + 1/mu must be positive, i.e. mu < -lambda",
                ));
            }
            if weight_sum && (1.0 - 2.0 * lambda) * (1.0 - 2.0 * mu) <= -1.0 {
                return Err(invalid(
                    "the highest frequency would grow: (1 - 2 lambda)(1 - 2 mu) must exceed -1",
                ));
            }
        }
        Method::Hc { alpha, beta } => {
            if !((0.0..=1.0).contains(&alpha) && (0.0..=1.0).contains(&beta)) {
                return Err(SmoothError::InvalidHc { alpha, beta });
            }
        }
    }
    if config.preserve_volume {
        if !mesh.is_closed() {
            return Err(SmoothError::VolumeNeedsClosedMesh {
                boundary_loops: mesh.boundary_loops().count(),
            });
        }
        if !config.pinned.is_empty() {
            return Err(SmoothError::VolumeWithPinned);
        }
    }
    if let Some(duration) = config.duration {
        let t = duration.time();
        // A cut-off's time is its square times a constant: a negative cut-off would pass
        // as its absolute value.
        let sign_ok = match duration {
            DiffusionTime::Time(_) => true,
            DiffusionTime::Cutoff(lc) => lc >= 0.0,
        };
        if !(sign_ok && t >= 0.0 && t.is_finite()) {
            return Err(SmoothError::InvalidDuration {
                reason: match duration {
                    DiffusionTime::Time(_) => {
                        format!("the time must be finite and >= 0, got {}", Short(t))
                    }
                    DiffusionTime::Cutoff(lc) if lc.is_nan() || lc < 0.0 => {
                        format!("the cut-off must be finite and >= 0, got {}", Short(lc))
                    }
                    DiffusionTime::Cutoff(lc) => format!(
                        "the cut-off must be finite and >= 0 and give a finite time, got {} (time {})",
                        Short(lc),
                        Short(t)
                    ),
                },
            });
        }
        if !matches!(config.method, Method::Laplacian | Method::Implicit { .. }) {
            return Err(SmoothError::InvalidDuration {
                reason: format!(
                    "a diffusion time applies to plain Laplacian diffusion (explicit or implicit) only, not to method '{}'",
                    config.method.name()
                ),
            });
        }
    }
    if let Some(eps) = config.until_change
        && !(eps > 0.0 && eps.is_finite())
    {
        return Err(SmoothError::InvalidUntilChange { value: eps });
    }
    Ok(())
}

/// Smooths `positions` with `scheme` as `config` says, in one call.
///
/// # Errors
/// As [`Smoother::new`] and [`Smoother::step`].
///
/// Implicit steps go through the same call:
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{smooth, ImplicitSolver, Method, SmoothConfig};
/// use beltrami_weights::Uniform;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh().unwrap();
/// // A step 100 times beyond what the explicit weight-sum step allows.
/// let config = SmoothConfig::new(100.0, 2).method(Method::implicit(ImplicitSolver::Cholesky));
/// let out = smooth(&mesh, &sphere.positions, &Uniform, config)?;
/// assert!(out.positions.iter().all(|p| p.is_finite() && p.length() < 1.0));
/// // Uniform weights never change: one factorisation serves both steps.
/// assert_eq!(out.report.solver.unwrap().numeric_factorizations, 1);
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{smooth, SmoothConfig};
/// use beltrami_weights::Uniform;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh().unwrap();
/// let out = smooth(&mesh, &sphere.positions, &Uniform, SmoothConfig::new(0.8, 10))?;
/// // Diffusion shrinks a sphere.
/// assert!(out.positions.iter().all(|p| p.length() < 1.0));
/// assert_eq!(out.report.iterations, 10);
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
pub fn smooth(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn WeightScheme,
    config: SmoothConfig,
) -> Result<Smoothed, SmoothError> {
    Smoother::new(mesh, positions, scheme, config)?.run(|_| ControlFlow::Continue(()))
}
