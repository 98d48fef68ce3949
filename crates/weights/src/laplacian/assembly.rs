//! Filling the rows: the built-in kernels row by row, other schemes through their
//! per-halfedge weights; the row sums and scales in the same pass.

use std::sync::OnceLock;

use beltrami_halfedge::geometry::{Geometry, distances_with, ring_cotangents_with};
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, TopologyError, VertexId};
use rayon::prelude::*;

use super::cotangent_plan::CotangentPlan;
use super::layout::{bit, ring_triangles};
use super::{CotangentKernel, Laplacian, NegativeWeights, Normalization};
use crate::PAR_CHUNK;
use crate::error::WeightError;
use crate::scheme::{BuiltIn, WeightContext, WeightScheme};

/// What a row pass writes for rows `first..first + sums.len()`: their slots of
/// `weights` (starting at `offsets[first]`; `None`: the weights are not kept, each row
/// is filled into a scratch buffer), weight sums and scales.
pub(super) struct Rows<'a> {
    pub(super) first: usize,
    pub(super) weights: Option<&'a mut [f64]>,
    pub(super) sums: &'a mut [f64],
    pub(super) scales: &'a mut [f64],
}

/// How many rows were stuck, and whether a row sum was not finite.
#[derive(Clone, Copy, Default)]
pub(super) struct RowTally {
    pub(super) stuck: usize,
    pub(super) non_finite: bool,
}

impl RowTally {
    fn join(self, other: Self) -> Self {
        Self {
            stuck: self.stuck + other.stuck,
            non_finite: self.non_finite || other.non_finite,
        }
    }
}

/// The sum of a row's weights in row order: `Iterator::sum`, a fold from `-0.0` (so
/// that an empty row or one of negative zeros sums to `-0.0`, as before the fold was
/// written out in the fills).
/// A row of six, the most common on a triangle mesh, is summed without a loop (the same
/// additions in the same order).
#[inline(always)]
pub(super) fn row_sum_of(w: &[f64]) -> f64 {
    if let Ok(six) = <&[f64; 6]>::try_from(w) {
        return six.iter().fold(-0.0, |s, &w| s + w);
    }
    w.iter().fold(-0.0, |s, &w| s + w)
}

/// The scale of a row whose weights sum to `sum`: `1/W_i`, or `1/A_i` with the vertex
/// area `area` (area normalisation); 0 when the row is stuck. A row moves only when it
/// has weights (`!empty`), they sum to a positive finite value (for either
/// normalisation: a non-positive sum would push the vertex away from its neighbours)
/// and its scale is positive and finite.
#[inline(always)]
pub(super) fn row_scale(sum: f64, area: Option<f64>, empty: bool) -> f64 {
    let scale = match area {
        None => 1.0 / sum,
        Some(a) => 1.0 / a,
    };
    let movable = !empty && sum.is_finite() && sum > 0.0 && scale.is_finite() && scale > 0.0;
    if movable { scale } else { 0.0 }
}

/// The arithmetic of one row of a built-in kernel, shared by
/// [`Laplacian::update`] and [`FreshRows`](super::FreshRows) (so that both give the
/// same bits by construction).
#[derive(Clone, Copy, Debug)]
pub(super) enum RowKernel<'a> {
    /// Every weight `negative.apply(1)`.
    Uniform { negative: NegativeWeights },
    /// `negative.apply(1 / (|x_j − x_i| + ε))`.
    InverseDistance { negative: NegativeWeights },
    /// `negative.apply(½ (cot α + cot β))` from the cotangent plan's refreshed
    /// `face_cots` ([`CotangentKernel::PerTriangle`]).
    Cotangent {
        negative: NegativeWeights,
        slot_cots: &'a [[u32; 2]],
        face_cots: &'a [f64],
    },
    /// `negative.apply(½ (cot α + cot β))`, the cotangents from the row's one-ring
    /// (`triangles`: the operator's bits of the slots whose left face is a triangle;
    /// [`CotangentKernel::Ring`]).
    CotangentRing {
        negative: NegativeWeights,
        triangles: &'a [u64],
    },
}

