//! The explicit Jacobi smoother: `step()`, `run()` with an observer, and `smooth()`.

use std::borrow::Cow;
use std::cell::{Cell, OnceCell};
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::reorder::{VertexPermutation, rcm_order};
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::{Laplacian, Normalization, RowSweep, WeightContext, WeightScheme};
use rayon::prelude::*;

use crate::config::{Boundary, DiffusionTime, Method, SmoothConfig, Statistics, WeightUpdate};
use crate::error::{Short, SmoothError};

/// Vertices per parallel work unit. Fixed, so that per-chunk partial sums (and hence
/// the reported statistics) do not depend on the number of threads.
const CHUNK: usize = 4096;

/// How one vertex moves (one byte per vertex, so the sweep streams little).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Never moves (fixed boundary, pinned, isolated).
    Still,
    /// Moves with its Laplacian row.
    Row,
    /// Moves along the boundary polyline towards its two boundary neighbours (see
    /// [`CurveRow`]).
    Curve,
}

/// A vertex that moves along the boundary polyline towards its two boundary
/// neighbours `a` and `b`; the weights are refreshed with the Laplacian.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CurveRow {
    v: u32,
    a: u32,
    b: u32,
    wa: f64,
    wb: f64,
}

/// Statistics of one iteration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// The largest distance a vertex moved, in the positions' unit.
    pub max_displacement: f64,
    /// The mean distance over all vertices (still ones count as 0).
    pub mean_displacement: f64,
    /// Vertices that should have moved but could not, because their weights summed to
    /// ≤ 0 or their area was 0 (see [`Laplacian::stuck_rows`]).
    pub stuck_vertices: usize,
}

/// What the [`ImplicitSmoother`](crate::ImplicitSmoother)'s observer sees after each
/// step.
#[derive(Debug)]
pub struct Iteration<'a> {
    /// The number of iterations done so far (1 after the first).
    pub index: usize,
    /// The positions after this iteration.
    pub positions: &'a [DVec3],
    /// This iteration's statistics.
    pub stats: StepStats,
}

/// What the explicit [`Smoother::run`]'s observer sees after each iteration.
///
/// The positions and the statistics are computed when first asked for (then kept for
/// this iteration): an observer that asks for neither costs nothing, and with
/// [`Reorder`](crate::Reorder) the positions are gathered into the caller's numbering
/// only when [`positions`](Self::positions) is called.
pub struct IterationView<'a> {
    /// The number of iterations done so far (1 after the first).
    pub index: usize,
    /// The positions after the iteration, internal numbering.
    after: &'a [DVec3],
    /// The positions before the iteration, internal numbering.
    before: &'a [DVec3],
    perm: Option<&'a VertexPermutation>,
    /// The buffer the positions are restored into (reordering only).
    spare: Cell<Vec<DVec3>>,
    restored: OnceCell<Vec<DVec3>>,
    stats: OnceCell<StepStats>,
    stuck: usize,
}

impl std::fmt::Debug for IterationView<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("IterationView")
            .field("index", &self.index)
            .field("stats", &self.stats.get())
            .finish_non_exhaustive()
    }
}

impl IterationView<'_> {
    /// The positions after this iteration, one per vertex in the caller's numbering.
    /// With reordering the first call gathers them (O(V), in parallel, into a buffer the
    /// smoother reuses); later calls return the same slice.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        match self.perm {
            None => self.after,
            Some(perm) => self.restored.get_or_init(|| {
                let mut out = self.spare.take();
                // Allocated on the first call of the run, reused after.
                out.resize(self.after.len(), DVec3::ZERO);
                restore_par(perm, self.after, &mut out);
                out
            }),
        }
    }

    /// This iteration's statistics: computed during the sweep with
    /// [`Statistics::EveryIteration`], otherwise on the first call (O(V), in parallel,
    /// from the positions before and after the iteration; the same bits either way).
    #[must_use]
    pub fn stats(&self) -> StepStats {
        *self
            .stats
            .get_or_init(|| displacement_stats(self.perm, self.before, self.after, self.stuck))
    }

    /// The restore buffer, for the next iteration.
    fn into_buffer(self) -> Vec<DVec3> {
        self.restored
            .into_inner()
            .unwrap_or_else(|| self.spare.into_inner())
    }
}

/// Why a run stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StopReason {
    /// All requested iterations were done.
    Completed,
    /// The observer returned `ControlFlow::Break`.
    Observer,
    /// An iteration moved no vertex farther than
    /// [`SmoothConfig::until_change`](crate::SmoothConfig::until_change).
    Converged,
}

impl StopReason {
    /// A short name: `completed`, `observer` or `converged`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Completed => "completed",
            Self::Observer => "observer",
            Self::Converged => "converged",
        }
    }
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothReport {
    /// The scheme's name.
    pub scheme: String,
    /// The configuration used. With a [`duration`](SmoothConfig::duration), `lambda` and
    /// `iterations` are the step and count the smoother chose.
    pub config: SmoothConfig,
    /// Iterations done.
    pub iterations: usize,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Per-iteration statistics, with [`Statistics::EveryIteration`] (the default); empty
    /// with [`Statistics::OnDemand`].
    pub steps: Vec<StepStats>,
    /// The largest number of stuck vertices in any iteration.
    pub max_stuck_vertices: usize,
    /// Wall time spent computing weights (including the first computation).
    pub weight_time: Duration,
    /// Wall time spent updating positions.
    pub update_time: Duration,
}

/// Smoothed positions and the report of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Smoothed {
    /// The positions after the run, one per vertex, in the input order.
    pub positions: Vec<DVec3>,
    /// What the run did.
    pub report: SmoothReport,
}

