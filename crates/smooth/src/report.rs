//! What a run reports: per-iteration statistics, the observer's view, the report.

use std::cell::{Cell, OnceCell};
use std::time::Duration;

use beltrami_halfedge::DVec3;
use beltrami_halfedge::reorder::VertexPermutation;
use rayon::prelude::*;

use crate::config::SmoothConfig;
use crate::numbering::{CHUNK, restore_par};

/// Statistics of one iteration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// The largest distance a vertex moved, in the positions' unit.
    pub max_displacement: f64,
    /// The mean distance over all vertices (still ones count as 0).
    pub mean_displacement: f64,
    /// Vertices that should have moved but could not, because their weights summed to
    /// ≤ 0 or their area was 0 (see
    /// [`Laplacian::stuck_rows`](beltrami_weights::Laplacian::stuck_rows)). An implicit
    /// step holds them as Dirichlet rows.
    pub stuck_vertices: usize,
    /// What the linear solver did in this step ([`Method::Implicit`](crate::Method::Implicit) only).
    pub solve: Option<SolveStats>,
}

/// What the linear solver did in one implicit step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    /// Whether this step factorised the matrix numerically (Cholesky only).
    pub factorized: bool,
    /// Conjugate-gradient iterations of this step, summed over the three coordinates
    /// (0 for Cholesky).
    pub cg_iterations: usize,
    /// The relative residual `‖b − A x‖₂ / ‖b‖₂` reached, worst coordinate
    /// (conjugate gradient; `None` for Cholesky, exact to rounding).
    pub residual: Option<f64>,
}

/// What the observer of [`Smoother::run`](crate::Smoother::run) sees after each
/// iteration, explicit or implicit.
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

impl<'a> IterationView<'a> {
    /// The view after iteration `index` from `before` to `after` (internal numbering),
    /// with the statistics when they were computed during the iteration; `spare` is
    /// the buffer the positions are gathered into with `perm`.
    pub(crate) fn new(
        index: usize,
        after: &'a [DVec3],
        before: &'a [DVec3],
        perm: Option<&'a VertexPermutation>,
        spare: Vec<DVec3>,
        stats: Option<StepStats>,
        stuck: usize,
    ) -> Self {
        Self {
            index,
            after,
            before,
            perm,
            spare: Cell::new(spare),
            restored: OnceCell::new(),
            stats: stats.map_or_else(OnceCell::new, OnceCell::from),
            stuck,
        }
    }

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
    /// [`Statistics::EveryIteration`](crate::Statistics::EveryIteration), otherwise on the first call (O(V), in parallel,
    /// from the positions before and after the iteration; the same bits either way).
    #[must_use]
    pub fn stats(&self) -> StepStats {
        *self
            .stats
            .get_or_init(|| displacement_stats(self.perm, self.before, self.after, self.stuck))
    }

    /// The restore buffer, for the next iteration.
    pub(crate) fn into_buffer(self) -> Vec<DVec3> {
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
    /// Per-iteration statistics, with [`Statistics::EveryIteration`](crate::Statistics::EveryIteration) (the default); empty
    /// with [`Statistics::OnDemand`](crate::Statistics::OnDemand).
    pub steps: Vec<StepStats>,
    /// The largest number of stuck vertices in any iteration.
    pub max_stuck_vertices: usize,
    /// Wall time spent computing weights (including the first computation); for an
    /// implicit run also the vertex areas and the matrix entries.
    pub weight_time: Duration,
    /// Wall time spent updating positions; for an implicit run the right-hand sides and
    /// solves (triangular solves or conjugate gradient).
    pub update_time: Duration,
    /// What the linear solver did over the run ([`Method::Implicit`](crate::Method::Implicit) only).
    pub solver: Option<SolverReport>,
    /// Iterations whose rows were summed element by element
    /// ([`Summation::Scatter`](crate::Summation::Scatter)); fewer than
    /// [`iterations`](Self::iterations) when that summation was asked for but did not
    /// apply (cotangent weights on faces other than triangles, a triangle collapsed to a
    /// point, an edge too long for plain products, a vertex order too scattered for the
    /// sweep without reordering), and 0 with the default summation.
    pub scattered_sweeps: usize,
}

/// What the linear solver of an implicit run did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SolverReport {
    /// Symbolic analyses done (Cholesky: 1, reused by every numeric factorisation).
    pub symbolic_factorizations: usize,
    /// Numeric factorisations done (Cholesky: 1 while the operator is frozen, one per
    /// step when the weights are recomputed).
    pub numeric_factorizations: usize,
    /// The number of non-zeros of the Cholesky factor (0 for conjugate gradient).
    pub factor_nonzeros: usize,
    /// Conjugate-gradient iterations over the run, all coordinates.
    pub cg_iterations: usize,
    /// Wall time of the symbolic analysis (ordering and factor structure).
    pub analysis_time: Duration,
    /// Wall time of the numeric factorisations.
    pub factorization_time: Duration,
}

/// Smoothed positions and the report of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Smoothed {
    /// The positions after the run, one per vertex, in the input order.
    pub positions: Vec<DVec3>,
    /// What the run did.
    pub report: SmoothReport,
}

/// The displacement statistics of an iteration from `before` to `after` (internal
/// numbering, finite), with `stuck` stuck vertices: the distances summed in the caller's
/// order in chunks of [`CHUNK`], as a sweep with [`Want::Full`] does (the same bits).
pub(crate) fn displacement_stats(
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
