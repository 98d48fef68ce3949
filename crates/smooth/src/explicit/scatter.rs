//! What the scattered sweeps share ([`faces`](super::faces): cotangents triangle by
//! triangle; [`edges`](super::edges): inverse distances edge by edge). Each computes an
//! element's weights once and adds them into the rows of its vertices, which are kept
//! open in a ring of sums until their last element has been added; a finished row
//! becomes its vertex's new position at once. No weight is stored.
//!
//! The elements are sorted by their smallest vertex, and a sweep over the rows
//! `first..end` starts with the elements of the row its first row's earliest element
//! begins at (the order's `reach`), so every row sums its terms in the same order
//! whichever rows a call covers: the result does not depend on how the rows are split
//! into work units, so not on the thread count.

use beltrami_halfedge::DVec3;

use super::rows::RowSweep;

/// Elements (triangles or edges: `K` vertex indices each, the smallest first) in the
/// order a scattered sweep adds them: grouped by their smallest vertex, with where
/// each vertex's elements start and how far back a sweep of the rows from a vertex on
/// must begin. `4 K` bytes per element and 8 per vertex.
#[derive(Debug)]
pub(super) struct Order<const K: usize> {
    /// The elements, grouped by their smallest vertex (their first).
    pub(super) elements: Vec<[u32; K]>,
    /// `starts[v]..starts[v + 1]`: the elements whose smallest vertex is `v` (`n + 1`
    /// entries).
    pub(super) starts: Vec<u32>,
    /// `reach[v]`: the smallest vertex of the elements whose largest vertex is `v` or
    /// more (`v` when there is none). A sweep of the rows from `v` on starts with the
    /// elements of `reach[v]`: every element at a row `v` or later comes after it.
    pub(super) reach: Vec<u32>,
    /// The largest difference between an element's largest and smallest vertex index:
    /// while a sweep adds an element whose smallest vertex is `v` (every row before
    /// `v` finished), only the rows `v..=v + span` are open.
    pub(super) span: usize,
}

impl<const K: usize> Order<K> {
    /// The order of `elements` over `starts.len() − 1` vertices, each element starting
    /// at its smallest vertex and grouped by it as `starts` says.
    pub(super) fn grouped(elements: Vec<[u32; K]>, starts: Vec<u32>) -> Self {
        let n = starts.len() - 1;
        let mut reach: Vec<u32> = (0..n as u32).collect();
        let mut span = 0;
        for e in &elements {
            let (lo, hi) = (e[0], e.iter().copied().max().unwrap_or(e[0]));
            debug_assert!(e.iter().all(|&v| v >= lo), "the smallest vertex first");
            reach[hi as usize] = reach[hi as usize].min(lo);
            span = span.max((hi - lo) as usize);
        }
        for v in (0..n.saturating_sub(1)).rev() {
            reach[v] = reach[v].min(reach[v + 1]);
        }
        Self {
            elements,
            starts,
            reach,
            span,
        }
    }
}

/// A row's sums `(Σ w·x, Σ w·y, Σ w·z, Σ w)`: four lanes that two multiply-adds update
/// together (a point is widened to `(x, y, z, 1)`, so the same operation adds a weight
/// to the weight sum).
pub(super) type P4 = [f64; 4];

/// The ring sizes the sweeps are compiled for; a larger span (a mesh in an order far
/// from its neighbourhoods) is swept by gathered rows instead.
pub(super) const RINGS: [usize; 5] = [1 << 8, 1 << 10, 1 << 12, 1 << 14, 1 << 16];

/// The largest span (the largest difference between an element's largest and smallest
/// vertex index) a scattered sweep takes: the largest ring's.
pub(super) const MAX_SPAN: usize = RINGS[RINGS.len() - 1] - 1;

/// The ring a sweep of elements whose span is `span` keeps its open rows in (an index
/// into [`RINGS`]): the smallest with room for `batch` rows besides the span, so that
/// batches are added at once, else the smallest that holds the span (batches are then
/// added element by element); `None` above [`MAX_SPAN`].
pub(super) fn ring_for(span: usize, batch: usize) -> Option<usize> {
    RINGS
        .iter()
        .position(|&r| r > span + batch)
        .or_else(|| RINGS.iter().position(|&r| r > span))
}