impl RowKernel<'_> {
    /// Every weight is exactly 1.
    pub(super) fn unit_weights(&self) -> bool {
        matches!(self, Self::Uniform { negative } if negative.apply(1.0) == 1.0)
    }

    /// Writes row `i`'s weights into `w` (its valence long; its first slot is `s` and
    /// `neighbours` starts there) and returns their sum in row order.
    #[inline(always)]
    pub(super) fn fill(
        &self,
        i: usize,
        s: usize,
        positions: &[DVec3],
        neighbours: &[u32],
        w: &mut [f64],
    ) -> f64 {
        match *self {
            Self::Uniform { negative } => fill_uniform(negative, w),
            Self::InverseDistance { negative } => {
                fill_inverse_distance::<0>(negative, positions, i, neighbours, w)
            }
            Self::Cotangent {
                negative,
                slot_cots,
                face_cots,
            } => fill_cotangent(negative, &slot_cots[s..], face_cots, w),
            Self::CotangentRing {
                negative,
                triangles,
            } => fill_cotangent_ring::<0>(negative, positions, i, s, neighbours, triangles, w),
        }
    }
}

/// A uniform row: every weight `negative.apply(1)`; returns the sum.
#[inline(always)]
pub(super) fn fill_uniform(negative: NegativeWeights, w: &mut [f64]) -> f64 {
    w.fill(negative.apply(1.0));
    row_sum_of(w)
}

/// An inverse-distance row `i` whose neighbours start `neighbours`: `negative.apply(1
/// / (|x_j − x_i| + ε))` (the geometry's distance); returns the sum. `CALLER` gives
/// each caller its own instance of the distance kernel (a closure of a generic
/// function is a type of its own), which the compiler then inlines into that caller's
/// loop: one instance with two callers was not inlined (40 instructions per row more).
#[inline(always)]
pub(super) fn fill_inverse_distance<const CALLER: u8>(
    negative: NegativeWeights,
    positions: &[DVec3],
    i: usize,
    neighbours: &[u32],
    w: &mut [f64],
) -> f64 {
    let eps = crate::DISTANCE_EPSILON;
    let nb = &neighbours[..w.len()];
    let xi = positions[i];
    // One branch-free function per policy (`negative.apply`, written out), so that the
    // kernel applies it to a pair of distances in packed instructions.
    match negative {
        NegativeWeights::Keep => distances_with(xi, positions, nb, w, |d| 1.0 / (d + eps)),
        NegativeWeights::Clamp => {
            distances_with(xi, positions, nb, w, |d| (1.0 / (d + eps)).max(0.0));
        }
        NegativeWeights::Abs => distances_with(xi, positions, nb, w, |d| (1.0 / (d + eps)).abs()),
    }
    row_sum_of(w)
}

/// A cotangent row whose slots' cotangent pairs start `pairs`: `negative.apply(½ (a +
/// b))`; returns the sum (`row_sum_of`'s fold, in the same loop). The policy is chosen
/// once per row, not per slot.
#[inline(always)]
pub(super) fn fill_cotangent(
    negative: NegativeWeights,
    pairs: &[[u32; 2]],
    face_cots: &[f64],
    w: &mut [f64],
) -> f64 {
    let pairs = &pairs[..w.len()];
    let cot = |[a, b]: [u32; 2]| 0.5 * (face_cots[a as usize] + face_cots[b as usize]);
    let mut sum = -0.0;
    // Six slots, the most common row of a triangle mesh: no loop (the same operations
    // in the same order).
    if let (Ok(pairs), Ok(w)) = (
        <&[[u32; 2]; 6]>::try_from(pairs),
        <&mut [f64; 6]>::try_from(&mut *w),
    ) {
        match negative {
            NegativeWeights::Keep => {
                for k in 0..6 {
                    w[k] = cot(pairs[k]);
                    sum += w[k];
                }
            }
            _ => {
                for k in 0..6 {
                    w[k] = negative.apply(cot(pairs[k]));
                    sum += w[k];
                }
            }
        }
        return sum;
    }
    match negative {
        NegativeWeights::Keep => {
            for (w, &p) in w.iter_mut().zip(pairs) {
                *w = cot(p);
                sum += *w;
            }
        }
        _ => {
            for (w, &p) in w.iter_mut().zip(pairs) {
                *w = negative.apply(cot(p));
                sum += *w;
            }
        }
    }
    sum
}

