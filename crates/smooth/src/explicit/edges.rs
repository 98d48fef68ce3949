//! The inverse-distance step scattered edge by edge: each edge's weight
//! `1 / (|x_j − x_i| + ε)` is computed once and added into the rows of both its
//! vertices, where the gathered rows compute it from each end (one square root and
//! one division per edge instead of two). No weight is stored.

use beltrami_halfedge::DVec3;
use beltrami_weights::DISTANCE_EPSILON;

use super::rows::RowSweep;
use super::scatter::{Decline, Finished, Order, P4, RINGS, arch, in_ring, ring_for};

/// A mesh's edges `[i, j]`, `i < j`, in the order a sweep scatters them: 8 bytes per
/// edge and 8 per vertex.
pub(super) type EdgeOrder = Order<2>;

impl Order<2> {
    /// The edges of the rows `neighbours(v)` for `v` in `0..n` (each neighbour list
    /// holds every edge of its vertex once, as an operator's rows do), grouped by their
    /// smaller vertex in the order of its row, or `None` when there are more than `u32`
    /// can count.
    pub(super) fn new<'a>(n: usize, neighbours: impl Fn(usize) -> &'a [u32]) -> Option<Self> {
        let mut starts = Vec::with_capacity(n + 1);
        let mut edges = Vec::new();
        for v in 0..n {
            starts.push(u32::try_from(edges.len()).ok()?);
            edges.extend(
                neighbours(v)
                    .iter()
                    .filter(|&&j| j as usize > v)
                    .map(|&j| [v as u32, j]),
            );
        }
        starts.push(u32::try_from(edges.len()).ok()?);
        Some(Self::grouped(edges, starts))
    }
}

/// What an edge sweep reads: the edges, the positions and λ.
pub(super) struct EdgeScatter<'a> {
    pub(super) sweep: &'a EdgeOrder,
    pub(super) positions: &'a [DVec3],
    pub(super) lambda: f64,
}

/// One explicit step `x_i + λ (Σ_j w_ij x_j / Σ_j w_ij − x_i)` with inverse-distance
/// weights `w_ij = 1 / (|x_j − x_i| + ε)` over the rows `first..first + out.len()`:
/// each edge's weight (the bits of the gathered rows' weight, from either end) is
/// added to both its vertices' rows, vertex by vertex in edge order, starting at the
/// edges of `sweep.reach[first]`, so that every row sums its terms in the same order
/// whichever rows a call covers. A row sums the edges to smaller vertices first (in
/// their order), then its own.
///
/// Stuck rows, `stuck` and `swept` as in
/// [`sweep_triangles`](super::faces::sweep_triangles).
///
/// [`Decline::Range`] when an edge's plain length is not finite (too long for plain
/// products, or a position that is not finite); [`Decline::Weight`] when a row's
/// weights do not sum to a finite value. The caller then falls back to the gathered
/// rows, which compute such lengths exactly and report any bad weight or position. The
/// rows of `out` are then unspecified.
///
/// # Panics
/// If `sweep.span` is above [`MAX_SPAN`](super::scatter::MAX_SPAN).
pub(super) fn sweep_edges(
    scatter: &EdgeScatter<'_>,
    first: usize,
    out: &mut [DVec3],
    unit: usize,
    stuck: &mut Vec<u32>,
    swept: &mut Vec<RowSweep>,
) -> Result<(), Decline> {
    let span = scatter.sweep.span;
    // `Finished` is made inside the sweep, a local of its loop: its sums and counters
    // then stay in registers (through a reference they went to memory every row).
    let finished = Finished::new(
        first,
        scatter.positions,
        scatter.lambda,
        out,
        unit,
        stuck,
        swept,
    );
    // A ring with room for a batch's rows besides the span: batches are then added at
    // once.
    // Compiled for AVX2 where the processor has it (the same bits either way).
    let arch = arch();
    match ring_for(span, BATCH) {
        Some(0) => in_ring::<{ RINGS[0] }>(span, |ring| {
            arch.dispatch(|| scatter_edges(scatter, finished, ring))
        }),
        Some(1) => in_ring::<{ RINGS[1] }>(span, |ring| {
            arch.dispatch(|| scatter_edges(scatter, finished, ring))
        }),
        Some(2) => in_ring::<{ RINGS[2] }>(span, |ring| {
            arch.dispatch(|| scatter_edges(scatter, finished, ring))
        }),
        Some(3) => in_ring::<{ RINGS[3] }>(span, |ring| {
            arch.dispatch(|| scatter_edges(scatter, finished, ring))
        }),
        Some(4) => in_ring::<{ RINGS[4] }>(span, |ring| {
            arch.dispatch(|| scatter_edges(scatter, finished, ring))
        }),
        _ => panic!("a span of {span} is above MAX_SPAN"),
    }
}