/// Rows per work unit of a scattered sweep over `n` rows, a multiple of `unit` (the
/// statistics' chunk). A unit starts `span` rows back (the elements of those rows are
/// added again, to the rows of the unit), and each costs a task, so the rows are split
/// into as many units as there are threads times the largest of 4, 3, 2, 1 that leaves
/// each unit at least 8 spans and [`MIN_UNIT_ROWS`] rows long; into one unit per
/// thread when that is not possible but each would still be at least 2 spans long;
/// else into one. The rows' sums do not depend on where a unit starts, so neither does
/// the result.
pub(super) fn block_rows(unit: usize, span: usize, n: usize) -> usize {
    let threads = rayon::current_num_threads().max(1);
    let long = |rows: usize| rows >= 8 * span && rows >= MIN_UNIT_ROWS;
    let count = match (1..=4).rev().find(|&m| long(n / (threads * m))) {
        Some(m) => threads * m,
        None if n / threads >= 2 * span => threads,
        None => 1,
    };
    n.div_ceil(count).div_ceil(unit).max(1) * unit
}

/// The fewest rows [`block_rows`] gives a work unit when it gives each thread more than
/// one (a unit per thread may be shorter).
pub(super) const MIN_UNIT_ROWS: usize = 4096;

/// Why a scattered sweep gave up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Decline {
    /// An element's lengths (after the scale) are outside the range of its kernel's
    /// plain products: a triangle sweep may be repeated with a
    /// [`cotangent_scale`](super::faces::cotangent_scale).
    Range,
    /// A row's weights do not sum to a finite value.
    Weight,
}

thread_local! {
    /// The ring of open rows of [`in_ring`], kept for the thread's next call (zero
    /// between calls).
    static RING: std::cell::RefCell<Vec<P4>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The instruction set a scattered sweep is compiled for, chosen at run time: AVX2
/// (with FMA, which the sweeps do not use) where the processor has it, else plain
/// SSE2; AVX-512 where pulp's `x86-v4` feature is on, as in the workspace's test builds
/// (through `beltrami-halfedge`'s bench). The sweeps
/// do the same operations in the same order in any of them (no fused multiply-adds), so
/// their bits do not depend on it (tested against SSE2).
pub(super) fn arch() -> pulp::Arch {
    #[cfg(test)]
    if tests::SSE2_ONLY.with(std::cell::Cell::get) {
        return pulp::Arch::Scalar;
    }
    pulp::Arch::new()
}

/// Runs `scatter` on this thread's ring of `R` open rows (all zero), and leaves the
/// ring zero again: `scatter` returns the first row it did not finish, after which the
/// `span + 1` rows its elements reached are cleared (all of them when it declined).
pub(super) fn in_ring<const R: usize>(
    span: usize,
    scatter: impl FnOnce(&mut [P4; R]) -> Result<usize, Decline>,
) -> Result<(), Decline> {
    RING.with_borrow_mut(|ring| {
        ring.resize(R.max(ring.len()), [0.0; 4]);
        let ring: &mut [P4; R] = (&mut ring[..R])
            .try_into()
            .expect("the ring was just resized to at least R slots");
        let done = scatter(ring);
        match done {
            Ok(open_from) => {
                for v in open_from..open_from + span + 1 {
                    ring[v % R] = [0.0; 4];
                }
            }
            Err(_) => ring.fill([0.0; 4]),
        }
        done.map(|_| ())
    })
}

/// Where a scattered sweep over the rows `first..end` puts each finished row: the new
/// position `x_i + λ (Σ w x / Σ w − x_i)` into `out`, a stuck row's index into `stuck`,
/// and every `unit` rows (and at the end) the part's [`RowSweep`] into `swept`.
pub(super) struct Finished<'s> {
    pub(super) first: usize,
    pub(super) end: usize,
    pub(super) positions: &'s [DVec3],
    lambda: f64,
    out: &'s mut [DVec3],
    unit: usize,
    /// Rows left in the current part.
    left: usize,
    part: RowSweep,
    stuck: &'s mut Vec<u32>,
    swept: &'s mut Vec<RowSweep>,
}