/// A cotangent row `i` whose first slot is `s` and whose neighbours start
/// `neighbours`: `negative.apply(½ (cot α + cot β))` from the one-ring
/// ([`ring_cotangents_with`]; `triangles` marks the slots whose left face is a
/// triangle); returns the sum. The policy is chosen once per row, not per slot;
/// `CALLER` gives each caller its own instance (see [`fill_inverse_distance`]).
#[inline(always)]
pub(super) fn fill_cotangent_ring<const CALLER: u8>(
    negative: NegativeWeights,
    positions: &[DVec3],
    i: usize,
    s: usize,
    neighbours: &[u32],
    triangles: &[u64],
    w: &mut [f64],
) -> f64 {
    let nb = &neighbours[..w.len()];
    let is_triangle = |k: usize| bit(triangles, s + k);
    let xi = positions[i];
    match negative {
        NegativeWeights::Keep => {
            ring_cotangents_with(xi, positions, nb, is_triangle, w, |c| 0.5 * c);
        }
        _ => ring_cotangents_with(xi, positions, nb, is_triangle, w, |c| {
            negative.apply(0.5 * c)
        }),
    }
    row_sum_of(w)
}

/// Runs a row pass over `rows` in parallel: chunks of [`PAR_CHUNK`] (8192) rows, or on a
/// mesh too small for four of them per thread a quarter of each thread's share (at
/// least 256), split by `rayon::join` (no allocation). In each row `fill(i, first_slot,
/// weights)` writes the row's weights and returns their sum `W_i` in row order (from
/// `-0.0`, as `Iterator::sum`: [`row_sum_of`] or the same fold inside the fill's loop),
/// then the sum and the scale are stored.
/// Every row's bits depend only on that row, so not on the chunks or the thread count.
pub(super) fn row_pass<F>(
    offsets: &[u32],
    areas: Option<&[f64]>,
    rows: Rows<'_>,
    fill: &F,
) -> RowTally
where
    F: Fn(usize, usize, &mut [f64]) -> f64 + Sync,
{
    let leaf = rows
        .sums
        .len()
        .div_ceil(4 * rayon::current_num_threads().max(1))
        .clamp(256, PAR_CHUNK);
    row_pass_in(offsets, areas, rows, fill, leaf)
}

/// [`row_pass`] in chunks of at most `leaf` rows.
fn row_pass_in<F>(
    offsets: &[u32],
    areas: Option<&[f64]>,
    rows: Rows<'_>,
    fill: &F,
    leaf: usize,
) -> RowTally
where
    F: Fn(usize, usize, &mut [f64]) -> f64 + Sync,
{
    let n = rows.sums.len();
    if n > leaf {
        let mid = n.div_ceil(2 * leaf) * leaf;
        let split = (offsets[rows.first + mid] - offsets[rows.first]) as usize;
        let (w0, w1) = match rows.weights {
            Some(w) => {
                let (w0, w1) = w.split_at_mut(split);
                (Some(w0), Some(w1))
            }
            None => (None, None),
        };
        let (s0, s1) = rows.sums.split_at_mut(mid);
        let (c0, c1) = rows.scales.split_at_mut(mid);
        let (a, b) = rayon::join(
            || {
                let rows = Rows {
                    first: rows.first,
                    weights: w0,
                    sums: s0,
                    scales: c0,
                };
                row_pass_in(offsets, areas, rows, fill, leaf)
            },
            || {
                let rows = Rows {
                    first: rows.first + mid,
                    weights: w1,
                    sums: s1,
                    scales: c1,
                };
                row_pass_in(offsets, areas, rows, fill, leaf)
            },
        );
        return a.join(b);
    }
    let mut tally = RowTally::default();
    let mut weights = rows.weights;
    let mut scratch = Vec::new();
    let bounds = &offsets[rows.first..=rows.first + n];
    let base = bounds[0] as usize;
    // The row's slots are one running offset: few values live across the loop.
    let mut a = 0;
    for (k, ((&end, sum_out), scale_out)) in bounds[1..]
        .iter()
        .zip(rows.sums.iter_mut())
        .zip(rows.scales.iter_mut())
        .enumerate()
    {
        let i = rows.first + k;
        let b = end as usize - base;
        let row: &mut [f64] = match weights.as_deref_mut() {
            Some(w) => &mut w[a..b],
            None => {
                scratch.resize(b - a, 0.0);
                &mut scratch
            }
        };
        let sum = fill(i, base + a, row);
        a = b;
        *sum_out = sum;
        tally.non_finite |= !sum.is_finite();
        let scale = row_scale(sum, areas.map(|a| a[i]), row.is_empty());
        *scale_out = scale;
        tally.stuck += usize::from(scale == 0.0);
    }
    tally
}

