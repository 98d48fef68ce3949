//! One chunk of a Jacobi sweep, with the statistics a run asks for.

use beltrami_halfedge::{DVec3, VertexId};
use beltrami_weights::{FreshRows, Laplacian};

use super::rows::{RowSweep, sweep_fresh_rows, sweep_rows};

use super::{CurveRow, Role};

/// Which displacement statistics a sweep computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Want {
    /// None (the stuck count only).
    Nothing,
    /// The largest displacement (no square root per vertex, no gather).
    Max,
    /// Everything in [`StepStats`].
    Full,
}

/// [`SweepInput::chunk`] modes (a `const` parameter, so each is its own loop).
pub(super) const NOTHING: u8 = 0;
pub(super) const MAX: u8 = 1;
pub(super) const FULL: u8 = 2;

/// What one chunk of a sweep found.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Partial {
    /// The sum of the displacements in vertex order (`FULL`).
    pub(super) sum: f64,
    /// The largest displacement (`FULL`), or the largest one outside the plain range
    /// (`MAX`).
    pub(super) max: f64,
    /// The largest squared length of a displacement in the plain range (`MAX`).
    pub(super) max_squared: f64,
    pub(super) stuck: usize,
    /// The first vertex whose new position is not finite.
    pub(super) bad: Option<u32>,
    /// A row's fresh weights did not sum to a finite value: the sweep is to be redone
    /// through [`Laplacian::update`] (which reports the weight), and the rest of this
    /// chunk was not computed.
    pub(super) redo: bool,
}

/// Where a sweep's rows come from.
#[derive(Clone, Copy)]
pub(super) enum RowSource<'s> {
    /// The operator's stored weights and scales.
    Stored(&'s Laplacian),
    /// Weights computed row by row as the sweep goes (at the sweep's `old` positions).
    Fresh(&'s FreshRows<'s>),
}

impl RowSource<'_> {
    /// [`sweep_rows`] or [`sweep_fresh_rows`]; `None` when a fresh row sum is not finite.
    #[inline]
    fn sweep(
        self,
        first: usize,
        positions: &[DVec3],
        lambda: f64,
        out: &mut [DVec3],
    ) -> Option<RowSweep> {
        match self {
            Self::Stored(laplacian) => Some(sweep_rows(
                &laplacian.rows_without_unit_weights(),
                first,
                positions,
                lambda,
                out,
            )),
            Self::Fresh(rows) => sweep_fresh_rows(rows, first, positions, lambda, out),
        }
    }

    /// Whether row `v` is stuck (found finite by the sweep already).
    fn is_stuck(self, v: u32, positions: &[DVec3]) -> bool {
        match self {
            Self::Stored(laplacian) => laplacian.scale(VertexId::new(v)).is_none(),
            Self::Fresh(rows) => !matches!(rows.scale(v as usize, positions), Some(s) if s > 0.0),
        }
    }
}

/// What a sweep reads besides its rows.
pub(super) struct SweepInput<'s> {
    pub(super) roles: &'s [Role],
    pub(super) exceptions: &'s [u32],
    pub(super) curve: &'s [CurveRow],
    pub(super) old: &'s [DVec3],
    pub(super) lambda: f64,
}

impl SweepInput<'_> {
    /// Sweeps the rows `first..first + out.len()` of `source` into `out`, with the statistics of
    /// `MODE` (`NOTHING`, `MAX`, `FULL`); with `RECORD` (and `FULL`), also stores each
    /// vertex's displacement in `disp`.
    #[inline]
    pub(super) fn chunk<const MODE: u8, const RECORD: bool>(
        &self,
        source: RowSource<'_>,
        first: usize,
        out: &mut [DVec3],
        disp: &mut [f64],
    ) -> Partial {
        // Every row moves by its Laplacian row...
        let Some(swept) = source.sweep(first, self.old, self.lambda, out) else {
            return Partial {
                redo: true,
                ..Partial::default()
            };
        };
        self.put_right::<MODE, RECORD>(first, out, disp, swept, |v| source.is_stuck(v, self.old))
    }

    /// The rest of [`chunk`](Self::chunk) once the rows `first..first + out.len()` have
    /// moved by their Laplacian rows into `out` (`swept`, with `is_stuck` telling which
    /// rows were stuck): the vertices that do not move that way are put right, and the
    /// statistics of `MODE` computed.
    #[inline]
    pub(super) fn put_right<const MODE: u8, const RECORD: bool>(
        &self,
        first: usize,
        out: &mut [DVec3],
        disp: &mut [f64],
        swept: RowSweep,
        is_stuck: impl Fn(u32) -> bool,
    ) -> Partial {
        let Self {
            roles,
            exceptions,
            curve,
            old,
            lambda,
            ..
        } = *self;
        let rows = first..first + out.len();
        let RowSweep {
            mut stuck,
            sum: mut probe,
        } = swept;
        // The vertices that do not move by their row are put right. `probe` keeps
        // the value a row gave them: a spurious non-finite sum only costs a scan.
        let lo = exceptions.partition_point(|&v| (v as usize) < rows.start);
        let hi = exceptions.partition_point(|&v| (v as usize) < rows.end);
        let mut cursor = curve.partition_point(|r| (r.v as usize) < first);
        for &v in &exceptions[lo..hi] {
            let i = v as usize;
            if is_stuck(v) {
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
                    let d = beltrami_halfedge::geometry::distance(xi, new);
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
            redo: false,
        }
    }
}