impl<'s> Finished<'s> {
    /// The rows `first..first + out.len()` at `positions`, with step `lambda`, in parts
    /// of `unit` rows.
    pub(super) fn new(
        first: usize,
        positions: &'s [DVec3],
        lambda: f64,
        out: &'s mut [DVec3],
        unit: usize,
        stuck: &'s mut Vec<u32>,
        swept: &'s mut Vec<RowSweep>,
    ) -> Self {
        Self {
            first,
            end: first + out.len(),
            positions,
            lambda,
            out,
            unit,
            left: unit,
            part: RowSweep::default(),
            stuck,
            swept,
        }
    }

    /// Finishes the rows from `*v` up to `until` (exclusive) with their sums in `ring`,
    /// whose slots are left zero, and moves `*v` there; the first decline is mapped by
    /// `blame` (see [`row`](Self::row)).
    #[inline(always)]
    pub(super) fn rows_until<const R: usize>(
        &mut self,
        ring: &mut [P4; R],
        v: &mut usize,
        until: usize,
        blame: impl Fn(Decline) -> Decline,
    ) -> Result<(), Decline> {
        while *v < until {
            self.row(*v, std::mem::take(&mut ring[*v % R]))
                .map_err(&blame)?;
            *v += 1;
        }
        Ok(())
    }

    /// Row `v` with its sums `open`: nothing for a row before the range (its slot is
    /// only cleared), [`Decline::Weight`] when its weights do not sum to a finite value.
    /// A row whose weights sum to zero or less (or whose reciprocal is not positive and
    /// finite) is stuck: its vertex keeps its position.
    #[inline(always)]
    pub(super) fn row(&mut self, v: usize, open: P4) -> Result<(), Decline> {
        if v < self.first {
            return Ok(());
        }
        let weight = open[3];
        if !weight.is_finite() {
            return Err(Decline::Weight);
        }
        let xi = self.positions[v];
        let inv = 1.0 / weight;
        // The weight is finite: when it is positive so is its reciprocal, which is
        // then finite unless it overflowed.
        let new = if weight > 0.0 && inv < f64::INFINITY {
            let s = DVec3::new(open[0], open[1], open[2]);
            xi + (s * inv - xi) * self.lambda
        } else {
            self.stuck.push(v as u32);
            self.part.stuck += 1;
            xi
        };
        self.out[v - self.first] = new;
        self.part.sum += new;
        self.left -= 1;
        if self.left == 0 || v + 1 == self.end {
            self.swept.push(std::mem::take(&mut self.part));
            self.left = self.unit;
        }
        Ok(())
    }
}

#[cfg(test)]
pub(super) mod tests {
    thread_local! {
        /// [`arch`](super::arch) gives plain SSE2 on this thread while set.
        pub(in super::super) static SSE2_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    }

    /// `f` run with the sweeps compiled for AVX2 (where the processor has it), then for
    /// SSE2 alone.
    /// The override is per thread: `f` must sweep on the calling thread.
    pub(in super::super) fn native_and_sse2<T>(f: impl Fn() -> T) -> (T, T) {
        /// Clears the override when dropped, also when `f` panics.
        struct Reset;
        impl Drop for Reset {
            fn drop(&mut self) {
                SSE2_ONLY.with(|c| c.set(false));
            }
        }
        let native = f();
        SSE2_ONLY.with(|c| c.set(true));
        let reset = Reset;
        let sse2 = f();
        drop(reset);
        (native, sse2)
    }

    /// The ring has room for a batch besides the span where one that large exists, and
    /// holds the span up to the largest.
    #[test]
    fn rings_hold_the_span_and_a_batch_where_they_can() {
        use super::{MAX_SPAN, RINGS, ring_for};
        assert_eq!(ring_for(0, 32), Some(0));
        assert_eq!(ring_for(223, 32), Some(0));
        assert_eq!(ring_for(224, 32), Some(1));
        assert_eq!(ring_for(MAX_SPAN - 32, 32), Some(RINGS.len() - 1));
        assert_eq!(ring_for(MAX_SPAN, 32), Some(RINGS.len() - 1));
        assert_eq!(ring_for(MAX_SPAN + 1, 32), None);
    }