/// Runs the row pass of unit weights (every weight `negative.apply(1)`, which is 1):
/// the sums and scales of [`row_pass`] with [`fill_uniform`], without writing weights.
pub(super) fn unit_pass(
    offsets: &[u32],
    areas: Option<&[f64]>,
    negative: NegativeWeights,
    sums: &mut [f64],
    scales: &mut [f64],
) -> RowTally {
    let one = negative.apply(1.0);
    sums.par_chunks_mut(PAR_CHUNK)
        .zip(scales.par_chunks_mut(PAR_CHUNK))
        .enumerate()
        .map(|(c, (sums, scales))| {
            let mut tally = RowTally::default();
            let first = c * PAR_CHUNK;
            for (k, (sum_out, scale_out)) in sums.iter_mut().zip(scales).enumerate() {
                let i = first + k;
                let len = offsets[i + 1] - offsets[i];
                // `row_sum_of` over `len` copies of `one`.
                let sum = (0..len).fold(-0.0, |s, _| s + one);
                *sum_out = sum;
                tally.non_finite |= !sum.is_finite();
                let scale = row_scale(sum, areas.map(|a| a[i]), len == 0);
                *scale_out = scale;
                tally.stuck += usize::from(scale == 0.0);
            }
            tally
        })
        .reduce(RowTally::default, RowTally::join)
}

impl Laplacian {
    /// Makes the chosen cotangent kernel's data ready for positions `geometry`: the
    /// ring kernel's triangle bits (built once), or the per-triangle plan (built once)
    /// with its cotangents refreshed. `false` when the plan cannot be built (more
    /// corners than `u32` indices).
    pub(super) fn prepare_cotangents(&mut self, geometry: &Geometry<'_>) -> bool {
        let mesh = geometry.mesh();
        let offsets = &self.offsets;
        match self.options.cotangent_kernel {
            CotangentKernel::Ring => {
                self.cotangent = None;
                self.ring_triangles
                    .get_or_insert_with(|| ring_triangles(mesh, offsets));
                true
            }
            _ => {
                self.ring_triangles = None;
                if self.cotangent.is_none() {
                    self.cotangent = CotangentPlan::new(mesh, offsets);
                }
                let Some(plan) = self.cotangent.as_mut() else {
                    return false;
                };
                plan.refresh(geometry.positions());
                true
            }
        }
    }
}

/// The row kernel of the cotangent scheme from the operator's kernel data, after
/// [`Laplacian::prepare_cotangents`].
pub(super) fn cotangent_row_kernel<'a>(
    negative: NegativeWeights,
    plan: Option<&'a CotangentPlan>,
    ring_triangles: Option<&'a [u64]>,
) -> RowKernel<'a> {
    match (plan, ring_triangles) {
        (Some(plan), None) => RowKernel::Cotangent {
            negative,
            slot_cots: &plan.slot_cots,
            face_cots: &plan.face_cots,
        },
        _ => RowKernel::CotangentRing {
            negative,
            triangles: ring_triangles.unwrap_or_default(),
        },
    }
}

