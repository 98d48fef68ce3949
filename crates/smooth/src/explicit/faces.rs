//! The cotangent step scattered triangle by triangle: each triangle's three cotangents
//! are computed once and added into the rows of its three vertices, which are finished
//! as soon as their last triangle has been added. No weight is stored, and no
//! cotangent is computed twice.

use beltrami_halfedge::geometry::DEGENERACY_RATIO;
use beltrami_halfedge::{DVec3, HalfedgeMesh};

use super::rows::RowSweep;
use super::scatter::{Decline, Finished, Order, P4, RINGS, arch, in_ring, ring_for};

/// A mesh's triangles in the order a sweep scatters them (vertex indices in face order,
/// rotated to start at the smallest): 12 bytes per triangle and 8 per vertex.
pub(super) type TriangleOrder = Order<3>;

impl Order<3> {
    /// The order of `triangles` (three vertex indices each, one after the other) over
    /// `n` vertices (indices below `n`): sorted by their smallest vertex (stable), or
    /// `None` when there are more than `u32` can count.
    pub(super) fn new(n: usize, triangles: &[u32]) -> Option<Self> {
        let corners = |c: &[u32]| -> [u32; 3] { [c[0], c[1], c[2]] };
        let triangles = || triangles.chunks_exact(3).map(corners);
        let count = triangles().len();
        u32::try_from(count).ok()?;
        let lowest = |t: &[u32; 3]| t[0].min(t[1]).min(t[2]) as usize;
        // A counting sort by the smallest vertex: stable, O(F + V).
        let mut starts = vec![0u32; n + 1];
        for t in triangles() {
            starts[lowest(&t) + 1] += 1;
        }
        for v in 1..=n {
            starts[v] += starts[v - 1];
        }
        let mut next = starts.clone();
        let mut sorted = vec![[0u32; 3]; count];
        for t in triangles() {
            let lo = lowest(&t);
            // Each triangle starts at its smallest vertex (its orientation kept), so the
            // cotangents' bits do not depend on which corner a face list starts at: the
            // mesh's faces and a detached triangle list give the same sweep.
            sorted[next[lo] as usize] = match t.iter().position(|&v| v as usize == lo) {
                Some(1) => [t[1], t[2], t[0]],
                Some(2) => [t[2], t[0], t[1]],
                _ => t,
            };
            next[lo] += 1;
        }
        Some(Self::grouped(sorted, starts))
    }

    /// The order of `mesh`'s faces, `None` when one is not a triangle (or there are more
    /// than `u32` can count).
    pub(super) fn of_mesh(mesh: &HalfedgeMesh) -> Option<Self> {
        let triangles: Option<Vec<[u32; 3]>> = mesh
            .faces()
            .map(|f| {
                let h0 = mesh.face_halfedge(f);
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                (mesh.next(h2) == h0).then(|| [h0, h1, h2].map(|h| mesh.to_vertex(h).raw()))
            })
            .collect();
        Self::new(mesh.n_vertices(), triangles?.as_flattened())
    }
}

/// Triangles whose cotangents are computed together, in lanes of arrays the compiler
/// vectorises.
const LANES: usize = 4;

/// Triangles whose cotangents are computed before they are scattered.
const BATCH: usize = 32;

/// The range of a triangle's longest squared edge length inside which
/// [`cotangent_lanes`] computes without rescaling: products of up to four coordinate
/// differences stay finite (up to 2^800), and for a triangle that is not degenerate
/// (whose shortest edge is then more than [`DEGENERACY_RATIO`] times its longest) they
/// stay normal, so the cotangents and the degeneracy test are the rescaled kernel's to
/// rounding. A shorter edge only occurs in a degenerate triangle, whose cotangents are 0
/// however its products round. Outside the range the sweep declines (see
/// [`cotangent_scale`]).
const PLAIN: std::ops::RangeInclusive<f64> = 3.872_591_914_849_318e-121..=2.582_249_878_086_908e120;

type Lanes = [f64; LANES];