/// An explicit diffusion smoother that the caller can drive step by step.
///
/// Each [`step`](Self::step) is one Jacobi iteration: every new position is computed
/// from the previous iterate, `x_i ← x_i + λ L x_i` (see
/// [`Laplacian::laplacian_at`] for the exact arithmetic), so results do not depend on
/// vertex order or thread count.
///
/// Large meshes are renumbered internally for memory locality (see
/// [`Reorder`](crate::Reorder)); everything the smoother returns is in the caller's
/// numbering and bit-identical to a run without reordering.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{SmoothConfig, Smoother};
/// use beltrami_weights::Cotangent;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh().unwrap();
/// let mut smoother = Smoother::new(&mesh, &sphere.positions, &Cotangent, SmoothConfig::new(0.5, 3))?;
/// let stats = smoother.step()?;
/// assert!(stats.max_displacement > 0.0);
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
pub struct Smoother<'a> {
    /// The mesh, renumbered when `perm` is set.
    mesh: Cow<'a, HalfedgeMesh>,
    /// The internal numbering (new = internal, old = the caller's), when reordering.
    perm: Option<VertexPermutation>,
    /// Per-vertex displacements of the last sweep, internal numbering (reordering with
    /// full statistics only, allocated when first needed; summed in the caller's order
    /// for the mean).
    disp: Vec<f64>,
    /// The buffer for the observer's positions in the caller's numbering (reordering
    /// only; allocated on the first call of [`IterationView::positions`], then reused).
    view: Vec<DVec3>,
    /// Per-chunk results of a sweep, reused (no allocation per iteration).
    partials: Vec<Partial>,
    /// Per-chunk displacement sums in the caller's order, reused (reordering only).
    mean_partials: Vec<f64>,
    scheme: &'a dyn WeightScheme,
    config: SmoothConfig,
    laplacian: Laplacian,
    roles: Vec<Role>,
    /// The vertices whose role is not [`Role::Row`], in increasing order: a sweep moves
    /// every row alike, then puts these right.
    exceptions: Vec<u32>,
    curve: Vec<CurveRow>,
    positions: Vec<DVec3>,
    next: Vec<DVec3>,
    /// The positions at the start of a compound step (Taubin, HC, volume rescale);
    /// empty for plain diffusion.
    start: Vec<DVec3>,
    /// The input positions (HC only; empty otherwise).
    original: Vec<DVec3>,
    /// HC's per-vertex push-back `b`, reused every iteration (HC only; empty otherwise).
    push_back: Vec<DVec3>,
    /// The input volume (volume preservation only).
    volume: f64,
    iteration: usize,
    weights_fresh: bool,
    weight_time: Duration,
    update_time: Duration,
}

impl std::fmt::Debug for Smoother<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Smoother")
            .field("scheme", &self.scheme.name())
            .field("config", &self.config)
            .field("iteration", &self.iteration)
            .finish_non_exhaustive()
    }
}