/// Edges whose weights are computed together before they are scattered.
const BATCH: usize = 32;

/// `(p, 1)`: a point widened so that the operation adding `w · p` to a row's sums adds
/// `w` to its weight sum.
#[inline(always)]
fn widen(p: DVec3) -> P4 {
    [p.x, p.y, p.z, 1.0]
}

/// `a + b`, lane by lane.
#[inline(always)]
fn sum(a: P4, b: P4) -> P4 {
    std::array::from_fn(|l| a[l] + b[l])
}

/// `w · a`, lane by lane.
#[inline(always)]
fn times(w: f64, a: P4) -> P4 {
    a.map(|x| w * x)
}

/// The reason to give for a decline: [`Decline::Range`] once a length was not finite
/// (an overflowed square makes a weight sum non-finite too).
#[inline(always)]
fn blame(finite: bool) -> impl Fn(Decline) -> Decline {
    move |e| if finite { e } else { Decline::Range }
}

/// The scatter of [`sweep_edges`] into `ring` (all zero, `R` > the span); returns the
/// first row it did not finish (the end of the range), or why it declined.
#[inline(always)]
fn scatter_edges<const R: usize>(
    scatter: &EdgeScatter<'_>,
    mut finished: Finished<'_>,
    ring: &mut [P4; R],
) -> Result<usize, Decline> {
    let EdgeScatter {
        sweep, positions, ..
    } = *scatter;
    let (first, end) = (finished.first, finished.end);
    let start = (sweep.reach[first] as usize).min(first);
    // Every plain length so far was finite (NaN fails).
    let mut finite = true;
    let edges = &sweep.elements[sweep.starts[start] as usize..sweep.starts[end] as usize];
    // The next row to finish.
    let mut v = start;
    let mut batches = edges.chunks(BATCH).peekable();
    while let Some(batch) = batches.next() {
        // The batch's weights, four edges at a time: the squared lengths in registers,
        // then their square roots and divisions together, in as many lanes as the
        // vector registers hold (edges past a short batch's end repeat its last, and
        // their weights are unused). The distance is the geometry's plain length
        // `sqrt(dx² + dy² + dz²)` of `x_j − x_u` (the negation of `x_u − x_j`: the same
        // squares, so the same bits from either end). A length below the plain range
        // gives the weight 1/ε exactly, as the exact length does (both are far below
        // ε's last bit); an infinite one declines. Whether every squared length is
        // finite is tested in lanes: `0 · q` is 0 for a finite `q`, NaN for an infinite
        // or NaN one.
        let last = batch.len() - 1;
        let mut w = [0.0; BATCH];
        let mut z = [0.0; 4];
        for g in 0..BATCH / 4 {
            let q: [f64; 4] = std::array::from_fn(|l| {
                let [u, j] = batch[(4 * g + l).min(last)];
                let (xu, xj) = (positions[u as usize], positions[j as usize]);
                let (dx, dy, dz) = (xj.x - xu.x, xj.y - xu.y, xj.z - xu.z);
                dx * dx + dy * dy + dz * dz
            });
            for l in 0..4 {
                z[l] += q[l] * 0.0;
                w[4 * g + l] = 1.0 / (q[l].sqrt() + DISTANCE_EPSILON);
            }
        }
        finite &= z.iter().all(|&z| z == 0.0);
        // Rows whose edges have all been added are complete: every row before the
        // batch's first smaller vertex (finished after the previous batch, but before
        // the first). The rows open while the batch is added then lie between that
        // vertex and the span past its last one; when they fit in the ring (unless the
        // batch crosses a run of vertices without edges to higher ones, such as
        // isolated vertices) the batch is added at once, else edge by edge, finishing
        // the rows before each edge's smaller vertex.
        let (first_u, last_u) = (batch[0][0] as usize, batch[last][0] as usize);
        finished.rows_until(ring, &mut v, first_u, blame(finite))?;
        if last_u - first_u + sweep.span < R {
            debug_assert!(last_u + sweep.span < v + R);
            // The row of the smaller vertex is summed in registers while its edges
            // follow one another, and stored when the next vertex's edges begin: the
            // same additions in the same order, without a store and a load of the
            // same slot between two of them. Its edges' other ends are larger and
            // within the span (so in other slots).
            let mut at = first_u;
            let mut open = ring[at % R];
            let mut xu = widen(positions[at]);
            for (&[u, j], &w) in batch.iter().zip(&w) {
                let (u, j) = (u as usize, j as usize);
                if u != at {
                    ring[at % R] = open;
                    at = u;
                    open = ring[at % R];
                    xu = widen(positions[u]);
                }
                open = sum(open, times(w, widen(positions[j])));
                let larger = &mut ring[j % R];
                *larger = sum(*larger, times(w, xu));
            }
            ring[at % R] = open;
        } else {
            for (&[u, j], &w) in batch.iter().zip(&w) {
                let (u, j) = (u as usize, j as usize);
                finished.rows_until(ring, &mut v, u, blame(finite))?;
                ring[u % R] = sum(ring[u % R], times(w, widen(positions[j])));
                ring[j % R] = sum(ring[j % R], times(w, widen(positions[u])));
            }
        }
        // The rows before the next batch's first smaller vertex are complete now.
        let next = batches.peek().map_or(end, |b| b[0][0] as usize);
        finished.rows_until(ring, &mut v, next, blame(finite))?;
    }
    finished.rows_until(ring, &mut v, end, blame(finite))?;
    if finite { Ok(end) } else { Err(Decline::Range) }
}