/// The smallest and largest longest squared edge length of the triangles
/// [`cotangent_lanes`] has seen, lane by lane (tested once, at the end of a sweep: no
/// branch per triangle).
#[derive(Clone, Copy)]
struct Range {
    lo: Lanes,
    hi: Lanes,
}

impl Range {
    const EMPTY: Self = Self {
        lo: [f64::INFINITY; LANES],
        hi: [0.0; LANES],
    };

    /// Whether every triangle seen has its longest squared edge in [`PLAIN`] (false for
    /// NaN); true when none was seen (a range of rows without triangles: isolated
    /// vertices), so that where work units start, which follows the thread count,
    /// decides nothing.
    fn plain(&self) -> bool {
        if self.hi.iter().any(|h| h.is_nan()) {
            return false;
        }
        let lo = self.lo.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        let hi = self.hi.iter().fold(0.0_f64, |a, &b| a.max(b));
        lo > hi || (PLAIN.contains(&lo) && PLAIN.contains(&hi))
    }

    /// The reason to give for `decline`: [`Decline::Range`] when a triangle seen so far
    /// is outside [`PLAIN`] (an overflowed product makes a weight sum non-finite too).
    fn blame(&self, decline: Decline) -> Decline {
        if self.plain() {
            decline
        } else {
            Decline::Range
        }
    }
}

/// The cotangents of `LANES` triangles whose corners are `p[corner][coordinate][lane]`:
/// per lane `[c1, c2, c0]` with `cᵢ` the cotangent of the angle at corner `i` (the order
/// of the geometry's `triangle_cotangents_into`: opposite the edges ending at the first,
/// second and third corner), from one cross product per triangle,
/// `cot = (u · v) / |u × v|` with the triangle's `|u × v|` (twice its area) for all
/// three corners: one square root and one division per triangle where the geometry's
/// kernel takes one per corner. The values are the geometry's to rounding, and 0 where
/// the triangle is degenerate (twice its area at most [`DEGENERACY_RATIO`] times its
/// longest edge squared, the geometry's test). The squared edge lengths come from the
/// three corner products (`|s₁|² = s₁·s₂ − e·s₁` and so on round, as `s₂ = s₁ + e`);
/// the longest goes into `range`, which the caller tests against [`PLAIN`] once per
/// sweep. With `SCALED` the edge vectors are multiplied by `scale`, a power of two (see
/// [`cotangent_scale`]): every product then scales exactly and the cotangents keep
/// their bits.
///
/// Positions that are not finite give non-finite cotangents, which reach the rows'
/// weight sums: the sweep then declines (see [`Finished::row`]).
#[inline(always)]
fn cotangent_lanes<const SCALED: bool>(
    p: &[[Lanes; 3]; 3],
    scale: f64,
    range: &mut Range,
) -> [Lanes; 3] {
    // With `SCALED`, each difference times `scale` (exact: a power of two).
    let sub = |a: &[Lanes; 3], b: &[Lanes; 3]| -> [Lanes; 3] {
        std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let d = a[k][l] - b[k][l];
                if SCALED { d * scale } else { d }
            })
        })
    };
    let dot = |a: &[Lanes; 3], b: &[Lanes; 3]| -> Lanes {
        std::array::from_fn(|l| a[0][l] * b[0][l] + a[1][l] * b[1][l] + a[2][l] * b[2][l])
    };
    // The edges leaving each corner: at corner 0, s1 = p1 − p0 and s2 = p2 − p0; at
    // corner 1, e = p2 − p1 and −s1; at corner 2, −s2 and −e.
    let s1 = sub(&p[1], &p[0]);
    let s2 = sub(&p[2], &p[0]);
    let e = sub(&p[2], &p[1]);
    let cross: [Lanes; 3] = [
        std::array::from_fn(|l| s1[1][l] * s2[2][l] - s1[2][l] * s2[1][l]),
        std::array::from_fn(|l| s1[2][l] * s2[0][l] - s1[0][l] * s2[2][l]),
        std::array::from_fn(|l| s1[0][l] * s2[1][l] - s1[1][l] * s2[0][l]),
    ];
    let (twice_area, recip) = sqrt_and_reciprocal(dot(&cross, &cross));
    let (d0, d1, d2) = (dot(&s1, &s2), dot(&e, &s1), dot(&s2, &e));
    let (q1, q2, qe): (Lanes, Lanes, Lanes) = (
        std::array::from_fn(|l| d0[l] - d1[l]),
        std::array::from_fn(|l| d0[l] + d2[l]),
        std::array::from_fn(|l| d2[l] - d1[l]),
    );
    let longest: Lanes = std::array::from_fn(|l| q1[l].max(q2[l]).max(qe[l]));
    for (l, &longest) in longest.iter().enumerate() {
        range.lo[l] = range.lo[l].min(longest);
        // A NaN (an overflowed product, or a position that is not finite) sticks, so
        // the range is not plain.
        let hi = range.hi[l];
        range.hi[l] = if longest.is_nan() || longest > hi {
            longest
        } else {
            hi
        };
    }
    // `1 / |u × v|`, or +0 for a degenerate triangle: a select of bits, without a
    // branch per lane.
    let inv: Lanes = std::array::from_fn(|l| {
        let keep = u64::from(twice_area[l] > DEGENERACY_RATIO * longest[l]).wrapping_neg();
        f64::from_bits(recip[l].to_bits() & keep)
    });
    // Corner 0 (u = s1, v = s2), corner 1 (u = e, v = −s1), corner 2 (u = −s2, v = −e).
    [
        std::array::from_fn(|l| -d1[l] * inv[l]),
        std::array::from_fn(|l| d2[l] * inv[l]),
        std::array::from_fn(|l| d0[l] * inv[l]),
    ]
}