impl<'a> Smoother<'a> {
    /// Prepares a run on `positions` (copied) and computes the first weights.
    ///
    /// # Errors
    /// [`SmoothError::InvalidLambda`] for λ outside (0, 1] (weight sum) or not positive
    /// and finite (area); [`SmoothError::CurveNeedsWeightSum`];
    /// [`SmoothError::PinnedOutOfRange`]; [`SmoothError::NonFiniteInput`];
    /// [`SmoothError::Weights`] when the positions do not match the mesh or the scheme
    /// gives a non-finite weight.
    ///
    /// # Panics
    /// Never: curve-boundary rows are made for boundary vertices only, which have an outgoing halfedge.
    pub fn new(
        mesh: &'a HalfedgeMesh,
        positions: &[DVec3],
        scheme: &'a dyn WeightScheme,
        config: SmoothConfig,
    ) -> Result<Self, SmoothError> {
        let weight_sum = config.laplacian.normalization == Normalization::WeightSum;
        let lambda = config.lambda;
        let (valid, range) = if weight_sum {
            (
                lambda > 0.0 && lambda <= 1.0,
                "in (0, 1] with weight-sum normalisation",
            )
        } else {
            (lambda > 0.0 && lambda.is_finite(), "positive and finite")
        };
        if !valid {
            return Err(SmoothError::InvalidLambda { lambda, range });
        }
        if config.boundary == Boundary::Curve && !weight_sum {
            return Err(SmoothError::CurveNeedsWeightSum);
        }
        validate_method(&config, mesh, weight_sum)?;
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
        // With a mismatched position count the operator reports the error unreordered.
        let perm = (config.reorder.applies(mesh.n_vertices())
            && positions.len() == mesh.n_vertices())
        .then(|| rcm_order(mesh));
        let (caller_mesh, caller_positions) = (mesh, positions);
        let (mesh, positions): (Cow<'a, HalfedgeMesh>, Cow<'_, [DVec3]>) = match &perm {
            Some(p) => (
                Cow::Owned(p.apply_to_mesh(mesh)),
                Cow::Owned(permute_par(p, positions)),
            ),
            None => (Cow::Borrowed(mesh), Cow::Borrowed(positions)),
        };
        let to_caller = |e: SmoothError| match &perm {
            Some(p) => error_to_caller(e, p),
            None => e,
        };
        let laplacian = Laplacian::new(&mesh, &positions, scheme, config.laplacian)
            .map_err(|e| to_caller(e.into()))?;
        let mut roles: Vec<Role> = mesh
            .vertices()
            .map(|v| {
                if mesh.is_isolated(v) {
                    return Role::Still;
                }
                match (mesh.is_boundary_vertex(v), config.boundary) {
                    (false, _) | (true, Boundary::Free) => Role::Row,
                    (true, Boundary::Fixed) => Role::Still,
                    (true, Boundary::Curve) => Role::Curve,
                }
            })
            .collect();
        for &v in &config.pinned {
            let v = perm.as_ref().map_or(v, |p| p.to_new(v));
            roles[v.index()] = Role::Still;
        }
        // In increasing vertex order, so that a sweep finds them with a cursor.
        let curve: Vec<CurveRow> = mesh
            .vertices()
            .filter(|v| roles[v.index()] == Role::Curve)
            .map(|v| {
                // Outgoing boundary halfedge v -> b; the boundary halfedge before it
                // comes from a.
                let out = mesh.outgoing_halfedge(v).expect("not isolated");
                CurveRow {
                    v: v.raw(),
                    a: mesh.from_vertex(mesh.prev(out)).raw(),
                    b: mesh.to_vertex(out).raw(),
                    wa: 0.0,
                    wb: 0.0,
                }
            })
            .collect();
        let compound = config.method != Method::Laplacian || config.preserve_volume;
        // The input volume in the caller's numbering (the same bits either way).
        let volume = if config.preserve_volume {
            let volume = Geometry::new(caller_mesh, caller_positions)
                .and_then(|g| g.volume())
                .map_err(beltrami_weights::WeightError::from)?;
            if !(volume > 0.0 && volume.is_finite()) {
                return Err(SmoothError::DegenerateVolume {
                    volume,
                    iteration: 0,
                });
            }
            volume
        } else {
            0.0
        };
        let mut config = config;
        if let Some(duration) = config.duration {
            let (lambda, iterations) = resolve_duration(
                perm.as_ref(),
                &positions,
                &laplacian,
                &roles,
                config.lambda,
                duration.time(),
            )?;
            config.lambda = lambda;
            config.iterations = iterations;
        }
        let n = positions.len();
        let eager_stats = config.statistics == Statistics::EveryIteration;
        let disp = if perm.is_some() && eager_stats {
            vec![0.0; n]
        } else {
            Vec::new()
        };
        let next = positions.to_vec();
        let compound_start = if compound {
            positions.to_vec()
        } else {
            Vec::new()
        };
        let original = if matches!(config.method, Method::Hc { .. }) {
            positions.to_vec()
        } else {
            Vec::new()
        };
        // A reordered copy is the smoother's own already: moved, not copied again.
        let positions = positions.into_owned();
        let mut smoother = Self {
            mesh,
            disp,
            view: Vec::new(),
            perm,
            partials: Vec::with_capacity(n.div_ceil(CHUNK)),
            mean_partials: Vec::with_capacity(n.div_ceil(CHUNK)),
            scheme,
            laplacian,
            exceptions: (0..n as u32)
                .filter(|&v| roles[v as usize] != Role::Row)
                .collect(),
            roles,
            curve,
            positions,
            next,
            start: compound_start,
            original,
            push_back: if matches!(config.method, Method::Hc { .. }) {
                vec![DVec3::ZERO; n]
            } else {
                Vec::new()
            },
            volume,
            config,
            iteration: 0,
            weights_fresh: true,
            weight_time: Duration::ZERO,
            update_time: Duration::ZERO,
        };
        smoother
            .refresh_curve_weights()
            .map_err(|e| smoother.to_caller(e))?;
        smoother.weight_time += start.elapsed();
        Ok(smoother)
    }

    /// Recomputes the 1-D weights of curve-boundary vertices from the current positions.
    fn refresh_curve_weights(&mut self) -> Result<(), SmoothError> {
        if self.config.boundary != Boundary::Curve {
            return Ok(());
        }
        let mesh: &HalfedgeMesh = &self.mesh;
        let geometry =
            Geometry::new(mesh, &self.positions).map_err(beltrami_weights::WeightError::from)?;
        let ctx = WeightContext::new(geometry);
        let perm = self.perm.as_ref();
        let caller = |v: u32| perm.map_or(v, |p| p.new_to_old()[v as usize]);
        // The first bad row in the caller's numbering: (its vertex there, the error).
        let mut first_bad: Option<(u32, beltrami_weights::WeightError)> = None;
        for row in &mut self.curve {
            let v = VertexId::new(row.v);
            let ha = mesh
                .find_halfedge(v, VertexId::new(row.a))
                .expect("boundary neighbour");
            let hb = mesh
                .find_halfedge(v, VertexId::new(row.b))
                .expect("boundary neighbour");
            row.wa = self.scheme.curve_weight(&ctx, ha);
            row.wb = self.scheme.curve_weight(&ctx, hb);
            let key = caller(row.v);
            if first_bad.as_ref().is_some_and(|(k, _)| *k < key) {
                continue;
            }
            if let Some((w, h)) = [(row.wa, ha), (row.wb, hb)]
                .into_iter()
                .find(|(w, _)| !w.is_finite())
            {
                // Internal numbering; `to_caller` maps it back.
                let error = beltrami_weights::WeightError::NonFiniteWeight {
                    scheme: self.scheme.name().to_string(),
                    from: row.v,
                    to: mesh.to_vertex(h).raw(),
                    value: w,
                };
                first_bad = Some((key, error));
            }
        }
        match first_bad {
            Some((_, error)) => Err(error.into()),
            None => Ok(()),
        }
    }

    /// `e` with its vertex indices in the caller's numbering.
    fn to_caller(&self, e: SmoothError) -> SmoothError {
        match &self.perm {
            Some(p) => error_to_caller(e, p),
            None => e,
        }
    }

    /// Whether the weights must be recomputed before the next iteration.
    fn weights_stale(&self) -> bool {
        match self.config.update {
            WeightUpdate::Once => false,
            WeightUpdate::Every => {
                !self.weights_fresh
                    && (self.scheme.depends_on_positions()
                        || self.config.laplacian.normalization != Normalization::WeightSum
                        || self.config.boundary == Boundary::Curve)
            }
        }
    }