#[cfg(test)]
mod tests {
    use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId, primitives};
    use beltrami_weights::{InverseDistance, Laplacian, LaplacianOptions};

    use super::super::rows::tests::wobble;
    use super::super::scatter::tests::{assert_step_of, bits, native_and_sse2, sweep_ranges};
    use super::{Decline, EdgeOrder, EdgeScatter, sweep_edges};

    /// The triangle sweep's cases and a cube of quads.
    fn cases() -> Vec<(HalfedgeMesh, Vec<DVec3>)> {
        let quads = primitives::cube_quads();
        let mut cases = super::super::scatter::tests::cases();
        cases.push((quads.mesh().unwrap(), wobble(&quads.positions, 0.1)));
        cases
    }

    fn order_of(mesh: &HalfedgeMesh, x: &[DVec3]) -> EdgeOrder {
        let lap = Laplacian::new(mesh, x, &InverseDistance, LaplacianOptions::new()).unwrap();
        EdgeOrder::new(mesh.n_vertices(), |v| {
            lap.neighbours(VertexId::new(v as u32))
        })
        .unwrap()
    }

    /// The sweep over the ranges between consecutive `cuts` in units of `unit` rows
    /// ([`sweep_ranges`]).
    fn sweep(
        order: &EdgeOrder,
        x: &[DVec3],
        cuts: &[usize],
        unit: usize,
    ) -> Result<(Vec<DVec3>, Vec<u32>), Decline> {
        let scatter = EdgeScatter {
            sweep: order,
            positions: x,
            lambda: 0.8,
        };
        sweep_ranges(x.len(), cuts, unit, |first, out, unit, stuck, swept| {
            sweep_edges(&scatter, first, out, unit, stuck, swept)
        })
    }

    #[test]
    fn edges_are_grouped_by_their_smaller_vertex_in_row_order() {
        let rows: [&[u32]; 5] = [&[3, 1], &[0, 4, 2], &[1], &[0], &[1]];
        let order = EdgeOrder::new(5, |v| rows[v]).unwrap();
        assert_eq!(order.elements, vec![[0, 3], [0, 1], [1, 4], [1, 2]]);
        assert_eq!(order.starts, vec![0, 2, 4, 4, 4, 4]);
        // Row 1 is reached by the edges of row 0; rows 3 and 4 by row 0's and row 1's.
        assert_eq!(order.reach, vec![0, 0, 0, 0, 1]);
        assert_eq!(order.span, 3);
        // Every edge of a mesh once.
        for (mesh, x) in cases() {
            assert_eq!(order_of(&mesh, &x).elements.len(), mesh.n_edges());
        }
    }

    /// The scattered rows are the operator's (inverse-distance weights, weight-sum
    /// normalisation) to rounding, with the same stuck rows, and the same bits wherever
    /// the rows are split into ranges and units.
    #[test]
    fn an_edge_sweep_is_the_operator_to_rounding() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = order_of(&mesh, &x);
            let (out, stuck) = sweep(&order, &x, &[0, n], 256).unwrap();
            let lap = Laplacian::new(&mesh, &x, &InverseDistance, LaplacianOptions::new()).unwrap();
            assert_step_of(&lap, &mesh, &x, &out, &stuck);
            for (cuts, unit) in [(vec![0, n / 3, n / 3, n - 1, n], 7), (vec![0, 1, n], 1)] {
                let (other, other_stuck) = sweep(&order, &x, &cuts, unit).unwrap();
                assert_eq!(bits(&other), bits(&out));
                assert_eq!(other_stuck, stuck);
            }
        }
    }

    /// The sweep compiled for AVX2 (where the processor has it) has the bits of its SSE2
    /// version, split into ranges and units or not.
    #[test]
    fn the_bits_do_not_depend_on_the_vector_width() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = order_of(&mesh, &x);
            for (cuts, unit) in [(vec![0, n], 64), (vec![0, n / 3, n - 1, n], 7)] {
                let (native, sse2) = native_and_sse2(|| sweep(&order, &x, &cuts, unit).unwrap());
                assert_eq!(bits(&native.0), bits(&sse2.0));
                assert_eq!(native.1, sse2.1);
            }
        }
    }

    /// Isolated vertices before the edges' rows (more of them than the ring holds) and
    /// amid the numbering: the rows get the bits they have without them, wherever the
    /// ranges are cut; an isolated row is stuck.
    #[test]
    fn isolated_vertices_change_no_row() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = order_of(&mesh, &x);
            let (want, want_stuck) = sweep(&order, &x, &[0, n], 64).unwrap();
            let gap = 3 * (1 << 16);
            let rows: Vec<Vec<u32>> = (0..n)
                .map(|v| {
                    let s = order.starts[v] as usize..order.starts[v + 1] as usize;
                    order.elements[s]
                        .iter()
                        .map(|e| e[1] + gap as u32)
                        .collect()
                })
                .collect();
            let wide = EdgeOrder::new(
                n + gap,
                |v| {
                    if v < gap { &[][..] } else { &rows[v - gap][..] }
                },
            )
            .unwrap();
            assert_eq!(wide.span, order.span);
            let mut y = vec![DVec3::new(5.0, -3.0, 1.0); gap];
            y.extend_from_slice(&x);
            for cuts in [
                vec![0, n + gap],
                vec![0, gap / 2, gap + n / 2, n + gap],
                vec![0, gap, n + gap],
            ] {
                let (out, stuck) = sweep(&wide, &y, &cuts, 256).unwrap();
                assert_eq!(bits(&out[gap..]), bits(&want), "{cuts:?}");
                assert_eq!(&out[..gap], &y[..gap]);
                let isolated: Vec<u32> = (0..gap as u32).collect();
                let shifted: Vec<u32> = want_stuck.iter().map(|&v| v + gap as u32).collect();
                assert_eq!(stuck, [isolated, shifted].concat());
            }
            // And a run of isolated vertices in the middle of the numbering, longer than
            // the ring.
            let (half, gap) = (n as u32 / 2, 700);
            let moved = |v: u32| if v < half { v } else { v + gap };
            let mut rows: Vec<Vec<u32>> = vec![Vec::new(); n + gap as usize];
            for v in 0..n {
                let s = order.starts[v] as usize..order.starts[v + 1] as usize;
                rows[moved(v as u32) as usize] =
                    order.elements[s].iter().map(|e| moved(e[1])).collect();
            }
            let split = EdgeOrder::new(rows.len(), |v| &rows[v][..]).unwrap();
            let mut y = x[..half as usize].to_vec();
            y.extend(std::iter::repeat_n(
                DVec3::new(5.0, -3.0, 1.0),
                gap as usize,
            ));
            y.extend_from_slice(&x[half as usize..]);
            let m = n + gap as usize;
            for cuts in [vec![0, m], vec![0, half as usize + 350, m]] {
                let (out, _) = sweep(&split, &y, &cuts, 256).unwrap();
                let real: Vec<DVec3> = (0..n as u32).map(|v| out[moved(v) as usize]).collect();
                assert_eq!(bits(&real), bits(&want), "{cuts:?}");
            }
        }
    }

    /// Edges below the plain range keep to the sweep (their weight is 1/ε, as the exact
    /// length gives); lengths whose squares overflow, and a NaN position, decline.
    #[test]
    fn the_sweep_declines_only_where_a_length_is_not_plain() {
        for (mesh, x) in cases() {
            let n = mesh.n_vertices();
            let order = order_of(&mesh, &x);
            let tiny: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(-700)).collect();
            let (out, _) = sweep(&order, &tiny, &[0, n], 64).unwrap();
            let lap =
                Laplacian::new(&mesh, &tiny, &InverseDistance, LaplacianOptions::new()).unwrap();
            for v in mesh.vertices() {
                let i = v.index();
                let want = lap
                    .laplacian_at(v, &tiny)
                    .map_or(tiny[i], |l| tiny[i] + l * 0.8);
                let d = (out[i] - want).abs().max_element();
                assert!(d <= 1e-14 * 2f64.powi(-700), "row {i}: {d:e}");
            }
            let huge: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(600)).collect();
            assert_eq!(
                sweep(&order, &huge, &[0, n], 64).err(),
                Some(Decline::Range)
            );
            // A NaN in the middle, and at the last vertex (the last row finished).
            for at in [n / 2, n - 1] {
                let mut nan = x.clone();
                nan[at].x = f64::NAN;
                assert_eq!(sweep(&order, &nan, &[0, n], 64).err(), Some(Decline::Range));
            }
        }
    }
}