/// `(√q, 1 / √q)` lane by lane: where the processor has AVX2, one vector square root
/// and one vector division for the four lanes (written out because the compiler left
/// them scalar, each lane behind a branch: the cotangent scatter took 12 % longer on
/// the level-8 sphere); else lane by lane. The same operations, so the same bits.
#[inline(always)]
fn sqrt_and_reciprocal(q: Lanes) -> (Lanes, Lanes) {
    #[cfg(target_arch = "x86_64")]
    {
        // The tests' SSE2 runs take the lane-by-lane path, as the sweeps' dispatch does.
        #[cfg(test)]
        let wide = !super::scatter::tests::SSE2_ONLY.with(std::cell::Cell::get);
        #[cfg(not(test))]
        let wide = true;
        if let Some(simd) = pulp::x86::V3::try_new().filter(|_| wide) {
            use pulp::Simd;
            let s = simd.sqrt_f64s(pulp::bytemuck::cast(q));
            let r = simd.div_f64s(simd.splat_f64s(1.0), s);
            return (pulp::bytemuck::cast(s), pulp::bytemuck::cast(r));
        }
    }
    let s = q.map(f64::sqrt);
    (s, s.map(|x| 1.0 / x))
}

/// What a triangle sweep reads: the triangles, the positions, λ, and the power of two
/// the cotangents' corner positions are multiplied by (see [`cotangent_scale`]).
pub(super) struct Scatter<'a> {
    pub(super) sweep: &'a TriangleOrder,
    pub(super) positions: &'a [DVec3],
    pub(super) lambda: f64,
    /// `None`: the positions as they are.
    pub(super) scale: Option<f64>,
}