    /// Does one iteration and returns its statistics.
    ///
    /// # Errors
    /// [`SmoothError::Weights`] when recomputed weights are not finite;
    /// [`SmoothError::NonFinite`] when a position would become NaN or infinite (the
    /// positions are then left as they were before the step).
    pub fn step(&mut self) -> Result<StepStats, SmoothError> {
        self.iterate(Want::Full)
    }

    /// Does one iteration like [`step`](Self::step) but computes no displacement
    /// statistics (a square root per vertex and, with reordering, a gather): the fast
    /// way to drive iterations. The positions are the same bits as with `step`.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn advance(&mut self) -> Result<(), SmoothError> {
        self.iterate(Want::Nothing).map(|_| ())
    }

    /// One iteration, with the statistics `want` asks for (the others are 0; the stuck
    /// count is always there).
    fn iterate(&mut self, want: Want) -> Result<StepStats, SmoothError> {
        self.iteration += 1;
        let method = self.config.method;
        if method == Method::Laplacian && !self.config.preserve_volume {
            return self.sweep(self.config.lambda, want);
        }
        self.start.copy_from_slice(&self.positions);
        let result = self.compound_step(method);
        if result.is_err() {
            self.positions.copy_from_slice(&self.start);
        }
        result
    }

    /// One iteration of a method other than plain diffusion, or with a volume rescale:
    /// the sweeps, the corrections, then statistics measured from `start`.
    fn compound_step(&mut self, method: Method) -> Result<StepStats, SmoothError> {
        let lambda = self.config.lambda;
        let stuck = match method {
            Method::Laplacian => self.sweep(lambda, Want::Nothing)?.stuck_vertices,
            Method::Taubin { mu } => {
                let first = self.sweep(lambda, Want::Nothing)?.stuck_vertices;
                first.max(self.sweep(mu, Want::Nothing)?.stuck_vertices)
            }
            Method::Hc { alpha, beta } => {
                let stuck = self.sweep(lambda, Want::Nothing)?.stuck_vertices;
                self.hc_correct(alpha, beta);
                stuck
            }
        };
        if self.config.preserve_volume {
            self.rescale_volume()?;
        }
        let start = Instant::now();
        let (before, after) = (&self.start, &self.positions);
        let partials: Vec<(f64, f64, Option<u32>)> = if let Some(perm) = &self.perm {
            // In the caller's order, so that the sum and the first bad index are the
            // unreordered run's.
            perm.old_to_new()
                .par_chunks(CHUNK)
                .enumerate()
                .map(|(c, ids)| {
                    let mut sum = 0.0;
                    let mut max: f64 = 0.0;
                    let mut bad = None;
                    for (k, &i) in ids.iter().enumerate() {
                        let (p, q) = (after[i as usize], before[i as usize]);
                        if !p.is_finite() && bad.is_none() {
                            bad = Some((c * CHUNK + k) as u32);
                        }
                        let d = beltrami_halfedge::geometry::distance(q, p);
                        sum += d;
                        max = max.max(d);
                    }
                    (sum, max, bad)
                })
                .collect()
        } else {
            after
                .par_chunks(CHUNK)
                .zip(before.par_chunks(CHUNK))
                .enumerate()
                .map(|(c, (a, b))| {
                    let mut sum = 0.0;
                    let mut max: f64 = 0.0;
                    let mut bad = None;
                    for (k, (p, q)) in a.iter().zip(b).enumerate() {
                        if !p.is_finite() && bad.is_none() {
                            bad = Some((c * CHUNK + k) as u32);
                        }
                        let d = beltrami_halfedge::geometry::distance(*q, *p);
                        sum += d;
                        max = max.max(d);
                    }
                    (sum, max, bad)
                })
                .collect()
        };
        self.update_time += start.elapsed();
        let mut stats = StepStats::default();
        let mut sum = 0.0;
        for (s, m, bad) in partials {
            if let Some(vertex) = bad {
                return Err(SmoothError::NonFinite {
                    vertex,
                    iteration: self.iteration,
                });
            }
            sum += s;
            stats.max_displacement = stats.max_displacement.max(m);
        }
        stats.stuck_vertices = stuck;
        let n = self.positions.len();
        stats.mean_displacement = if n == 0 { 0.0 } else { sum / n as f64 };
        Ok(stats)
    }

    /// The HC push-back (see [`Method::Hc`]): `positions` holds `p` (after the sweep),
    /// `next` holds `q` (before it).
    fn hc_correct(&mut self, alpha: f64, beta: f64) {
        let start = Instant::now();
        let (p, q, o) = (&self.positions, &self.next, &self.original);
        self.push_back
            .par_iter_mut()
            .zip(p.par_iter())
            .zip(q.par_iter().zip(o.par_iter()))
            .for_each(|((b, p), (q, o))| *b = *p - (*o * alpha + *q * (1.0 - alpha)));
        let b = &self.push_back;
        let (laplacian, roles) = (&self.laplacian, &self.roles);
        self.next
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                for (k, slot) in out.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    let pi = p[i];
                    *slot = if roles[i] == Role::Row {
                        // The plain neighbour average, as Vollmer et al.: weights
                        // that can be negative (cotangent) would amplify b.
                        let row = laplacian.row(VertexId::new(i as u32));
                        let n = row.len();
                        let s: DVec3 = row.map(|(j, _)| b[j.index()]).sum();
                        let mean = s / n as f64;
                        if n > 0 && mean.is_finite() {
                            pi - (b[i] * beta + mean * (1.0 - beta))
                        } else {
                            pi - b[i]
                        }
                    } else {
                        pi
                    };
                }
            });
        std::mem::swap(&mut self.positions, &mut self.next);
        self.update_time += start.elapsed();
    }

    /// Rescales about the surface centroid so that the volume is the input's.
    fn rescale_volume(&mut self) -> Result<(), SmoothError> {
        let start = Instant::now();
        let geometry = Geometry::new(&self.mesh, &self.positions)
            .map_err(beltrami_weights::WeightError::from)?;
        let volume = geometry
            .volume()
            .map_err(beltrami_weights::WeightError::from)?;
        let centre = geometry.surface_centroid().unwrap_or(DVec3::ZERO);
        let beta = (self.volume / volume).cbrt();
        if !(volume > 0.0 && beta.is_finite()) {
            return Err(SmoothError::DegenerateVolume {
                volume,
                iteration: self.iteration,
            });
        }
        let mesh: &HalfedgeMesh = &self.mesh;
        self.positions
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, x)| {
                if !mesh.is_isolated(VertexId::new(i as u32)) {
                    *x = centre + (*x - centre) * beta;
                }
            });
        self.update_time += start.elapsed();
        Ok(())
    }

    /// One Jacobi sweep `x ← x + step · L x` over the moving vertices, refreshing the
    /// weights first when they are stale, with the statistics `want` asks for. On error
    /// the positions are unchanged.
    fn sweep(&mut self, lambda: f64, want: Want) -> Result<StepStats, SmoothError> {
        if self.weights_stale() {
            let start = Instant::now();
            let refreshed = match self
                .laplacian
                .update(&self.mesh, &self.positions, self.scheme)
            {
                Ok(()) => self.refresh_curve_weights(),
                Err(e) => Err(e.into()),
            };
            if let Err(e) = refreshed {
                return Err(self.to_caller(e));
            }
            self.weight_time += start.elapsed();
        }
        self.weights_fresh = false;

        if want == Want::Full && self.perm.is_some() {
            // Once per run at most: with on-demand statistics only a `step()` needs it.
            self.disp.resize(self.positions.len(), 0.0);
        }
        let start = Instant::now();
        let sweep = SweepInput {
            laplacian: &self.laplacian,
            roles: &self.roles,
            exceptions: &self.exceptions,
            curve: &self.curve,
            old: &self.positions,
            lambda,
        };
        let chunks = self.next.par_chunks_mut(CHUNK).enumerate();
        match (want, self.perm.is_some()) {
            (Want::Nothing, _) => chunks
                .map(|(c, out)| sweep.chunk::<NOTHING, false>(c * CHUNK, out, &mut []))
                .collect_into_vec(&mut self.partials),
            (Want::Max, _) => chunks
                .map(|(c, out)| sweep.chunk::<MAX, false>(c * CHUNK, out, &mut []))
                .collect_into_vec(&mut self.partials),
            (Want::Full, false) => chunks
                .map(|(c, out)| sweep.chunk::<FULL, false>(c * CHUNK, out, &mut []))
                .collect_into_vec(&mut self.partials),
            (Want::Full, true) => chunks
                .zip(self.disp.par_chunks_mut(CHUNK))
                .map(|((c, out), disp)| sweep.chunk::<FULL, true>(c * CHUNK, out, disp))
                .collect_into_vec(&mut self.partials),
        }
        self.update_time += start.elapsed();

        let mut stats = StepStats::default();
        let mut sum = 0.0;
        let mut squared: f64 = 0.0;
        for p in &self.partials {
            if let Some(vertex) = p.bad {
                // The smallest vertex in the caller's numbering, as without reordering.
                let vertex = match &self.perm {
                    Some(perm) => self
                        .next
                        .par_iter()
                        .zip(perm.new_to_old().par_iter())
                        .filter(|(x, _)| !x.is_finite())
                        .map(|(_, &old)| old)
                        .min()
                        .unwrap_or(vertex),
                    None => vertex,
                };
                self.next.copy_from_slice(&self.positions);
                return Err(SmoothError::NonFinite {
                    vertex,
                    iteration: self.iteration,
                });
            }
            sum += p.sum;
            stats.max_displacement = stats.max_displacement.max(p.max);
            squared = squared.max(p.max_squared);
            stats.stuck_vertices += p.stuck;
        }
        // Every plain displacement is the square root of its squared length, and the
        // square root is monotonic: the largest of them is the root of the largest square.
        stats.max_displacement = stats.max_displacement.max(squared.sqrt());
        if want == Want::Full
            && let Some(perm) = &self.perm
        {
            // The same chunks and order as without reordering: the same bits.
            let start = Instant::now();
            let disp = &self.disp;
            perm.old_to_new()
                .par_chunks(CHUNK)
                .map(|ids| {
                    let mut sum = 0.0;
                    for &i in ids {
                        sum += disp[i as usize];
                    }
                    sum
                })
                .collect_into_vec(&mut self.mean_partials);
            sum = 0.0;
            for s in &self.mean_partials {
                sum += s;
            }
            self.update_time += start.elapsed();
        }
        let n = self.positions.len();
        stats.mean_displacement = if n == 0 { 0.0 } else { sum / n as f64 };
        std::mem::swap(&mut self.positions, &mut self.next);
        Ok(stats)
    }

    /// The positions before the last iteration (internal numbering): `next` after a
    /// plain sweep, `start` after a compound step.
    fn before(&self) -> &[DVec3] {
        if self.config.method == Method::Laplacian && !self.config.preserve_volume {
            &self.next
        } else {
            &self.start
        }
    }

    /// Runs the configured number of iterations, calling `observer` after each one; the
    /// observer stops the run early by returning `ControlFlow::Break(())`.
    ///
    /// With [`Statistics::EveryIteration`] (the default) every iteration's statistics
    /// are computed and kept in the report; with [`Statistics::OnDemand`] only when the
    /// observer calls [`IterationView::stats`] (and the largest displacement when
    /// [`SmoothConfig::until_change`] needs it).
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn run<F>(mut self, mut observer: F) -> Result<Smoothed, SmoothError>
    where
        F: FnMut(&IterationView<'_>) -> ControlFlow<()>,
    {
        let every = self.config.statistics == Statistics::EveryIteration;
        let want = if every {
            Want::Full
        } else if self.config.until_change.is_some() {
            Want::Max
        } else {
            Want::Nothing
        };
        let mut steps = Vec::with_capacity(if every { self.config.iterations } else { 0 });
        let mut max_stuck = 0;
        let mut stop = StopReason::Completed;
        while self.iteration < self.config.iterations {
            let stats = self.iterate(want)?;
            if every {
                steps.push(stats);
            }
            max_stuck = max_stuck.max(stats.stuck_vertices);
            let spare = std::mem::take(&mut self.view);
            let it = IterationView {
                index: self.iteration,
                after: &self.positions,
                before: self.before(),
                perm: self.perm.as_ref(),
                spare: Cell::new(spare),
                restored: OnceCell::new(),
                stats: if every {
                    OnceCell::from(stats)
                } else {
                    OnceCell::new()
                },
                stuck: stats.stuck_vertices,
            };
            let flow = observer(&it);
            self.view = it.into_buffer();
            if flow.is_break() {
                stop = StopReason::Observer;
                break;
            }
            if self
                .config
                .until_change
                .is_some_and(|eps| stats.max_displacement <= eps)
            {
                stop = StopReason::Converged;
                break;
            }
        }
        let report = SmoothReport {
            scheme: self.scheme.name().to_string(),
            iterations: self.iteration,
            stop,
            max_stuck_vertices: max_stuck,
            steps,
            weight_time: self.weight_time,
            update_time: self.update_time,
            config: self.config,
        };
        let positions = match &self.perm {
            Some(perm) => {
                // `next` is not needed any more: it takes the caller's order.
                let mut out = std::mem::take(&mut self.next);
                out.resize(self.positions.len(), DVec3::ZERO);
                restore_par(perm, &self.positions, &mut out);
                out
            }
            None => self.positions,
        };
        Ok(Smoothed { positions, report })
    }

    /// The largest stable explicit step of an area-normalised operator on the current
    /// positions, in length² (a time per iteration): `1 / max_i (W_i / A_i)` over the
    /// moving vertices, with `W_i` the weight sum and `A_i` the vertex area. The step
    /// `x + λ M⁻¹ L x` has the eigenvalues of `λ M⁻¹ L` in `[−2 λ r, 0]` by
    /// Gershgorin's theorem (non-negative weights), so `λ ≤ 1 / r` keeps every
    /// frequency from growing. `None` with weight-sum normalisation (whose stable range
    /// is λ ≤ 1) or when no vertex moves. Weights recomputed every iteration move the
    /// limit a little as the mesh changes.
    ///
    /// A step from [`DiffusionTime`](crate::DiffusionTime) is chosen below half this
    /// limit; a step given directly is the caller's to check, e.g. to fail with
    /// [`SmoothError::UnstableStep`].
    #[must_use]
    pub fn stable_step_limit(&self) -> Option<f64> {
        if self.config.laplacian.normalization == Normalization::WeightSum {
            return None;
        }
        let rate = area_rate(&self.laplacian, &self.roles);
        (rate > 0.0).then(|| 1.0 / rate)
    }

    /// The configuration of the run; with a [`duration`](SmoothConfig::duration),
    /// `lambda` and `iterations` are the step and count the smoother chose.
    #[must_use]
    pub fn config(&self) -> &SmoothConfig {
        &self.config
    }

    /// The current positions, in the caller's numbering: borrowed when the smoother
    /// works in that numbering, a restored copy (O(V) time and memory) when it reorders
    /// (see [`Reorder`](crate::Reorder) and [`permutation`](Self::permutation)).
    #[must_use]
    pub fn positions(&self) -> Cow<'_, [DVec3]> {
        match &self.perm {
            Some(perm) => {
                let mut out = vec![DVec3::ZERO; self.positions.len()];
                restore_par(perm, &self.positions, &mut out);
                Cow::Owned(out)
            }
            None => Cow::Borrowed(&self.positions),
        }
    }

    /// The internal vertex numbering, when the smoother reorders: internal vertex `i`
    /// is the caller's vertex `new_to_old()[i]`. `None` when it works in the caller's
    /// numbering.
    #[must_use]
    pub fn permutation(&self) -> Option<&VertexPermutation> {
        self.perm.as_ref()
    }

    /// The number of iterations done.
    #[must_use]
    pub fn iteration(&self) -> usize {
        self.iteration
    }

    /// The operator as last assembled, in the internal numbering: its row `i` and its
    /// neighbour ids are internal vertex ids (the caller's when
    /// [`permutation`](Self::permutation) is `None`; map them with it otherwise).
    #[must_use]
    pub fn laplacian(&self) -> &Laplacian {
        &self.laplacian
    }
}

