//! The rows of one explicit step, `x_i + λ L x_i`, straight from the operator's
//! compressed rows: one tight pass per normalisation and weight kind.

use beltrami_halfedge::DVec3;
use beltrami_weights::{FreshRows, LaplacianRows, Normalization};
use wide::f64x2;

/// What [`sweep_rows`] found besides the new positions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct RowSweep {
    /// The rows of the range that are stuck (their vertex kept its position).
    pub(super) stuck: usize,
    /// The sum of the new positions, in row order: finite when every new position is
    /// (a cheap test; a non-finite sum can also come from overflow, so a caller that
    /// sees one looks at the positions themselves).
    pub(super) sum: DVec3,
}

/// One explicit diffusion step over the rows `first..first + out.len()`: writes
/// `out[k] = x_i + λ · L x_i` for `i = first + k`, with `L x_i` exactly as
/// [`Laplacian::laplacian_at`](beltrami_weights::Laplacian::laplacian_at) computes it and `x_i + (L x_i) · λ` rounded
/// coordinate by coordinate (the bits of the `DVec3` expression), or `x_i` for a
/// stuck row. `positions` are read, never written (a Jacobi step).
///
/// This is the explicit smoother's inner loop: one tight pass per normalisation and
/// weight kind, with every row treated alike (a caller whose vertices do not all
/// move overwrites those afterwards; `RowSweep::stuck` counts every stuck row in
/// the range).
///
/// # Panics
/// If the rows reach past the last row or `positions` is shorter than the mesh's
/// vertex count.
pub(super) fn sweep_rows(
    rows: &LaplacianRows<'_>,
    first: usize,
    positions: &[DVec3],
    lambda: f64,
    out: &mut [DVec3],
) -> RowSweep {
    let area = matches!(rows.normalization, Normalization::Area(_));
    match (area, rows.unit_weights) {
        (false, true) => sweep_rows_as::<false, true>(rows, first, positions, lambda, out),
        (false, false) => sweep_rows_as::<false, false>(rows, first, positions, lambda, out),
        (true, true) => sweep_rows_as::<true, true>(rows, first, positions, lambda, out),
        (true, false) => sweep_rows_as::<true, false>(rows, first, positions, lambda, out),
    }
}

/// [`sweep_rows`] for one normalisation (`AREA`) and weight kind
/// (`UNIT`: every weight is 1 and none is read). Few values live across the row loop,
/// so that they stay in registers; the row's slots are one running offset.
#[inline(always)]
fn sweep_rows_as<const AREA: bool, const UNIT: bool>(
    rows: &LaplacianRows<'_>,
    first: usize,
    positions: &[DVec3],
    lambda: f64,
    out: &mut [DVec3],
) -> RowSweep {
    let n = out.len();
    let bounds = &rows.offsets[first..=first + n];
    let slots = bounds[0] as usize..bounds[n] as usize;
    let block = Block {
        bounds,
        neighbours: &rows.neighbours[slots.clone()],
        weights: if UNIT { &[][..] } else { &rows.weights[slots] },
        scales: &rows.scales[first..first + n],
        first,
    };
    let mut swept = RowSweep::default();
    sweep_block::<AREA, UNIT>(&block, positions, lambda, out, &mut swept);
    swept
}

/// Consecutive rows with their weights and scales: `bounds` are the rows' offsets
/// (`n + 1` of them, the first at `neighbours[0]` and `weights[0]`; `weights` is empty
/// for unit weights), the first row is `first`.
struct Block<'b> {
    bounds: &'b [u32],
    neighbours: &'b [u32],
    weights: &'b [f64],
    scales: &'b [f64],
    first: usize,
}

/// The loop of [`sweep_rows_as`] over one [`Block`], adding its stuck rows and new
/// positions to `swept`. Few values live across the row loop, so that they stay in
/// registers; the row's slots are one running offset.
#[inline(always)]
fn sweep_block<const AREA: bool, const UNIT: bool>(
    block: &Block<'_>,
    positions: &[DVec3],
    lambda: f64,
    out: &mut [DVec3],
    swept: &mut RowSweep,
) {
    let n = out.len();
    let base = block.bounds[0] as usize;
    let xs = &positions[block.first..block.first + n];
    let mut stuck = 0;
    let mut sum = Xy::from(swept.sum);
    let mut a = 0;
    for (((o, &xi), &scale), &end) in out
        .iter_mut()
        .zip(xs)
        .zip(block.scales)
        .zip(&block.bounds[1..])
    {
        let b = end as usize - base;
        let nb = &block.neighbours[a..b];
        let ws = if UNIT { &[][..] } else { &block.weights[a..b] };
        a = b;
        let x = Xy::from(xi);
        let new = if scale > 0.0 {
            let s = gather_sum::<AREA, UNIT>(nb, ws, positions, x);
            let l = if AREA { s * scale } else { s * scale - x };
            x + l * lambda
        } else {
            stuck += 1;
            x
        };
        sum = sum + new;
        *o = new.to_dvec3();
    }
    swept.stuck += stuck;
    swept.sum = sum.to_dvec3();
}