/// The power of two that brings the mesh's largest edge component (`|x_b − x_a|` over
/// the triangles' edges) into `[1, 2)`, for a mesh whose triangles leave [`PLAIN`]:
/// [`cotangent_lanes`] multiplies the edge vectors by it, and the cotangents from
/// `2^k (x_b − x_a)` are those from `x_b − x_a` bit for bit (every product scales by a
/// power of two, exactly, while it stays normal). So the sweep keeps its bits at any
/// scale where the differences are normal, wherever the mesh lies, the property the
/// gathered rows' kernel has by rescaling edge by edge. `None` when the largest
/// component is zero, not finite, or too far from 1 for a normal power of two.
pub(super) fn cotangent_scale(sweep: &TriangleOrder, positions: &[DVec3]) -> Option<f64> {
    let mut largest = 0.0_f64;
    for t in &sweep.elements {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        for d in [b - a, c - b, a - c] {
            if !d.is_finite() {
                return None;
            }
            largest = largest.max(d.abs().max_element());
        }
    }
    if largest == 0.0 {
        return None;
    }
    // The unbiased binary exponent of `largest` (a subnormal counts as -1023).
    let exponent = ((largest.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    let k = -exponent;
    // 2^k as a normal number.
    (-1022..=1023)
        .contains(&k)
        .then(|| f64::from_bits(((k + 1023) as u64) << 52))
}

/// One explicit step `x_i + λ (Σ_j w_ij x_j / Σ_j w_ij − x_i)` with cotangent weights
/// over the rows `first..first + out.len()`: each triangle's cotangents
/// ([`cotangent_lanes`]; the ½ of `w_ij` cancels) are added to its vertices' rows in
/// triangle order, starting at the triangles of `sweep.reach[first]`, so that every row
/// sums its terms in the same order whichever rows a call covers.
///
/// A row whose weights sum to zero or less (or whose reciprocal is not positive and
/// finite) is stuck: its vertex keeps its position and its index goes into `stuck`, in
/// row order. `unit` rows at a time (the last part may be shorter), the new positions'
/// sum and the stuck rows' count go into `swept`, one [`RowSweep`] per part.
///
/// [`Decline::Range`] when a triangle is too small or too large for plain products
/// ([`PLAIN`]) at `scatter.scale`, or a position is not finite (the caller may repeat
/// the sweep with a [`cotangent_scale`], which there is none for in the second case);
/// [`Decline::Weight`] when a row's weights do not sum to a finite value otherwise.
/// The caller then falls back to the gathered rows, which report any bad weight or
/// position. The rows of `out` are then unspecified.
///
/// # Panics
/// If `sweep.span` is above [`MAX_SPAN`](super::scatter::MAX_SPAN).
pub(super) fn sweep_triangles(
    scatter: &Scatter<'_>,
    first: usize,
    out: &mut [DVec3],
    unit: usize,
    stuck: &mut Vec<u32>,
    swept: &mut Vec<RowSweep>,
) -> Result<(), Decline> {
    // `Finished` is moved into the sweep, a local of its loop (see `edges`).
    let finished = Finished::new(
        first,
        scatter.positions,
        scatter.lambda,
        out,
        unit,
        stuck,
        swept,
    );
    let span = scatter.sweep.span;
    // The scale is a const parameter: the plain sweep multiplies by nothing.
    match (ring_for(span, BATCH), scatter.scale.is_some()) {
        (Some(0), false) => sweep_in_ring::<{ RINGS[0] }, false>(scatter, finished),
        (Some(1), false) => sweep_in_ring::<{ RINGS[1] }, false>(scatter, finished),
        (Some(2), false) => sweep_in_ring::<{ RINGS[2] }, false>(scatter, finished),
        (Some(3), false) => sweep_in_ring::<{ RINGS[3] }, false>(scatter, finished),
        (Some(4), false) => sweep_in_ring::<{ RINGS[4] }, false>(scatter, finished),
        (Some(0), true) => sweep_in_ring::<{ RINGS[0] }, true>(scatter, finished),
        (Some(1), true) => sweep_in_ring::<{ RINGS[1] }, true>(scatter, finished),
        (Some(2), true) => sweep_in_ring::<{ RINGS[2] }, true>(scatter, finished),
        (Some(3), true) => sweep_in_ring::<{ RINGS[3] }, true>(scatter, finished),
        (Some(4), true) => sweep_in_ring::<{ RINGS[4] }, true>(scatter, finished),
        _ => panic!("a span of {span} is above MAX_SPAN"),
    }
}

/// [`sweep_triangles`] with the open rows in a ring of `R` slots (`R` > the span, and
/// `R` > the span + [`BATCH`] where a ring that large exists), the corner positions
/// multiplied by `scatter.scale` when `SCALED`.
fn sweep_in_ring<const R: usize, const SCALED: bool>(
    scatter: &Scatter<'_>,
    finished: Finished<'_>,
) -> Result<(), Decline> {
    in_ring::<R>(scatter.sweep.span, |ring| {
        // Compiled for AVX2 where the processor has it (the same bits either way). The
        // closure is inlined into the dispatched function today; should it grow so that
        // it is not (a profile then shows `scatter_in_ring::{{closure}}` and calls to
        // `_mm256_*`: a run 7 times slower), a `pulp::WithSimd` type as the refresh's
        // brings the body back inside (measured 6 % slower than this closure now).
        arch().dispatch(|| scatter_in_ring::<R, SCALED>(scatter, finished, ring))
    })
}

/// The scatter of [`sweep_in_ring`] into `ring` (all zero); returns the first row it
/// did not finish (the end of the range), or why it declined (a row's weight sum not
/// finite, or an edge length outside [`PLAIN`]).
#[inline(always)]
fn scatter_in_ring<const R: usize, const SCALED: bool>(
    scatter: &Scatter<'_>,
    mut finished: Finished<'_>,
    ring: &mut [P4; R],
) -> Result<usize, Decline> {
    let Scatter {
        sweep,
        positions,
        scale,
        ..
    } = *scatter;
    let scale = scale.unwrap_or(1.0);
    let (first, end) = (finished.first, finished.end);
    let start = (sweep.reach[first] as usize).min(first);
    let (t_begin, t_end) = (sweep.starts[start] as usize, sweep.starts[end] as usize);
    let mut range = Range::EMPTY;
    // The next row to finish.
    let mut v = start;
    let tris = &sweep.elements[t_begin..t_end];
    let mut batches = tris.chunks(BATCH).peekable();
    while let Some(batch) = batches.next() {
        // The batch's cotangents, `LANES` triangles at a time (a short last step repeats
        // its last triangle).
        let mut cots = [[0.0; 3]; BATCH];
        for (group, out) in batch.chunks(LANES).zip(cots.chunks_mut(LANES)) {
            let k = group.len();
            let mut p = [[[0.0; LANES]; 3]; 3];
            for l in 0..LANES {
                let tri = &group[l.min(k - 1)];
                for c in 0..3 {
                    let q = positions[tri[c] as usize];
                    p[c][0][l] = q.x;
                    p[c][1][l] = q.y;
                    p[c][2][l] = q.z;
                }
            }
            let lanes = cotangent_lanes::<SCALED>(&p, scale, &mut range);
            for (l, o) in out.iter_mut().enumerate().take(k) {
                *o = [lanes[0][l], lanes[1][l], lanes[2][l]];
            }
        }
        // Rows whose triangles have all been added are complete: every row before the
        // batch's first smallest vertex (finished after the previous batch, but before
        // the first). The rows open while the batch is added then lie between that
        // vertex and the span past its last one; when they fit in the ring (unless the
        // batch crosses a run of vertices that start no triangle) the batch is added at
        // once, else triangle by triangle, finishing the rows before each triangle's
        // smallest vertex.
        let (first_lo, last_lo) = (batch[0][0] as usize, batch[batch.len() - 1][0] as usize);
        finished.rows_until(ring, &mut v, first_lo, |e| range.blame(e))?;
        // The angles at b (opposite the edge ending at a), at c and at a.
        let add = |ring: &mut [P4; R], tri: &[u32; 3], [at_b, at_c, at_a]: [f64; 3]| {
            let [a, b, c] = tri.map(|v| v as usize);
            let (pa, pb, pc) = (positions[a], positions[b], positions[c]);
            add2(&mut ring[a % R], at_c, pb, at_b, pc);
            add2(&mut ring[b % R], at_c, pa, at_a, pc);
            add2(&mut ring[c % R], at_b, pa, at_a, pb);
        };
        if last_lo - first_lo + sweep.span < R {
            debug_assert!(last_lo + sweep.span < v + R);
            for (tri, &cot) in batch.iter().zip(&cots) {
                add(ring, tri, cot);
            }
        } else {
            for (tri, &cot) in batch.iter().zip(&cots) {
                finished.rows_until(ring, &mut v, tri[0] as usize, |e| range.blame(e))?;
                debug_assert!(tri.iter().all(|&u| (u as usize) < v + R));
                add(ring, tri, cot);
            }
        }
        // The rows before the next batch's first smallest vertex are complete now.
        let next = batches.peek().map_or(end, |b| b[0][0] as usize);
        finished.rows_until(ring, &mut v, next, |e| range.blame(e))?;
    }
    finished.rows_until(ring, &mut v, end, |e| range.blame(e))?;
    if range.plain() {
        Ok(end)
    } else {
        Err(Decline::Range)
    }
}

/// `acc += wa · (pa, 1) + wb · (pb, 1)`, lane by lane (the two terms added one after
/// the other; the last lane adds the weights themselves).
#[inline(always)]
fn add2(acc: &mut P4, wa: f64, pa: DVec3, wb: f64, pb: DVec3) {
    use wide::f64x2;
    let (wa, wb) = (f64x2::splat(wa), f64x2::splat(wb));
    let lo = f64x2::new([acc[0], acc[1]])
        + wa * f64x2::new([pa.x, pa.y])
        + wb * f64x2::new([pb.x, pb.y]);
    let hi =
        f64x2::new([acc[2], acc[3]]) + wa * f64x2::new([pa.z, 1.0]) + wb * f64x2::new([pb.z, 1.0]);
    let [a0, a1] = lo.to_array();
    let [a2, a3] = hi.to_array();
    *acc = [a0, a1, a2, a3];
}

#[cfg(test)]
mod tests {
    use beltrami_halfedge::{DVec3, primitives};
    use beltrami_weights::{Cotangent, Laplacian, LaplacianOptions};

    use super::super::rows::tests::wobble;
    use super::super::scatter::tests::{
        assert_step_of, bits, cases, native_and_sse2, sweep_ranges,
    };
    use super::{Decline, Scatter, TriangleOrder, cotangent_scale, sweep_triangles};

    /// The sweep over the ranges between consecutive `cuts` in units of `unit` rows
    /// ([`sweep_ranges`]).
    fn sweep(
        order: &TriangleOrder,
        x: &[DVec3],
        scale: Option<f64>,
        cuts: &[usize],
        unit: usize,
    ) -> Result<(Vec<DVec3>, Vec<u32>), Decline> {
        let scatter = Scatter {
            sweep: order,
            positions: x,
            lambda: 0.8,
            scale,
        };
        sweep_ranges(x.len(), cuts, unit, |first, out, unit, stuck, swept| {
            sweep_triangles(&scatter, first, out, unit, stuck, swept)
        })
    }

    #[test]
    fn triangles_start_at_their_smallest_vertex_in_face_order() {
        let triangles = [[4, 2, 7], [0, 5, 1], [3, 6, 2], [2, 3, 1]];
        let order = TriangleOrder::new(8, triangles.as_flattened()).unwrap();
        // Rotated (orientation kept) and sorted by the smallest vertex, stably.
        assert_eq!(
            order.elements,
            vec![[0, 5, 1], [1, 2, 3], [2, 7, 4], [2, 3, 6]]
        );
        assert_eq!(order.starts, vec![0, 1, 2, 4, 4, 4, 4, 4, 4]);
        assert_eq!(order.span, 5);
        // The mesh's faces and its triangle list give the same order.
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let list: Vec<[u32; 3]> = sphere.faces.iter().map(|f| [f[1], f[2], f[0]]).collect();
        let a = TriangleOrder::of_mesh(&mesh).unwrap();
        let b = TriangleOrder::new(mesh.n_vertices(), list.as_flattened()).unwrap();
        assert_eq!(
            (&a.elements, &a.starts, &a.reach),
            (&b.elements, &b.starts, &b.reach)
        );
    }

    /// The scattered rows are the operator's (cotangent weights, weight-sum
    /// normalisation, negative weights kept) to rounding, with the same stuck rows, and
    /// the same bits wherever the rows are split into ranges and units.
    #[test]
    fn a_triangle_sweep_is_the_operator_to_rounding() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = TriangleOrder::of_mesh(&mesh).unwrap();
            let (out, stuck) = sweep(&order, &x, None, &[0, n], 256).unwrap();
            let lap = Laplacian::new(&mesh, &x, &Cotangent, LaplacianOptions::new()).unwrap();
            assert_step_of(&lap, &mesh, &x, &out, &stuck);
            for (cuts, unit) in [(vec![0, n / 3, n / 3, n - 1, n], 7), (vec![0, 1, n], 1)] {
                let (other, other_stuck) = sweep(&order, &x, None, &cuts, unit).unwrap();
                assert_eq!(bits(&other), bits(&out));
                assert_eq!(other_stuck, stuck);
            }
        }
    }

    /// Isolated vertices before the triangles' rows (as reordering puts them, and
    /// more of them than the ring holds), and ranges that hold only isolated rows: the
    /// rows get the bits they have without the isolated vertices, wherever the ranges
    /// are cut, and a range without triangles does not decline.
    #[test]
    fn isolated_vertices_change_no_row() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = TriangleOrder::of_mesh(&mesh).unwrap();
            let (want, want_stuck) = sweep(&order, &x, None, &[0, n], 64).unwrap();
            let gap = 3 * (1 << 16);
            let shifted: Vec<u32> = order
                .elements
                .iter()
                .flatten()
                .map(|&v| v + gap as u32)
                .collect();
            let wide = TriangleOrder::new(n + gap, &shifted).unwrap();
            assert_eq!(wide.span, order.span);
            let mut y = vec![DVec3::new(5.0, -3.0, 1.0); gap];
            y.extend_from_slice(&x);
            for cuts in [
                vec![0, n + gap],
                vec![0, gap / 2, gap + n / 2, n + gap],
                vec![0, gap, n + gap],
            ] {
                let (out, stuck) = sweep(&wide, &y, None, &cuts, 256).unwrap();
                assert_eq!(bits(&out[gap..]), bits(&want), "{cuts:?}");
                assert_eq!(&out[..gap], &y[..gap]);
                let isolated: Vec<u32> = (0..gap as u32).collect();
                let shifted_stuck: Vec<u32> = want_stuck.iter().map(|&v| v + gap as u32).collect();
                assert_eq!(stuck, [isolated, shifted_stuck].concat());
            }
            // And a run of isolated vertices in the middle of the numbering.
            let (half, gap) = (n as u32 / 2, 700);
            let moved = |v: u32| if v < half { v } else { v + gap };
            let split: Vec<u32> = order.elements.iter().flatten().map(|&v| moved(v)).collect();
            let wide = TriangleOrder::new(n + gap as usize, &split).unwrap();
            let mut y = x[..half as usize].to_vec();
            y.extend(std::iter::repeat_n(
                DVec3::new(5.0, -3.0, 1.0),
                gap as usize,
            ));
            y.extend_from_slice(&x[half as usize..]);
            let m = n + gap as usize;
            for cuts in [vec![0, m], vec![0, half as usize + 350, m]] {
                let (out, _) = sweep(&wide, &y, None, &cuts, 256).unwrap();
                let real: Vec<DVec3> = (0..n as u32).map(|v| out[moved(v) as usize]).collect();
                assert_eq!(bits(&real), bits(&want), "{cuts:?}");
            }
        }
    }

    /// A flat mesh far from the origin across its plane, with edges too short for plain
    /// products: the scaled sweep multiplies the edge vectors, not the positions (which
    /// would overflow), and gives the in-plane bits of the mesh at unit scale.
    #[test]
    fn a_flat_mesh_far_from_the_origin_is_scaled_by_its_edges() {
        let grid = primitives::grid(12, 9);
        let mesh = grid.mesh().unwrap();
        let x: Vec<DVec3> = wobble(&grid.positions, 0.3)
            .iter()
            .map(|p| DVec3::new(p.x, p.y, 0.0))
            .collect();
        let n = x.len();
        let order = TriangleOrder::of_mesh(&mesh).unwrap();
        let (unit, _) = sweep(&order, &x, None, &[0, n], 64).unwrap();
        let (s, z) = (2f64.powi(-300), 2f64.powi(900));
        let y: Vec<DVec3> = x.iter().map(|p| DVec3::new(p.x * s, p.y * s, z)).collect();
        assert_eq!(
            sweep(&order, &y, None, &[0, n], 64).err(),
            Some(Decline::Range)
        );
        let scale = cotangent_scale(&order, &y).unwrap();
        assert!(
            y.iter().any(|p| !(p.z * scale).is_finite()),
            "positions would overflow"
        );
        let (out, _) = sweep(&order, &y, Some(scale), &[0, n], 64).unwrap();
        for (p, q) in out.iter().zip(&unit) {
            assert_eq!(
                [p.x, p.y].map(f64::to_bits),
                [q.x * s, q.y * s].map(f64::to_bits)
            );
            assert!(
                (p.z - z).abs() <= 4.0 * f64::EPSILON * z,
                "{} against {z}",
                p.z
            );
        }
    }

    /// The sweep compiled for AVX2 (where the processor has it) has the bits of its SSE2
    /// version, at unit scale and scaled.
    #[test]
    fn the_bits_do_not_depend_on_the_vector_width() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = TriangleOrder::of_mesh(&mesh).unwrap();
            let (native, sse2) = native_and_sse2(|| sweep(&order, &x, None, &[0, n], 64).unwrap());
            assert_eq!(bits(&native.0), bits(&sse2.0));
            assert_eq!(native.1, sse2.1);
            let y: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(600)).collect();
            let scale = cotangent_scale(&order, &y);
            let (native, sse2) =
                native_and_sse2(|| sweep(&order, &y, scale, &[0, n / 2, n], 7).unwrap());
            assert_eq!(bits(&native.0), bits(&sse2.0));
            assert_eq!(native.1, sse2.1);
        }
    }

    /// Far from unit scale the plain products leave their range: the sweep declines,
    /// and on positions multiplied by [`cotangent_scale`] it gives the bits of the same
    /// mesh at unit scale times the power of two. A NaN position declines, and no scale
    /// is tried (the gathered rows then name it).
    #[test]
    fn a_scaled_sweep_has_the_bits_of_unit_scale() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = TriangleOrder::of_mesh(&mesh).unwrap();
            let (unit, stuck) = sweep(&order, &x, None, &[0, n], 64).unwrap();
            for k in [-700, -600, -250, 250, 600, 1000] {
                let s = 2f64.powi(k);
                let y: Vec<DVec3> = x.iter().map(|&p| p * s).collect();
                assert_eq!(
                    sweep(&order, &y, None, &[0, n], 64).err(),
                    Some(Decline::Range),
                    "{k}"
                );
                let scale = cotangent_scale(&order, &y).unwrap();
                assert_eq!(scale.to_bits() & ((1 << 52) - 1), 0, "a power of two");
                let (out, scaled_stuck) = sweep(&order, &y, Some(scale), &[0, n], 64).unwrap();
                let want: Vec<DVec3> = unit.iter().map(|&p| p * s).collect();
                assert_eq!(bits(&out), bits(&want), "2^{k}");
                assert_eq!(scaled_stuck, stuck);
            }
            let mut nan = x.clone();
            nan[n / 2].x = f64::NAN;
            assert_eq!(
                sweep(&order, &nan, None, &[0, n], 64).err(),
                Some(Decline::Range)
            );
            assert_eq!(cotangent_scale(&order, &nan), None);
        }
    }
}