/// Which displacement statistics a sweep computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Want {
    /// None (the stuck count only).
    Nothing,
    /// The largest displacement (no square root per vertex, no gather).
    Max,
    /// Everything in [`StepStats`].
    Full,
}

/// [`SweepInput::chunk`] modes (a `const` parameter, so each is its own loop).
const NOTHING: u8 = 0;
const MAX: u8 = 1;
const FULL: u8 = 2;

/// What one chunk of a sweep found.
#[derive(Clone, Copy, Debug, Default)]
struct Partial {
    /// The sum of the displacements in vertex order (`FULL`).
    sum: f64,
    /// The largest displacement (`FULL`), or the largest one outside the plain range
    /// (`MAX`).
    max: f64,
    /// The largest squared length of a displacement in the plain range (`MAX`).
    max_squared: f64,
    stuck: usize,
    /// The first vertex whose new position is not finite.
    bad: Option<u32>,
}

/// What a sweep reads.
struct SweepInput<'s> {
    laplacian: &'s Laplacian,
    roles: &'s [Role],
    exceptions: &'s [u32],
    curve: &'s [CurveRow],
    old: &'s [DVec3],
    lambda: f64,
}

impl SweepInput<'_> {
    /// Sweeps the rows `first..first + out.len()` into `out`, with the statistics of
    /// `MODE` (`NOTHING`, `MAX`, `FULL`); with `RECORD` (and `FULL`), also stores each
    /// vertex's displacement in `disp`.
    #[inline]
    fn chunk<const MODE: u8, const RECORD: bool>(
        &self,
        first: usize,
        out: &mut [DVec3],
        disp: &mut [f64],
    ) -> Partial {
        let Self {
            laplacian,
            roles,
            exceptions,
            curve,
            old,
            lambda,
        } = *self;
        let rows = first..first + out.len();
        // Every row moves by its Laplacian row...
        let RowSweep {
            mut stuck,
            sum: mut probe,
        } = laplacian.sweep_rows(first, old, lambda, out);
        // ...then the vertices that do not move that way are put right. `probe` keeps
        // the value a row gave them: a spurious non-finite sum only costs a scan.
        let lo = exceptions.partition_point(|&v| (v as usize) < rows.start);
        let hi = exceptions.partition_point(|&v| (v as usize) < rows.end);
        let mut cursor = curve.partition_point(|r| (r.v as usize) < first);
        for &v in &exceptions[lo..hi] {
            let i = v as usize;
            if laplacian.scale(VertexId::new(v)).is_none() {
                // Counted by the row sweep, but this vertex is not a row.
                stuck -= 1;
            }
            let xi = old[i];
            let new = match roles[i] {
                Role::Still | Role::Row => xi,
                Role::Curve => {
                    let CurveRow { a, b, wa, wb, .. } = curve[cursor];
                    cursor += 1;
                    let s = old[a as usize] * wa + old[b as usize] * wb;
                    let inv = 1.0 / (wa + wb);
                    if inv.is_finite() && inv > 0.0 {
                        xi + (s * inv - xi) * lambda
                    } else {
                        stuck += 1;
                        xi
                    }
                }
            };
            probe += new;
            out[i - first] = new;
        }
        let mut sum = 0.0;
        let mut max: f64 = 0.0;
        let mut max_squared: f64 = 0.0;
        if MODE != NOTHING {
            for (k, (&xi, &new)) in old[rows].iter().zip(out.iter()).enumerate() {
                if MODE == FULL {
                    // `geometry::distance` is the plain length whenever that is at
                    // least sqrt(f64::MIN_POSITIVE) and finite (the same bits); the
                    // call handles the rest (zero, tiny, huge, non-finite).
                    let plain = (new - xi).length();
                    let d = if (1.491_668_146_240_041_3e-154..f64::INFINITY).contains(&plain) {
                        plain
                    } else {
                        beltrami_halfedge::geometry::distance(xi, new)
                    };
                    sum += d;
                    max = max.max(d);
                    if RECORD {
                        disp[k] = d;
                    }
                } else {
                    // The plain length is `q.sqrt()`, in [sqrt(MIN_POSITIVE), ∞)
                    // exactly when `q` is in [MIN_POSITIVE, ∞) (both ends are exact
                    // squares).
                    let q = (new - xi).length_squared();
                    if (f64::MIN_POSITIVE..f64::INFINITY).contains(&q) {
                        max_squared = max_squared.max(q);
                    } else {
                        max = max.max(beltrami_halfedge::geometry::distance(xi, new));
                    }
                }
            }
        }
        let bad = if probe.is_finite() {
            None
        } else {
            out.iter()
                .position(|x| !x.is_finite())
                .map(|k| (first + k) as u32)
        };
        Partial {
            sum,
            max,
            max_squared,
            stuck,
            bad,
        }
    }
}