impl Laplacian {
    /// The weight array to write, one per slot (the stored one's buffer when there is
    /// one), or `None` when the weights are not to be kept (the stored ones are then
    /// released); put it back with [`put_weights`](Self::put_weights).
    fn weight_buffer(&mut self, store: bool) -> Option<Vec<f64>> {
        let mut w = self.weights.take().unwrap_or_default();
        if !store {
            return None;
        }
        w.resize(self.neighbours.len(), 0.0);
        Some(w)
    }

    /// Uniform rows: their sums, scales and stuck count, and no weights (all 1, not
    /// stored) — or, should a negative-weight policy ever change 1, those weights when
    /// `store`, like any other kernel's.
    pub(super) fn set_uniform_rows(&mut self, areas: Option<&[f64]>, store: bool) {
        let negative = self.options.negative;
        let tally = unit_pass(
            &self.offsets,
            areas,
            negative,
            &mut self.weight_sums,
            &mut self.scales,
        );
        self.stuck = tally.stuck;
        self.unit_weights = RowKernel::Uniform { negative }.unit_weights();
        self.weights = OnceLock::new();
        if self.unit_weights {
            return;
        }
        // Unreachable with the policies there are (each keeps 1).
        let mut weights = self.weight_buffer(store);
        if let Some(w) = weights.as_mut() {
            w.fill(negative.apply(1.0));
        }
        self.put_weights(weights);
    }

    /// Stores the weights written into a [`weight_buffer`](Self::weight_buffer).
    fn put_weights(&mut self, weights: Option<Vec<f64>>) {
        if let Some(w) = weights {
            self.weights = OnceLock::from(w);
        }
    }

    /// Recomputes the weights and scales from new positions, reusing the buffers. The
    /// mesh must be the one the operator was assembled on.
    ///
    /// The built-in schemes ([`Uniform`](crate::Uniform),
    /// [`InverseDistance`](crate::InverseDistance), [`Cotangent`](crate::Cotangent)) are
    /// computed row by row: inverse-distance weights from the two positions of each row
    /// slot, cotangents by the chosen [`CotangentKernel`] (each triangle's once and
    /// gathered into the slots, or from the row's one-ring); the row sums and scales in
    /// the same pass. Uniform weights are not stored (they are all 1). Other schemes go
    /// through [`WeightScheme::fill_weights`]. The numbers are the same either way.
    ///
    /// # Errors
    /// As [`new`](Self::new). After an error the operator's weights are unspecified
    /// until the next successful update.
    ///
    /// # Panics
    /// If `mesh` has a different number of vertices or halfedges than at assembly.
    pub fn update(
        &mut self,
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
    ) -> Result<(), WeightError> {
        self.update_as(mesh, positions, scheme, true)
    }