/// Rows per block of a fresh sweep: their weights are computed together
/// ([`FreshRows::block`]) and applied while they are in L1.
const BLOCK_ROWS: usize = 64;

/// Slots of a block kept on the stack (a block with more uses a heap buffer).
const BLOCK_SLOTS: usize = 1024;

/// [`sweep_rows`] with the weights computed as the sweep goes
/// ([`FreshRows::block`]) instead of read from a stored operator: the same bits as
/// [`Laplacian::update`](beltrami_weights::Laplacian::update) at `positions` followed
/// by [`sweep_rows`], without writing or reading a weight array. `positions` must be
/// those the rows were made for.
///
/// `None` when a row's weights do not sum to a finite value (the caller falls back to
/// `update`, which reports a non-finite weight).
///
/// # Panics
/// As [`sweep_rows`].
pub(super) fn sweep_fresh_rows(
    rows: &FreshRows<'_>,
    first: usize,
    positions: &[DVec3],
    lambda: f64,
    out: &mut [DVec3],
) -> Option<RowSweep> {
    let area = matches!(rows.normalization(), Normalization::Area(_));
    match (area, rows.unit_weights()) {
        (false, true) => sweep_fresh_rows_as::<false, true>(rows, first, positions, lambda, out),
        (false, false) => sweep_fresh_rows_as::<false, false>(rows, first, positions, lambda, out),
        (true, true) => sweep_fresh_rows_as::<true, true>(rows, first, positions, lambda, out),
        (true, false) => sweep_fresh_rows_as::<true, false>(rows, first, positions, lambda, out),
    }
}

/// [`sweep_fresh_rows`] for one normalisation and weight kind (as
/// [`sweep_rows_as`]): blocks of [`BLOCK_ROWS`] rows get their weights and scales in
/// buffers on the stack, then the loop of the stored sweep runs over them.
#[inline(always)]
fn sweep_fresh_rows_as<const AREA: bool, const UNIT: bool>(
    rows: &FreshRows<'_>,
    first: usize,
    positions: &[DVec3],
    lambda: f64,
    out: &mut [DVec3],
) -> Option<RowSweep> {
    let offsets = rows.offsets();
    let mut small = [0.0; BLOCK_SLOTS];
    let mut large = Vec::new();
    let mut scales = [0.0; BLOCK_ROWS];
    let mut swept = RowSweep::default();
    for (k, out) in out.chunks_mut(BLOCK_ROWS).enumerate() {
        let f = first + k * BLOCK_ROWS;
        let m = out.len();
        let bounds = &offsets[f..=f + m];
        let slots = bounds[0] as usize..bounds[m] as usize;
        let weights = if slots.len() <= BLOCK_SLOTS {
            &mut small[..slots.len()]
        } else {
            large.resize(slots.len(), 0.0);
            &mut large[..]
        };
        if !rows.block(f, positions, weights, &mut scales[..m]) {
            return None;
        }
        let block = Block {
            bounds,
            neighbours: &rows.neighbours()[slots],
            weights: if UNIT { &[][..] } else { weights },
            scales: &scales[..m],
            first: f,
        };
        sweep_block::<AREA, UNIT>(&block, positions, lambda, out, &mut swept);
    }
    Some(swept)
}

/// The row sum of [`sweep_rows`], from zero in row order: `Σ_j w_j x_j`, or
/// with `AREA` `Σ_j w_j (x_j − x)`; with `UNIT` the weights are 1 and the products are
/// left out (they are exact). Rows of valence 6, the most common on a triangle mesh,
/// are summed without a loop, the others two neighbours per loop step: the same
/// additions in the same order either way.
#[inline(always)]
fn gather_sum<const AREA: bool, const UNIT: bool>(
    nb: &[u32],
    ws: &[f64],
    positions: &[DVec3],
    x: Xy,
) -> Xy {
    #[inline(always)]
    fn term<const AREA: bool, const UNIT: bool>(j: u32, w: f64, positions: &[DVec3], x: Xy) -> Xy {
        let p = Xy::from(positions[j as usize]);
        let d = if AREA { p - x } else { p };
        if UNIT { d } else { d * w }
    }
    let w = |k: usize| if UNIT { 1.0 } else { ws[k] };
    let mut s = Xy::ZERO;
    if let Ok(six) = <&[u32; 6]>::try_from(nb) {
        let ws: &[f64] = if UNIT { &[1.0; 6] } else { ws };
        if let Ok(ws) = <&[f64; 6]>::try_from(ws) {
            for k in 0..6 {
                s = s + term::<AREA, UNIT>(six[k], ws[k], positions, x);
            }
            return s;
        }
    }
    let pairs = nb.len() / 2;
    for k in 0..pairs {
        s = s + term::<AREA, UNIT>(nb[2 * k], w(2 * k), positions, x);
        s = s + term::<AREA, UNIT>(nb[2 * k + 1], w(2 * k + 1), positions, x);
    }
    if nb.len() % 2 == 1 {
        let k = nb.len() - 1;
        s = s + term::<AREA, UNIT>(nb[k], w(k), positions, x);
    }
    s
}