/// The displacement statistics of an iteration from `before` to `after` (internal
/// numbering, finite), with `stuck` stuck vertices: the distances summed in the caller's
/// order in chunks of [`CHUNK`], as a sweep with [`Want::Full`] does (the same bits).
fn displacement_stats(
    perm: Option<&VertexPermutation>,
    before: &[DVec3],
    after: &[DVec3],
    stuck: usize,
) -> StepStats {
    let distance = |i: usize| beltrami_halfedge::geometry::distance(before[i], after[i]);
    let fold = |ids: &mut dyn Iterator<Item = usize>| {
        let mut sum = 0.0;
        let mut max: f64 = 0.0;
        for i in ids {
            let d = distance(i);
            sum += d;
            max = max.max(d);
        }
        (sum, max)
    };
    let partials: Vec<(f64, f64)> = match perm {
        Some(perm) => perm
            .old_to_new()
            .par_chunks(CHUNK)
            .map(|ids| fold(&mut ids.iter().map(|&i| i as usize)))
            .collect(),
        None => (0..after.len().div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| fold(&mut (c * CHUNK..((c + 1) * CHUNK).min(after.len()))))
            .collect(),
    };
    let mut stats = StepStats {
        stuck_vertices: stuck,
        ..StepStats::default()
    };
    let mut sum = 0.0;
    for (s, m) in partials {
        sum += s;
        stats.max_displacement = stats.max_displacement.max(m);
    }
    let n = after.len();
    stats.mean_displacement = if n == 0 { 0.0 } else { sum / n as f64 };
    stats
}