    /// [`update`](Self::update), keeping the weights (`store`) or only their sums and
    /// scales (the stored weights are then released, as by
    /// [`fresh_rows`](Self::fresh_rows)).
    pub(super) fn update_as(
        &mut self,
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
        store: bool,
    ) -> Result<(), WeightError> {
        assert_eq!(mesh.n_halfedges(), self.n_halfedges, "a different mesh");
        assert_eq!(mesh.n_vertices(), self.scales.len(), "a different mesh");
        let geometry = Geometry::new(mesh, positions)?;
        let areas = match self.options.normalization {
            Normalization::WeightSum => Ok(None),
            Normalization::Area(kind) => geometry.vertex_areas(kind).map(Some),
        };
        let Ok(areas) = areas else {
            // The generic path reports a non-finite weight before this error.
            return self.update_generic(mesh, &geometry, areas.map(|_| None), scheme, store);
        };
        let areas = areas.as_ref().map(|a| a.as_slice());
        let negative = self.options.negative;
        let kernel = BuiltIn::of(scheme);
        self.unit_weights = false;
        if kernel == Some(BuiltIn::Uniform) {
            // Uniform weights are all 1, hence their sums finite: no error to report.
            self.set_uniform_rows(areas, store);
            return Ok(());
        }
        let ready = kernel == Some(BuiltIn::Cotangent) && self.prepare_cotangents(&geometry);
        let mut weights = self.weight_buffer(store);
        let cotangent = ready.then(|| {
            cotangent_row_kernel(
                negative,
                self.cotangent.as_ref(),
                self.ring_triangles.as_deref(),
            )
        });
        let rows = Rows {
            first: 0,
            weights: weights.as_deref_mut(),
            sums: &mut self.weight_sums,
            scales: &mut self.scales,
        };
        let (offsets, neighbours) = (&self.offsets, &self.neighbours);
        let tally = match kernel {
            Some(BuiltIn::InverseDistance) => {
                Some(row_pass(offsets, areas, rows, &|i, s, w: &mut [f64]| {
                    fill_inverse_distance::<1>(negative, positions, i, &neighbours[s..], w)
                }))
            }
            Some(BuiltIn::Cotangent) => match cotangent {
                Some(RowKernel::Cotangent {
                    slot_cots,
                    face_cots,
                    ..
                }) => Some(row_pass(offsets, areas, rows, &|_, s, w: &mut [f64]| {
                    fill_cotangent(negative, &slot_cots[s..], face_cots, w)
                })),
                Some(RowKernel::CotangentRing { triangles, .. }) => {
                    Some(row_pass(offsets, areas, rows, &|i, s, w: &mut [f64]| {
                        fill_cotangent_ring::<1>(
                            negative,
                            positions,
                            i,
                            s,
                            &neighbours[s..],
                            triangles,
                            w,
                        )
                    }))
                }
                _ => None,
            },
            _ => None,
        };
        self.put_weights(weights);
        match tally {
            // A kernel found only finite row sums, hence only finite weights.
            Some(tally) if !tally.non_finite => {
                self.stuck = tally.stuck;
                Ok(())
            }
            // No kernel, or a non-finite weight (whose error names the first one in
            // halfedge order, as the generic path does).
            _ => self.update_generic(mesh, &geometry, Ok(areas), scheme, store),
        }
    }

    /// [`update`](Self::update) through [`WeightScheme::fill_weights`]; each row's
    /// slots take their halfedges' weights in the mesh's circulation order.
    fn update_generic(
        &mut self,
        mesh: &HalfedgeMesh,
        geometry: &Geometry<'_>,
        areas: Result<Option<&[f64]>, TopologyError>,
        scheme: &dyn WeightScheme,
        store: bool,
    ) -> Result<(), WeightError> {
        self.unit_weights = false;
        self.halfedge_weights.resize(self.n_halfedges, 0.0);
        let ctx = WeightContext::new(*geometry);
        scheme.fill_weights(&ctx, &mut self.halfedge_weights);
        let bad = self
            .halfedge_weights
            .par_chunks(PAR_CHUNK)
            .any(|c| c.iter().any(|w| !w.is_finite()));
        if bad {
            let h = self
                .halfedge_weights
                .iter()
                .position(|w| !w.is_finite())
                .expect("a non-finite weight");
            let h = HalfedgeId::new(h as u32);
            return Err(WeightError::NonFiniteWeight {
                scheme: scheme.name().to_string(),
                from: mesh.from_vertex(h).raw(),
                to: mesh.to_vertex(h).raw(),
                value: self.halfedge_weights[h.index()],
            });
        }
        let areas = areas?;
        let negative = self.options.negative;
        let mut weights = self.weight_buffer(store);
        let halfedge_weights = &self.halfedge_weights;
        let rows = Rows {
            first: 0,
            weights: weights.as_deref_mut(),
            sums: &mut self.weight_sums,
            scales: &mut self.scales,
        };
        let tally = row_pass(&self.offsets, areas, rows, &|i, _, w: &mut [f64]| {
            let ring = mesh.halfedges_around_vertex(VertexId::new(i as u32));
            for (w, h) in w.iter_mut().zip(ring) {
                *w = negative.apply(halfedge_weights[h.index()]);
            }
            row_sum_of(w)
        });
        self.put_weights(weights);
        self.stuck = tally.stuck;
        Ok(())
    }
}