/// A point with `x` and `y` in one [`f64x2`] lane pair and `z` alone: row sums add
/// two coordinates per instruction. Each lane operation is the correctly rounded IEEE
/// operation of the scalar coordinate (no fused multiply-add, no reassociation), so a
/// sum in `Xy` has the bits of the same sum in `DVec3`.
#[derive(Clone, Copy, Debug)]
struct Xy {
    xy: f64x2,
    z: f64,
}

impl Xy {
    const ZERO: Self = Self {
        xy: f64x2::ZERO,
        z: 0.0,
    };

    #[inline(always)]
    fn to_dvec3(self) -> DVec3 {
        let [x, y] = self.xy.to_array();
        DVec3::new(x, y, self.z)
    }
}

impl From<DVec3> for Xy {
    #[inline(always)]
    fn from(p: DVec3) -> Self {
        Self {
            xy: f64x2::new([p.x, p.y]),
            z: p.z,
        }
    }
}

impl std::ops::Add for Xy {
    type Output = Self;
    #[inline(always)]
    fn add(self, rhs: Self) -> Self {
        Self {
            xy: self.xy + rhs.xy,
            z: self.z + rhs.z,
        }
    }
}

impl std::ops::Sub for Xy {
    type Output = Self;
    #[inline(always)]
    fn sub(self, rhs: Self) -> Self {
        Self {
            xy: self.xy - rhs.xy,
            z: self.z - rhs.z,
        }
    }
}