/// `internal` back in the caller's numbering, into `out`, gathered in parallel.
fn restore_par(perm: &VertexPermutation, internal: &[DVec3], out: &mut [DVec3]) {
    out.par_chunks_mut(CHUNK)
        .zip(perm.old_to_new().par_chunks(CHUNK))
        .for_each(|(out, ids)| {
            for (x, &i) in out.iter_mut().zip(ids) {
                *x = internal[i as usize];
            }
        });
}

/// `positions` in the internal numbering of `perm`, gathered in parallel.
fn permute_par(perm: &VertexPermutation, positions: &[DVec3]) -> Vec<DVec3> {
    perm.new_to_old()
        .par_iter()
        .map(|&o| positions[o as usize])
        .collect()
}

/// `e` with the vertex indices of the internal numbering `perm` mapped back to the
/// caller's.
fn error_to_caller(e: SmoothError, perm: &VertexPermutation) -> SmoothError {
    let old = |v: u32| perm.new_to_old()[v as usize];
    match e {
        SmoothError::Weights(beltrami_weights::WeightError::NonFiniteWeight {
            scheme,
            from,
            to,
            value,
        }) => SmoothError::Weights(beltrami_weights::WeightError::NonFiniteWeight {
            scheme,
            from: old(from),
            to: old(to),
            value,
        }),
        e => e,
    }
}

