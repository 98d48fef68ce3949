//! The explicit Jacobi smoother: `step()`, `run()` with an observer, and `smooth()`.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::{Laplacian, Normalization, WeightContext, WeightScheme};
use rayon::prelude::*;

use crate::config::{Boundary, SmoothConfig, WeightUpdate};
use crate::error::SmoothError;

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

/// What the observer sees after each iteration.
#[derive(Debug)]
pub struct Iteration<'a> {
    /// The number of iterations done so far (1 after the first).
    pub index: usize,
    /// The positions after this iteration.
    pub positions: &'a [DVec3],
    /// This iteration's statistics.
    pub stats: StepStats,
}

/// Why a run stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StopReason {
    /// All requested iterations were done.
    Completed,
    /// The observer returned `ControlFlow::Break`.
    Observer,
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothReport {
    /// The scheme's name.
    pub scheme: String,
    /// The configuration used.
    pub config: SmoothConfig,
    /// Iterations done.
    pub iterations: usize,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Per-iteration statistics.
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
    mesh: &'a HalfedgeMesh,
    scheme: &'a dyn WeightScheme,
    config: SmoothConfig,
    laplacian: Laplacian,
    roles: Vec<Role>,
    curve: Vec<CurveRow>,
    positions: Vec<DVec3>,
    next: Vec<DVec3>,
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
        for v in &config.pinned {
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
        let mut smoother = Self {
            mesh,
            scheme,
            config,
            laplacian,
            roles,
            curve,
            positions: positions.to_vec(),
            next: positions.to_vec(),
            iteration: 0,
            weights_fresh: true,
            weight_time: Duration::ZERO,
            update_time: Duration::ZERO,
        };
        smoother.refresh_curve_weights()?;
        smoother.weight_time += start.elapsed();
        Ok(smoother)
    }

    /// Recomputes the 1-D weights of curve-boundary vertices from the current positions.
    fn refresh_curve_weights(&mut self) -> Result<(), SmoothError> {
        if self.config.boundary != Boundary::Curve {
            return Ok(());
        }
        let geometry = Geometry::new(self.mesh, &self.positions)
            .map_err(beltrami_weights::WeightError::from)?;
        let ctx = WeightContext::new(geometry);
        let mesh = self.mesh;
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
            for (w, h) in [(row.wa, ha), (row.wb, hb)] {
                if !w.is_finite() {
                    return Err(beltrami_weights::WeightError::NonFiniteWeight {
                        scheme: self.scheme.name().to_string(),
                        from: row.v,
                        to: mesh.to_vertex(h).raw(),
                        value: w,
                    }
                    .into());
                }
            }
        }
        Ok(())
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
        if self.weights_stale() {
            let start = Instant::now();
            self.laplacian
                .update(self.mesh, &self.positions, self.scheme)?;
            self.refresh_curve_weights()?;
            self.weight_time += start.elapsed();
        }
        self.weights_fresh = false;
        self.iteration += 1;

        let start = Instant::now();
        let lambda = self.config.lambda;
        let (laplacian, roles, curve, old) =
            (&self.laplacian, &self.roles, &self.curve, &self.positions);
        // Each chunk returns (sum of displacements, max displacement, stuck count, first
        // non-finite vertex).
        let partials: Vec<(f64, f64, usize, Option<u32>)> = self
            .next
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, out)| {
                let first = c * CHUNK;
                let mut sum = 0.0;
                let mut max: f64 = 0.0;
                let mut stuck = 0;
                let mut bad = None;
                let mut cursor = curve.partition_point(|r| (r.v as usize) < first);
                laplacian.for_each_row(first..first + out.len(), old, |i, xi, l| {
                    let new = match roles[i] {
                        Role::Still => xi,
                        Role::Row => match l {
                            Some(l) => xi + l * lambda,
                            None => {
                                stuck += 1;
                                xi
                            }
                        },
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
                    if !new.is_finite() && bad.is_none() {
                        bad = Some(i as u32);
                    }
                    // `geometry::distance` is the plain length whenever that is at least
                    // sqrt(f64::MIN_POSITIVE) and finite (the same bits); the call handles
                    // the rest (zero, tiny, huge, non-finite).
                    let plain = (new - xi).length();
                    let d = if (1.491_668_146_240_041_3e-154..f64::INFINITY).contains(&plain) {
                        plain
                    } else {
                        beltrami_halfedge::geometry::distance(xi, new)
                    };
                    sum += d;
                    max = max.max(d);
                    out[i - first] = new;
                });
                (sum, max, stuck, bad)
            })
            .collect();
        self.update_time += start.elapsed();

        let mut stats = StepStats::default();
        let mut sum = 0.0;
        for (s, m, stuck, bad) in partials {
            if let Some(vertex) = bad {
                self.next.copy_from_slice(&self.positions);
                return Err(SmoothError::NonFinite {
                    vertex,
                    iteration: self.iteration,
                });
            }
            sum += s;
            stats.max_displacement = stats.max_displacement.max(m);
            stats.stuck_vertices += stuck;
        }
        let n = self.positions.len();
        stats.mean_displacement = if n == 0 { 0.0 } else { sum / n as f64 };
        std::mem::swap(&mut self.positions, &mut self.next);
        Ok(stats)
    }

    /// Runs the configured number of iterations, calling `observer` after each one; the
    /// observer stops the run early by returning `ControlFlow::Break(())`.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn run<F>(mut self, mut observer: F) -> Result<Smoothed, SmoothError>
    where
        F: FnMut(&Iteration<'_>) -> ControlFlow<()>,
    {
        let mut steps = Vec::with_capacity(self.config.iterations);
        let mut stop = StopReason::Completed;
        while self.iteration < self.config.iterations {
            let stats = self.step()?;
            steps.push(stats);
            let it = Iteration {
                index: self.iteration,
                positions: &self.positions,
                stats,
            };
            if observer(&it).is_break() {
                stop = StopReason::Observer;
                break;
            }
        }
        let report = SmoothReport {
            scheme: self.scheme.name().to_string(),
            iterations: self.iteration,
            stop,
            max_stuck_vertices: steps.iter().map(|s| s.stuck_vertices).max().unwrap_or(0),
            steps,
            weight_time: self.weight_time,
            update_time: self.update_time,
            config: self.config,
        };
        Ok(Smoothed {
            positions: self.positions,
            report,
        })
    }

    /// The current positions.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The number of iterations done.
    #[must_use]
    pub fn iteration(&self) -> usize {
        self.iteration
    }

    /// The operator as last assembled.
    #[must_use]
    pub fn laplacian(&self) -> &Laplacian {
        &self.laplacian
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