impl std::ops::Mul<f64> for Xy {
    type Output = Self;
    #[inline(always)]
    fn mul(self, w: f64) -> Self {
        Self {
            xy: self.xy * f64x2::splat(w),
            z: self.z * w,
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use beltrami_halfedge::geometry::VertexAreaKind;
    use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
    use beltrami_weights::{
        Cotangent, InverseDistance, Laplacian, LaplacianOptions, NegativeWeights, Normalization,
        Uniform, WeightScheme,
    };

    use super::{sweep_fresh_rows, sweep_rows};

    /// The ranges a test sweeps, splitting the rows anywhere (an empty one too).
    fn ranges(n: usize) -> [std::ops::Range<usize>; 4] {
        [0..n / 3, n / 3..n / 3, n / 3..n - 1, n - 1..n]
    }

    /// The fresh-weight sweep at `x`, with the rows of an operator assembled at other
    /// positions, gives `want` (the stored sweep at `x`) bit for bit, and its stuck count.
    fn assert_fresh_sweep_is_the_same(
        mesh: &HalfedgeMesh,
        x: &[DVec3],
        scheme: &dyn WeightScheme,
        options: LaplacianOptions,
        want: &[DVec3],
        want_stuck: usize,
    ) {
        let elsewhere: Vec<DVec3> = x.iter().map(|&p| p * 0.7 + DVec3::X).collect();
        let mut stale = Laplacian::new(mesh, &elsewhere, scheme, options).unwrap();
        let fresh = stale.fresh_rows(mesh, x, scheme).unwrap();
        let n = mesh.n_vertices();
        let mut out = vec![DVec3::splat(f64::NAN); n];
        let mut stuck = 0;
        for range in ranges(n) {
            let r = sweep_fresh_rows(&fresh, range.start, x, 0.8, &mut out[range]).unwrap();
            stuck += r.stuck;
        }
        assert_eq!(stuck, want_stuck, "{options:?} {}", scheme.name());
        let bits = |p: &[DVec3]| -> Vec<[u64; 3]> {
            p.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
        };
        assert_eq!(bits(&out), bits(want), "{options:?} {}", scheme.name());
    }

    /// A row whose fresh weights do not sum to a finite value stops the fresh sweep
    /// exactly when the refreshed operator has such a row or reports an error (the
    /// smoother then refreshes the operator, which reports the weight): a NaN position
    /// makes inverse-distance weights NaN (cotangents of a NaN triangle are 0, uniform
    /// weights do not read positions); nearly coincident vertices give large but finite
    /// weights.
    #[test]
    fn a_fresh_sweep_refuses_non_finite_weights() {
        let grid = primitives::grid(6, 5);
        let mesh = grid.mesh().unwrap();
        let mut nan = grid.positions.clone();
        nan[8].y = f64::NAN;
        let mut close = grid.positions.clone();
        close[8] = close[9] + DVec3::new(1e-320, 0.0, 0.0);
        let mut refusals = 0;
        for x in [&nan, &close] {
            for scheme in [&Uniform as &dyn WeightScheme, &InverseDistance, &Cotangent] {
                let options = LaplacianOptions::default();
                let mut lap = Laplacian::new(&mesh, &grid.positions, scheme, options).unwrap();
                let mut out = vec![DVec3::ZERO; x.len()];
                let fresh = lap.fresh_rows(&mesh, x, scheme).unwrap();
                let refused = sweep_fresh_rows(&fresh, 0, x, 0.8, &mut out).is_none();
                let failed = lap.update(&mesh, x, scheme).is_err()
                    || mesh.vertices().any(|v| !lap.weight_sum(v).is_finite());
                assert_eq!(refused, failed, "{}", scheme.name());
                refusals += usize::from(refused);
            }
        }
        assert!(refusals >= 1, "{refusals}");
    }

    /// Noisy positions: a fixed, cheap perturbation (no generator needed).
    pub(in crate::explicit) fn wobble(p: &[DVec3], amount: f64) -> Vec<DVec3> {
        p.iter()
            .enumerate()
            .map(|(i, &x)| {
                let t = i as f64;
                x + DVec3::new((t * 1.3).sin(), (t * 2.1).cos(), (t * 0.7).sin()) * amount
            })
            .collect()
    }

    /// One explicit step over ranges that split the rows anywhere gives
    /// `x_i + λ L x_i` with `laplacian_at`'s `L`, rounded as the `DVec3` expression, or
    /// `x_i` for a stuck row; the stuck rows are counted and a non-finite position shows
    /// in the sum.
    #[test]
    fn a_sweep_has_the_bits_of_laplacian_at() {
        let grid = primitives::grid(12, 9);
        let sphere = primitives::icosphere(3);
        let torus = primitives::torus(2.0, 0.7, 13, 7);
        let mut cases: Vec<(HalfedgeMesh, Vec<DVec3>)> = vec![
            (grid.mesh().unwrap(), wobble(&grid.positions, 0.4)),
            (sphere.mesh().unwrap(), wobble(&sphere.positions, 0.05)),
            (torus.mesh().unwrap(), torus.positions.clone()),
        ];
        // Degenerate triangles and a huge scale.
        let mut y = cases[0].1.clone();
        y[14] = y[15];
        cases.push((cases[0].0.clone(), y));
        let huge: Vec<DVec3> = cases[0].1.iter().map(|&p| p * 1e300).collect();
        cases.push((cases[0].0.clone(), huge));
        let lambda = 0.8;
        for (mesh, x) in &cases {
            for normalization in [
                Normalization::WeightSum,
                Normalization::Area(VertexAreaKind::MixedVoronoi),
                Normalization::Area(VertexAreaKind::Barycentric),
            ] {
                for negative in [
                    NegativeWeights::Keep,
                    NegativeWeights::Clamp,
                    NegativeWeights::Abs,
                ] {
                    let options = LaplacianOptions::new()
                        .normalization(normalization)
                        .negative(negative);
                    for scheme in [&Uniform as &dyn WeightScheme, &InverseDistance, &Cotangent] {
                        let Ok(lap) = Laplacian::new(mesh, x, scheme, options) else {
                            continue;
                        };
                        let n = mesh.n_vertices();
                        let mut out = vec![DVec3::splat(f64::NAN); n];
                        let (mut stuck, mut sum) = (0, DVec3::ZERO);
                        for range in ranges(n) {
                            let r =
                                sweep_rows(&lap.rows(), range.start, x, lambda, &mut out[range]);
                            stuck += r.stuck;
                            sum += r.sum;
                        }
                        assert_eq!(stuck, lap.stuck_rows(), "{options:?} {}", scheme.name());
                        assert_fresh_sweep_is_the_same(mesh, x, scheme, options, &out, stuck);
                        if out.iter().any(|p| !p.is_finite()) {
                            assert!(!sum.is_finite());
                        }
                        for v in mesh.vertices() {
                            let i = v.index();
                            let want = lap.laplacian_at(v, x).map_or(x[i], |l| x[i] + l * lambda);
                            assert_eq!(
                                out[i].to_array().map(f64::to_bits),
                                want.to_array().map(f64::to_bits),
                                "{options:?} {} row {i}",
                                scheme.name()
                            );
                        }
                    }
                }
            }
        }
    }
}
