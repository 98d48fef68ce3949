//! Filling the rows: the built-in kernels row by row, other schemes through their
//! per-halfedge weights; the row sums and scales in the same pass.

use beltrami_halfedge::geometry::{Geometry, distances_with};
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, TopologyError};
use rayon::prelude::*;

use super::cotangent_plan::CotangentPlan;
use super::{Laplacian, NegativeWeights, Normalization};
use crate::PAR_CHUNK;
use crate::error::WeightError;
use crate::scheme::{BuiltIn, WeightContext, WeightScheme};

/// What a row pass writes for rows `first..first + sums.len()`: their slots of
/// `weights` (starting at `offsets[first]`), weight sums and scales.
struct Rows<'a> {
    first: usize,
    weights: &'a mut [f64],
    sums: &'a mut [f64],
    scales: &'a mut [f64],
}

/// How many rows were stuck, and whether a row sum was not finite.
#[derive(Clone, Copy, Default)]
struct RowTally {
    stuck: usize,
    non_finite: bool,
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
#[inline(always)]
fn row_sum_of(w: &[f64]) -> f64 {
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
    /// `face_cots`.
    Cotangent {
        negative: NegativeWeights,
        slot_cots: &'a [[u32; 2]],
        face_cots: &'a [f64],
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
    distances_with(positions[i], positions, nb, w, |d| {
        negative.apply(1.0 / (d + eps))
    });
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

/// Runs a row pass over `rows` in parallel: chunks of `PAR_CHUNK` rows (split by
/// `rayon::join`, no allocation), and in each row `fill(i, first_slot, weights)` writes
/// the row's weights and returns their sum `W_i` in row order (from `-0.0`, as
/// `Iterator::sum`: [`row_sum_of`] or the same fold inside the fill's loop), then the
/// sum and the scale are stored.
/// Every row's bits depend only on that row, so not on the thread count.
fn row_pass<F>(offsets: &[u32], areas: Option<&[f64]>, rows: Rows<'_>, fill: &F) -> RowTally
where
    F: Fn(usize, usize, &mut [f64]) -> f64 + Sync,
{
    let n = rows.sums.len();
    if n > PAR_CHUNK {
        let mid = n.div_ceil(2 * PAR_CHUNK) * PAR_CHUNK;
        let split = (offsets[rows.first + mid] - offsets[rows.first]) as usize;
        let (w0, w1) = rows.weights.split_at_mut(split);
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
                row_pass(offsets, areas, rows, fill)
            },
            || {
                let rows = Rows {
                    first: rows.first + mid,
                    weights: w1,
                    sums: s1,
                    scales: c1,
                };
                row_pass(offsets, areas, rows, fill)
            },
        );
        return a.join(b);
    }
    let mut tally = RowTally::default();
    let weights = rows.weights;
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
        let row = &mut weights[a..b];
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

impl Laplacian {
    /// Recomputes the weights and scales from new positions, reusing the buffers. The
    /// mesh must be the one the operator was assembled on.
    ///
    /// The built-in schemes ([`Uniform`](crate::Uniform),
    /// [`InverseDistance`](crate::InverseDistance), [`Cotangent`](crate::Cotangent)) are
    /// computed row by row:
    /// inverse-distance weights from the two positions of each row slot, cotangents
    /// once per triangle and gathered into the slots; the row sums and scales in the
    /// same pass. Other schemes go through [`WeightScheme::fill_weights`]. The numbers
    /// are the same either way.
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
        assert_eq!(mesh.n_halfedges(), self.n_halfedges, "a different mesh");
        assert_eq!(mesh.n_vertices(), self.scales.len(), "a different mesh");
        let geometry = Geometry::new(mesh, positions)?;
        let areas = match self.options.normalization {
            Normalization::WeightSum => Ok(None),
            Normalization::Area(kind) => geometry.vertex_areas(kind).map(Some),
        };
        let Ok(areas) = areas else {
            // The generic path reports a non-finite weight before this error.
            return self.update_generic(mesh, &geometry, areas.map(|_| None), scheme);
        };
        let areas = areas.as_ref().map(|a| a.as_slice());
        let negative = self.options.negative;
        let rows = Rows {
            first: 0,
            weights: &mut self.weights,
            sums: &mut self.weight_sums,
            scales: &mut self.scales,
        };
        let offsets = &self.offsets;
        let kernel = BuiltIn::of(scheme);
        self.unit_weights = false;
        let tally = match kernel {
            Some(BuiltIn::Uniform) => {
                let kernel = RowKernel::Uniform { negative };
                self.unit_weights = kernel.unit_weights();
                Some(row_pass(offsets, areas, rows, &|_, _, w: &mut [f64]| {
                    fill_uniform(negative, w)
                }))
            }
            Some(BuiltIn::InverseDistance) => {
                let neighbours = &self.neighbours;
                Some(row_pass(offsets, areas, rows, &|i, s, w: &mut [f64]| {
                    fill_inverse_distance::<1>(negative, positions, i, &neighbours[s..], w)
                }))
            }
            Some(BuiltIn::Cotangent) => {
                if self.cotangent.is_none() {
                    self.cotangent = CotangentPlan::new(mesh, &self.halfedges);
                }
                self.cotangent.as_mut().map(|plan| {
                    plan.refresh(&geometry);
                    let (slot_cots, face_cots) = (&plan.slot_cots[..], &plan.face_cots[..]);
                    row_pass(offsets, areas, rows, &|_, s, w: &mut [f64]| {
                        fill_cotangent(negative, &slot_cots[s..], face_cots, w)
                    })
                })
            }
            _ => None,
        };
        match tally {
            // A kernel found only finite row sums, hence only finite weights.
            Some(tally) if !tally.non_finite => {
                self.stuck = tally.stuck;
                Ok(())
            }
            // No kernel, or a non-finite weight (whose error names the first one in
            // halfedge order, as the generic path does).
            _ => self.update_generic(mesh, &geometry, Ok(areas), scheme),
        }
    }

    /// [`update`](Self::update) through [`WeightScheme::fill_weights`].
    fn update_generic(
        &mut self,
        mesh: &HalfedgeMesh,
        geometry: &Geometry<'_>,
        areas: Result<Option<&[f64]>, TopologyError>,
        scheme: &dyn WeightScheme,
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
        let (halfedges, halfedge_weights) = (&self.halfedges, &self.halfedge_weights);
        let rows = Rows {
            first: 0,
            weights: &mut self.weights,
            sums: &mut self.weight_sums,
            scales: &mut self.scales,
        };
        let tally = row_pass(&self.offsets, areas, rows, &|_, s, w: &mut [f64]| {
            for (w, &h) in w.iter_mut().zip(&halfedges[s..]) {
                *w = negative.apply(halfedge_weights[h as usize]);
            }
            row_sum_of(w)
        });
        self.stuck = tally.stuck;
        Ok(())
    }
}