/// Smooths `positions` with `scheme` as `config` says, in one call.
///
/// # Errors
/// As [`Smoother::new`] and [`Smoother::step`].
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

/// Checks the method, volume, duration and convergence settings of `config`.
fn validate_method(
    config: &SmoothConfig,
    mesh: &HalfedgeMesh,
    weight_sum: bool,
) -> Result<(), SmoothError> {
    let lambda = config.lambda;
    match config.method {
        Method::Laplacian => {}
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
        if !(t >= 0.0 && t.is_finite()) {
            return Err(SmoothError::InvalidDuration {
                reason: match duration {
                    DiffusionTime::Time(_) => {
                        format!("the time must be finite and >= 0, got {}", Short(t))
                    }
                    DiffusionTime::Cutoff(lc) => format!(
                        "the cut-off must be finite and >= 0 and give a finite time, got {} (time {})",
                        Short(lc),
                        Short(t)
                    ),
                },
            });
        }
        if config.method != Method::Laplacian {
            return Err(SmoothError::InvalidDuration {
                reason: format!(
                    "a diffusion time applies to plain Laplacian diffusion only, not to method '{}'",
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

/// The largest rate `max_i W_i / A_i` of the moving rows of an area-normalised
/// Laplacian (weight sum over vertex area, in 1/length²), 0 when no row moves.
fn area_rate(laplacian: &Laplacian, roles: &[Role]) -> f64 {
    let mut rate: f64 = 0.0;
    for (i, role) in roles.iter().enumerate() {
        let v = VertexId::new(i as u32);
        if *role == Role::Row
            && let Some(scale) = laplacian.scale(v)
        {
            rate = rate.max(laplacian.weight_sum(v) * scale);
        }
    }
    rate
}

/// The step and iteration count that diffuse for the time `t` (length²); see
/// [`DiffusionTime`](crate::DiffusionTime).
fn resolve_duration(
    perm: Option<&VertexPermutation>,
    positions: &[DVec3],
    laplacian: &Laplacian,
    roles: &[Role],
    max_lambda: f64,
    t: f64,
) -> Result<(f64, usize), SmoothError> {
    if t == 0.0 {
        return Ok((max_lambda, 0));
    }
    let (time_per_unit, max_step) = match laplacian.options().normalization {
        Normalization::WeightSum => {
            // A normalised row acting on f = ½|x − x_i|² gives ½⟨ℓ²⟩_w, the
            // weighted mean squared edge length; Δf = 2 on a surface, so the row is
            // ≈ (⟨ℓ²⟩_w / 4) Δ: one step λ advances vertex i's time by λ⟨ℓ²⟩_w / 4.
            // The mean over the moving rows is the mesh's time per unit step.
            let mut sum = 0.0;
            let mut count = 0usize;
            // Summed in the caller's vertex order, so that reordering changes no bit.
            for old in 0..positions.len() {
                let v = VertexId::new(perm.map_or(old as u32, |p| p.old_to_new()[old]));
                if roles[v.index()] != Role::Row {
                    continue;
                }
                let xi = positions[v.index()];
                let w = laplacian.weight_sum(v);
                let mut s = 0.0;
                for (j, wij) in laplacian.row(v) {
                    s += wij * positions[j.index()].distance_squared(xi);
                }
                let mean = s / w;
                if w > 0.0 && mean.is_finite() && mean > 0.0 {
                    sum += mean;
                    count += 1;
                }
            }
            let mean = if count == 0 { 0.0 } else { sum / count as f64 };
            if !(mean > 0.0 && mean.is_finite()) {
                return Err(SmoothError::InvalidDuration {
                    reason: "the mesh has no moving vertex with edges of positive length to measure time by".into(),
                });
            }
            // One step λ advances the time by λ ⟨ℓ²⟩ / 4.
            (mean / 4.0, max_lambda)
        }
        // Area normalisation: λ is a time per iteration.
        _ => {
            let rate = area_rate(laplacian, roles);
            let cap = if rate > 0.0 { 0.5 / rate } else { max_lambda };
            (1.0, max_lambda.min(cap))
        }
    };
    let units = t / time_per_unit;
    let iterations = (units / max_step).ceil();
    if !(iterations.is_finite() && iterations <= 1e9) {
        return Err(SmoothError::InvalidDuration {
            reason: format!("the time {t} would need {iterations} iterations"),
        });
    }
    let iterations = (iterations as usize).max(1);
    Ok((units / iterations as f64, iterations))
}