    /// On two threads: units of a multiple of the threads while they stay 8 spans and
    /// `MIN_UNIT_ROWS` long, one per thread while 2 spans long, else one; whole
    /// statistics' chunks.
    #[test]
    fn units_share_the_rows_among_the_threads() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| {
            use super::{MIN_UNIT_ROWS, block_rows};
            // The level-8 sphere and the golf ball, reordered: four units a thread.
            assert_eq!(block_rows(1, 1282, 655_362), 655_362_usize.div_ceil(8));
            assert_eq!(block_rows(1, 446, 79_212), 79_212_usize.div_ceil(8));
            // In statistics' chunks of 4096 rows.
            assert_eq!(block_rows(4096, 446, 79_212), 3 * 4096);
            // Short units: one a thread (the F-lens), while each is 2 spans long.
            assert_eq!(block_rows(1, 69, 2244), 1122);
            assert_eq!(
                block_rows(1, 8 * MIN_UNIT_ROWS, 4 * MIN_UNIT_ROWS),
                4 * MIN_UNIT_ROWS
            );
            assert_eq!(
                block_rows(1, MIN_UNIT_ROWS, 4 * MIN_UNIT_ROWS),
                2 * MIN_UNIT_ROWS
            );
            // Three units a thread where four would be too short.
            assert_eq!(block_rows(1, 100, 6 * MIN_UNIT_ROWS), MIN_UNIT_ROWS);
        });
    }

    use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
    use beltrami_weights::Laplacian;

    use super::super::rows::RowSweep;
    use super::super::rows::tests::wobble;
    use super::Decline;

    /// `out` is the explicit step `x + 0.8 L x` of `lap` at `x` to 1e-14 per
    /// coordinate (a stuck row's vertex kept), and `stuck` its stuck rows in order.
    pub(in super::super) fn assert_step_of(
        lap: &Laplacian,
        mesh: &HalfedgeMesh,
        x: &[DVec3],
        out: &[DVec3],
        stuck: &[u32],
    ) {
        let mut want_stuck = Vec::new();
        for v in mesh.vertices() {
            let i = v.index();
            let want = match lap.laplacian_at(v, x) {
                Some(l) => x[i] + l * 0.8,
                None => {
                    want_stuck.push(i as u32);
                    x[i]
                }
            };
            let d = (out[i] - want).abs().max_element();
            assert!(d <= 1e-14, "row {i}: {d:e}");
        }
        assert_eq!(stuck, want_stuck);
        assert_eq!(stuck.len(), lap.stuck_rows());
    }

    /// A grid, the same grid with two coincident vertices (degenerate triangles), a
    /// noisy sphere, a torus.
    pub(in super::super) fn cases() -> Vec<(HalfedgeMesh, Vec<DVec3>)> {
        let grid = primitives::grid(12, 9);
        let sphere = primitives::icosphere(3);
        let torus = primitives::torus(2.0, 0.7, 13, 7);
        let mut coincident = wobble(&grid.positions, 0.4);
        coincident[14] = coincident[15];
        vec![
            (grid.mesh().unwrap(), wobble(&grid.positions, 0.4)),
            (grid.mesh().unwrap(), coincident),
            (sphere.mesh().unwrap(), wobble(&sphere.positions, 0.05)),
            (torus.mesh().unwrap(), torus.positions.clone()),
        ]
    }

    pub(in super::super) fn bits(p: &[DVec3]) -> Vec<[u64; 3]> {
        p.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
    }

    /// A scattered sweep `sweep(first, out, unit, stuck, swept)` of `n` rows over the
    /// ranges between consecutive `cuts` (rows split anywhere) in units of `unit` rows:
    /// the new positions and the stuck rows (the per-unit counts checked against them
    /// and the parts counted).
    pub(in super::super) fn sweep_ranges(
        n: usize,
        cuts: &[usize],
        unit: usize,
        sweep: impl Fn(
            usize,
            &mut [DVec3],
            usize,
            &mut Vec<u32>,
            &mut Vec<RowSweep>,
        ) -> Result<(), Decline>,
    ) -> Result<(Vec<DVec3>, Vec<u32>), Decline> {
        let mut out = vec![DVec3::splat(f64::NAN); n];
        let mut stuck = Vec::new();
        let mut counted = 0;
        for range in cuts.windows(2).map(|c| c[0]..c[1]) {
            let mut swept = Vec::new();
            sweep(
                range.start,
                &mut out[range.clone()],
                unit,
                &mut stuck,
                &mut swept,
            )?;
            assert_eq!(swept.len(), range.len().div_ceil(unit));
            counted += swept.iter().map(|s| s.stuck).sum::<usize>();
        }
        assert_eq!(counted, stuck.len());
        Ok((out, stuck))
    }
}
