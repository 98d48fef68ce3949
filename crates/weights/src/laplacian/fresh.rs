//! Weights computed where they are used: the rows of the built-in kernels at new
//! positions, one row at a time, for an integrator that applies each row as soon as it
//! has it instead of storing every weight (see [`FreshRows`]).

use beltrami_halfedge::geometry::{Geometry, distance, lengths_with, vertex_area_share};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use rayon::prelude::*;

use super::Laplacian;
use std::sync::OnceLock;

use super::assembly::{
    RowKernel, Rows, cotangent_row_kernel, fill_cotangent, fill_cotangent_ring,
    fill_inverse_distance, fill_uniform, row_pass, row_scale, row_sum_of,
};
use super::layout::{NO_TRIANGLE, corner_code, slot_corners};
use super::options::{CotangentKernel, NegativeWeights, Normalization};
use crate::PAR_CHUNK;
use crate::scheme::{BuiltIn, WeightScheme};

/// The rows of a [`Laplacian`] at new positions, computed one row at a time and not
/// stored: what [`Laplacian::update`] would write, row by row, for an integrator that
/// uses each row at once (an explicit step that recomputes the weights every
/// iteration, say). Made by [`Laplacian::fresh_rows`].
///
/// [`row`](Self::row) gives row `i`'s weights and scale with the bits that
/// [`Laplacian::update`] at the same positions stores in
/// [`rows`](Laplacian::rows)`().weights` and `.scales` (the same functions compute
/// both). The operator's row sums and scales stay those of its last assembly or
/// update; its stored weights are released (see [`Laplacian::fresh_rows`]).
#[derive(Debug)]
pub struct FreshRows<'a> {
    offsets: &'a [u32],
    neighbours: &'a [u32],
    kernel: RowKernel<'a>,
    /// The vertex areas of area normalisation (`None` for weight-sum normalisation).
    areas: Option<Vec<f64>>,
    normalization: Normalization,
}

impl Laplacian {
    /// Whether a sweep may compute these rows itself by scattering each triangle's
    /// cotangents into its three vertices' rows: `scheme` is the built-in
    /// [`Cotangent`](crate::Cotangent), with weight-sum normalisation and negative weights
    /// kept ([`NegativeWeights::Keep`]; a clamped or mirrored edge weight needs both of
    /// its triangles' cotangents before it can be taken). Row `i` is then
    /// `Σ_j w_ij x_j / Σ_j w_ij` with `w_ij = ½(cot α + cot β)`, whatever the
    /// [`CotangentKernel`](crate::CotangentKernel) (the ½ cancels).
    ///
    /// When it may, the stored weights are released, as [`fresh_rows`](Self::fresh_rows)
    /// releases them: the sweep's weights are newer, and [`update`](Self::update) at
    /// that sweep's positions gives its operator (to rounding: the sweep sums each
    /// row's terms triangle by triangle, the operator edge by edge). The row sums and
    /// scales stay those of the last assembly or update.
    pub fn scatters_cotangents(&mut self, scheme: &dyn WeightScheme) -> bool {
        let scatters = BuiltIn::of(scheme) == Some(BuiltIn::Cotangent)
            && self.options.normalization == Normalization::WeightSum
            && self.options.negative == NegativeWeights::Keep;
        if scatters && !self.unit_weights {
            self.weights = OnceLock::new();
        }
        scatters
    }

    /// Whether an integrator may compute this operator's inverse-distance weights
    /// itself, edge by edge, each edge's weight `1 / (|x_j − x_i| + ε)` once for both
    /// its rows: `scheme` is the built-in [`InverseDistance`](crate::InverseDistance)
    /// and the rows are normalised by their weight sums (every negative-weight policy
    /// leaves a positive weight as it is). When it may, the stored weights are released
    /// as by [`fresh_rows`](Self::fresh_rows): until the next
    /// [`update`](Self::update), [`weights_stored`](Self::weights_stored) is `false`.
    pub fn scatters_distances(&mut self, scheme: &dyn WeightScheme) -> bool {
        let scatters = BuiltIn::of(scheme) == Some(BuiltIn::InverseDistance)
            && self.options.normalization == Normalization::WeightSum;
        if scatters {
            self.weights = OnceLock::new();
        }
        scatters
    }

    /// The rows at `positions`, to be computed one at a time by [`FreshRows::row`]:
    /// the per-vertex and per-face parts (vertex areas for area normalisation; with
    /// [`CotangentKernel::PerTriangle`](crate::CotangentKernel::PerTriangle), the
    /// cotangents of every triangle) are computed here, in parallel; the per-row
    /// weights, sums and scales are left to [`FreshRows::row`] (with
    /// [`CotangentKernel::Ring`](crate::CotangentKernel::Ring), the cotangents too, from
    /// the row's one-ring).
    ///
    /// The rows replace the operator's stored weights, which are released (unless the
    /// weights are all 1, which are not stored anyway): until the next
    /// [`update`](Self::update), [`weights_stored`](Self::weights_stored) is `false`
    /// and the accessors that read weights panic. So an integrator that computes the
    /// weights inside its sweep every iteration holds no weight array; one that needs
    /// the operator of a sweep calls `update` at that sweep's positions (the same
    /// bits). The row sums and scales stay those of the last assembly or update.
    ///
    /// `None` when the rows cannot be computed that way: `scheme` is not one of the
    /// built-in [`Uniform`](crate::Uniform), [`InverseDistance`](crate::InverseDistance)
    /// and [`Cotangent`](crate::Cotangent), the positions do not match the mesh, or the
    /// vertex areas cannot be computed. [`update`](Self::update) handles every such case
    /// (and reports its error).
    ///
    /// # Panics
    /// If `mesh` has a different number of vertices or halfedges than at assembly.
    pub fn fresh_rows(
        &mut self,
        mesh: &HalfedgeMesh,
        positions: &'_ [DVec3],
        scheme: &dyn WeightScheme,
    ) -> Option<FreshRows<'_>> {
        assert_eq!(mesh.n_halfedges(), self.n_halfedges, "a different mesh");
        assert_eq!(mesh.n_vertices(), self.scales.len(), "a different mesh");
        let geometry = Geometry::new(mesh, positions).ok()?;
        let areas = match self.options.normalization {
            Normalization::WeightSum => None,
            Normalization::Area(kind) => Some(geometry.vertex_areas(kind).ok()?.into_vec()),
        };
        let built_in = BuiltIn::of(scheme)?;
        self.fresh_rows_with(areas, built_in, |lap| lap.prepare_cotangents(&geometry))
    }

    /// The [`FreshRows`] of `built_in` with the vertex `areas` of area normalisation,
    /// after `prepare` made the cotangent kernel's data ready (cotangent rows only;
    /// `None` when it could not).
    fn fresh_rows_with(
        &mut self,
        areas: Option<Vec<f64>>,
        built_in: BuiltIn,
        prepare: impl FnOnce(&mut Self) -> bool,
    ) -> Option<FreshRows<'_>> {
        let negative = self.options.negative;
        if !self.unit_weights {
            self.weights = OnceLock::new();
        }
        if built_in == BuiltIn::Cotangent && !prepare(self) {
            return None;
        }
        let kernel = match built_in {
            BuiltIn::Uniform => RowKernel::Uniform { negative },
            BuiltIn::InverseDistance => RowKernel::InverseDistance { negative },
            BuiltIn::Cotangent => cotangent_row_kernel(
                negative,
                self.cotangent.as_ref(),
                self.ring_triangles.as_deref(),
            ),
        };
        Some(FreshRows {
            offsets: &self.offsets,
            neighbours: &self.neighbours,
            kernel,
            areas,
            normalization: self.options.normalization,
        })
    }

    /// Makes the operator able to recompute its rows without the mesh
    /// ([`fresh_rows_detached`](Self::fresh_rows_detached),
    /// [`update_detached`](Self::update_detached)): for area normalisation it keeps, per
    /// row slot, where the row's vertex stands in the triangle on the slot's left (two
    /// bits per slot, so that each vertex area sums its triangles' shares in the
    /// mesh's order), and for cotangent weights it builds the chosen kernel's data now
    /// (the one-ring kernel's triangle bits, or the per-triangle plan, whose refresh
    /// reads only the positions). The rows' offsets and neighbours are the rest.
    ///
    /// `false` (and nothing kept) when the rows cannot be recomputed that way:
    /// `scheme` is not one of the built-in [`Uniform`](crate::Uniform),
    /// [`InverseDistance`](crate::InverseDistance) and [`Cotangent`](crate::Cotangent);
    /// a face is not a triangle; two vertices are joined by more than one edge (a row's
    /// neighbours then do not name its triangles); the positions do not match the mesh;
    /// or the per-triangle plan does not fit `u32` indices. Such operators keep
    /// needing the mesh ([`update`](Self::update), [`fresh_rows`](Self::fresh_rows)).
    ///
    /// # Panics
    /// If `mesh` has a different number of vertices or halfedges than at assembly.
    pub fn detach(
        &mut self,
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
    ) -> bool {
        assert_eq!(mesh.n_halfedges(), self.n_halfedges, "a different mesh");
        assert_eq!(mesh.n_vertices(), self.scales.len(), "a different mesh");
        let Some(built_in) = BuiltIn::of(scheme) else {
            return false;
        };
        if !self.halfedges.is_empty() || !mesh.is_triangle_mesh() {
            return false;
        }
        let Ok(geometry) = Geometry::new(mesh, positions) else {
            return false;
        };
        // The kernel's data as assembled, or built now (its refresh is then wasted work).
        let ready = match self.options.cotangent_kernel {
            CotangentKernel::Ring => self.ring_triangles.is_some(),
            _ => self.cotangent.is_some(),
        };
        if built_in == BuiltIn::Cotangent && !ready && !self.prepare_cotangents(&geometry) {
            return false;
        }
        if let Normalization::Area(_) = self.options.normalization {
            self.slot_corners = slot_corners(mesh, &self.offsets);
        }
        self.detached = true;
        true
    }

    /// Whether [`detach`](Self::detach) can take `scheme` at all: one of this crate's
    /// built-in schemes ([`Uniform`](crate::Uniform),
    /// [`InverseDistance`](crate::InverseDistance), [`Cotangent`](crate::Cotangent)),
    /// whose rows the operator recomputes without the mesh. A scheme of your own reads
    /// the mesh. (`detach` may still decline for the mesh: polygon faces, repeated
    /// neighbours.)
    #[must_use]
    pub fn detaches(scheme: &dyn WeightScheme) -> bool {
        BuiltIn::of(scheme).is_some()
    }

    /// Whether [`detach`](Self::detach) made the operator able to recompute its rows
    /// without the mesh.
    #[must_use]
    pub fn is_detached(&self) -> bool {
        self.detached
    }

    /// [`fresh_rows`](Self::fresh_rows) without the mesh, after
    /// [`detach`](Self::detach): the same rows, bit for bit (each vertex area sums its
    /// triangles' shares in the mesh's order; the cotangent kernels read the kept
    /// data). `None` when the operator is not detached, `scheme` is not the built-in
    /// one it was detached for, or `positions` does not have one entry per row.
    pub fn fresh_rows_detached(
        &mut self,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
    ) -> Option<FreshRows<'_>> {
        if !self.detached || positions.len() != self.scales.len() {
            return None;
        }
        let built_in = BuiltIn::of(scheme)?;
        let areas = self.detached_areas(positions);
        self.fresh_rows_with(areas, built_in, |lap| {
            lap.prepare_cotangents_detached(positions)
        })
    }

    /// [`update`](Self::update) without the mesh, after [`detach`](Self::detach): the
    /// same weights, sums and scales, bit for bit. `false` when they cannot be computed
    /// without the mesh — the operator is not detached, `scheme` is not the built-in
    /// one it was detached for, `positions` does not have one entry per row, or a
    /// weight is not finite (which `update` reports with the halfedge it is on) — and
    /// the operator's weights are then unspecified until the next successful update.
    #[must_use]
    pub fn update_detached(&mut self, positions: &[DVec3], scheme: &dyn WeightScheme) -> bool {
        if !self.detached || positions.len() != self.scales.len() {
            return false;
        }
        let Some(built_in) = BuiltIn::of(scheme) else {
            return false;
        };
        let areas = self.detached_areas(positions);
        let areas = areas.as_deref();
        let negative = self.options.negative;
        self.unit_weights = false;
        if built_in == BuiltIn::Uniform {
            self.set_uniform_rows(areas, true);
            return true;
        }
        if built_in == BuiltIn::Cotangent && !self.prepare_cotangents_detached(positions) {
            return false;
        }
        let mut weights = self.weights.take().unwrap_or_default();
        weights.resize(self.neighbours.len(), 0.0);
        let rows = Rows {
            first: 0,
            weights: Some(&mut weights),
            sums: &mut self.weight_sums,
            scales: &mut self.scales,
        };
        let (offsets, neighbours) = (&self.offsets, &self.neighbours);
        let kernel = match built_in {
            BuiltIn::Cotangent => cotangent_row_kernel(
                negative,
                self.cotangent.as_ref(),
                self.ring_triangles.as_deref(),
            ),
            _ => RowKernel::InverseDistance { negative },
        };
        // The same row functions, instances and order as `update`.
        let tally = match kernel {
            RowKernel::Cotangent {
                slot_cots,
                face_cots,
                ..
            } => row_pass(offsets, areas, rows, &|_, s, w: &mut [f64]| {
                fill_cotangent(negative, &slot_cots[s..], face_cots, w)
            }),
            RowKernel::CotangentRing { triangles, .. } => {
                row_pass(offsets, areas, rows, &|i, s, w: &mut [f64]| {
                    fill_cotangent_ring::<1>(
                        negative,
                        positions,
                        i,
                        s,
                        &neighbours[s..],
                        triangles,
                        w,
                    )
                })
            }
            _ => row_pass(offsets, areas, rows, &|i, s, w: &mut [f64]| {
                fill_inverse_distance::<1>(negative, positions, i, &neighbours[s..], w)
            }),
        };
        self.weights = OnceLock::from(weights);
        if tally.non_finite {
            return false;
        }
        self.stuck = tally.stuck;
        true
    }

    /// The weight of a curve-boundary neighbour at `to` of a vertex at `from` for a
    /// built-in scheme, from the two positions alone: the bits of
    /// [`WeightScheme::curve_weight`] of [`Uniform`](crate::Uniform) (1) and of
    /// [`InverseDistance`](crate::InverseDistance) and [`Cotangent`](crate::Cotangent)
    /// (`1 / (|x_to − x_from| + ε)`). `None` for any other scheme, whose curve weight
    /// may read the mesh.
    #[must_use]
    pub fn curve_weight_detached(scheme: &dyn WeightScheme, from: DVec3, to: DVec3) -> Option<f64> {
        match BuiltIn::of(scheme)? {
            BuiltIn::Uniform => Some(1.0),
            BuiltIn::InverseDistance | BuiltIn::Cotangent => {
                Some(1.0 / (distance(from, to) + crate::DISTANCE_EPSILON))
            }
        }
    }

    /// The vertex areas of area normalisation from the detached slot codes (`None` for
    /// weight-sum normalisation): each vertex sums its triangles' shares from 0.0 in
    /// row order, as [`Geometry::vertex_area`] does around the vertex. In parallel with
    /// fixed chunks.
    fn detached_areas(&self, positions: &[DVec3]) -> Option<Vec<f64>> {
        let Normalization::Area(kind) = self.options.normalization else {
            return None;
        };
        let (offsets, neighbours, codes) = (&self.offsets, &self.neighbours, &self.slot_corners);
        let mut areas = vec![0.0; self.scales.len()];
        areas
            .par_chunks_mut(PAR_CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                for (k, a) in out.iter_mut().enumerate() {
                    let i = c * PAR_CHUNK + k;
                    let (first, end) = (offsets[i] as usize, offsets[i + 1] as usize);
                    let xi = positions[i];
                    let mut area = 0.0;
                    for s in first..end {
                        let code = corner_code(codes, s);
                        if code == NO_TRIANGLE {
                            continue;
                        }
                        let next = if s + 1 == end { first } else { s + 1 };
                        let a = positions[neighbours[s] as usize];
                        let b = positions[neighbours[next] as usize];
                        let triangle = match code {
                            0 => [xi, a, b],
                            1 => [b, xi, a],
                            _ => [a, b, xi],
                        };
                        area += vertex_area_share(triangle, usize::from(code), kind);
                    }
                    *a = area;
                }
            });
        Some(areas)
    }

    /// Makes the cotangent kernel's data ready for `positions` without the mesh: the
    /// one-ring kernel's bits as kept, or the per-triangle plan refreshed. `false` when
    /// the chosen kernel's data was not built by [`detach`](Self::detach).
    fn prepare_cotangents_detached(&mut self, positions: &[DVec3]) -> bool {
        match self.options.cotangent_kernel {
            CotangentKernel::Ring => self.ring_triangles.is_some(),
            _ => match self.cotangent.as_mut() {
                Some(plan) => {
                    plan.refresh(positions);
                    true
                }
                None => false,
            },
        }
    }
}

impl FreshRows<'_> {
    /// Row offsets into the slots, `n_rows + 1` entries from 0 (as
    /// [`LaplacianRows::offsets`](crate::LaplacianRows::offsets)).
    #[must_use]
    pub fn offsets(&self) -> &[u32] {
        self.offsets
    }

    /// The neighbour vertex index of each slot (as
    /// [`LaplacianRows::neighbours`](crate::LaplacianRows::neighbours)).
    #[must_use]
    pub fn neighbours(&self) -> &[u32] {
        self.neighbours
    }

    /// How the rows are normalised.
    #[must_use]
    pub fn normalization(&self) -> Normalization {
        self.normalization
    }

    /// Every weight is exactly 1 (uniform weights), so an integrator need not read them
    /// (as [`LaplacianRows::unit_weights`](crate::LaplacianRows::unit_weights)).
    #[must_use]
    pub fn unit_weights(&self) -> bool {
        self.kernel.unit_weights()
    }

    /// Row `i`'s weights at the positions, written to `weights` (one per slot, after
    /// the negative-weight policy; `weights.len()` must be the row's valence), and its
    /// scale (`1/W_i` or `1/A_i`; 0 for a stuck row): the bits
    /// [`Laplacian::update`] would store. `positions` must be those given to
    /// [`Laplacian::fresh_rows`] (the vertex areas and cotangents are theirs).
    ///
    /// `None` when the row's weights do not sum to a finite value: a weight may be
    /// NaN or infinite, which [`Laplacian::update`] reports as an error (with the
    /// vertices of the first such halfedge), so a caller falls back to it.
    ///
    /// # Panics
    /// If `i` is not a row, `weights` is shorter than the row, or `positions` is
    /// shorter than the mesh's vertex count.
    #[inline(always)]
    pub fn row(&self, i: usize, positions: &[DVec3], weights: &mut [f64]) -> Option<f64> {
        let s = self.offsets[i] as usize;
        let weights = &mut weights[..self.offsets[i + 1] as usize - s];
        let sum = self
            .kernel
            .fill(i, s, positions, &self.neighbours[s..], weights);
        if !sum.is_finite() {
            return None;
        }
        let area = self.areas.as_ref().map(|a| a[i]);
        Some(row_scale(sum, area, weights.is_empty()))
    }

    /// The rows `first..first + scales.len()` at once: their weights into `weights`
    /// (the rows' slots one after the other, `offsets[first + n] − offsets[first]` of
    /// them) and their scales into `scales`, with the bits of [`row`](Self::row). One
    /// loop per kernel (the kernel is chosen once per block, not per row), for an
    /// integrator that applies small blocks of rows while their weights are in cache.
    ///
    /// `false` when a row's weights do not sum to a finite value (see
    /// [`row`](Self::row)); `weights` and `scales` are then unspecified.
    ///
    /// # Panics
    /// If the rows reach past the last row, `weights` is shorter than their slots or
    /// `positions` is shorter than the mesh's vertex count.
    pub fn block(
        &self,
        first: usize,
        positions: &[DVec3],
        weights: &mut [f64],
        scales: &mut [f64],
    ) -> bool {
        match self.kernel {
            RowKernel::Uniform { negative } => {
                self.block_as(first, weights, scales, |_, _, w| fill_uniform(negative, w))
            }
            RowKernel::InverseDistance { negative } => {
                self.inverse_distance_block(negative, first, positions, weights, scales)
            }
            RowKernel::Cotangent {
                negative,
                slot_cots,
                face_cots,
            } => self.block_as(first, weights, scales, |_, s, w| {
                fill_cotangent(negative, &slot_cots[s..], face_cots, w)
            }),
            RowKernel::CotangentRing {
                negative,
                triangles,
            } => self.cotangent_block(negative, triangles, first, positions, weights, scales),
        }
    }

    /// [`block`](Self::block) of cotangent rows: a function of its own, so that the ring
    /// kernel is inlined into its loop (as in `inverse_distance_block`).
    #[inline(never)]
    fn cotangent_block(
        &self,
        negative: NegativeWeights,
        triangles: &[u64],
        first: usize,
        positions: &[DVec3],
        weights: &mut [f64],
        scales: &mut [f64],
    ) -> bool {
        let nb = self.neighbours;
        self.block_as(first, weights, scales, |i, s, w| {
            fill_cotangent_ring::<2>(negative, positions, i, s, &nb[s..], triangles, w)
        })
    }

    /// [`block`](Self::block) of inverse-distance rows: every slot's squared length
    /// first, then all the block's weights at once in full vector registers
    /// ([`lengths_with`]), then each row's sum; the bits of
    /// [`fill_inverse_distance`] (the geometry's distance, `1 / (d + ε)`, the sum in row
    /// order), which computes the block row by row instead when a length is not plain
    /// (coincident vertices, coordinates beyond 1e±154).
    #[inline(never)]
    fn inverse_distance_block(
        &self,
        negative: NegativeWeights,
        first: usize,
        positions: &[DVec3],
        weights: &mut [f64],
        scales: &mut [f64],
    ) -> bool {
        let nb = self.neighbours;
        let bounds = &self.offsets[first..=first + scales.len()];
        let base = bounds[0] as usize;
        // The block's slots only (a longer buffer's tail is not the block's).
        let weights = &mut weights[..bounds[scales.len()] as usize - base];
        let mut a = 0;
        for (i, &end) in (first..).zip(&bounds[1..]) {
            let b = end as usize - base;
            let xi = positions[i];
            for (w, &j) in weights[a..b].iter_mut().zip(&nb[base + a..base + b]) {
                *w = (positions[j as usize] - xi).length_squared();
            }
            a = b;
        }
        let eps = crate::DISTANCE_EPSILON;
        // `negative.apply`, written out per policy, as in `fill_inverse_distance`.
        let plain = match negative {
            NegativeWeights::Keep => lengths_with(weights, |d| 1.0 / (d + eps)),
            NegativeWeights::Clamp => lengths_with(weights, |d| (1.0 / (d + eps)).max(0.0)),
            NegativeWeights::Abs => lengths_with(weights, |d| (1.0 / (d + eps)).abs()),
        };
        if plain {
            self.block_as(first, weights, scales, |_, _, w| row_sum_of(w))
        } else {
            self.block_as(first, weights, scales, |i, s, w| {
                fill_inverse_distance::<2>(negative, positions, i, &nb[s..], w)
            })
        }
    }

    /// [`block`](Self::block) with the kernel's fill `fill(i, first_slot, weights)`.
    #[inline(always)]
    fn block_as<F>(&self, first: usize, weights: &mut [f64], scales: &mut [f64], fill: F) -> bool
    where
        F: Fn(usize, usize, &mut [f64]) -> f64,
    {
        let n = scales.len();
        let bounds = &self.offsets[first..=first + n];
        let base = bounds[0] as usize;
        let mut a = 0;
        let mut finite = true;
        for (k, (&end, scale)) in bounds[1..].iter().zip(scales.iter_mut()).enumerate() {
            let b = end as usize - base;
            let w = &mut weights[a..b];
            let i = first + k;
            let sum = fill(i, base + a, w);
            finite &= sum.is_finite();
            let area = self.areas.as_ref().map(|areas| areas[i]);
            *scale = row_scale(sum, area, w.is_empty());
            a = b;
        }
        finite
    }

    /// Row `i`'s scale alone (0 for a stuck row), or `None` as [`row`](Self::row).
    ///
    /// # Panics
    /// As [`row`](Self::row).
    #[must_use]
    pub fn scale(&self, i: usize, positions: &[DVec3]) -> Option<f64> {
        let len = (self.offsets[i + 1] - self.offsets[i]) as usize;
        // The weights in a buffer on the stack where they fit (nearly every row): the
        // sweeps ask for the boundary rows' scales every iteration, and an allocation
        // for each took a twentieth of a small open mesh's run.
        let mut small = [0.0; 32];
        if len <= small.len() {
            self.row(i, positions, &mut small)
        } else {
            self.row(i, positions, &mut vec![0.0; len])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Cotangent, CotangentKernel, InverseDistance, LaplacianOptions, Uniform};
    use beltrami_halfedge::geometry::VertexAreaKind;
    use beltrami_halfedge::primitives;

    /// `p` moved by a deterministic wobble (no two vertices alike).
    fn wobble(p: &[DVec3], amount: f64) -> Vec<DVec3> {
        p.iter()
            .enumerate()
            .map(|(i, &p)| {
                let t = i as f64;
                p + DVec3::new((1.3 * t).sin(), (2.1 * t).cos(), (0.7 * t).sin()) * amount
            })
            .collect()
    }

    fn row_bits(lap: &Laplacian) -> (Vec<u64>, Vec<u64>, Vec<u64>, usize) {
        let rows = lap.rows();
        let sums = (0..lap.n_rows())
            .map(|i| {
                lap.weight_sum(beltrami_halfedge::VertexId::new(i as u32))
                    .to_bits()
            })
            .collect();
        (
            rows.weights.iter().map(|w| w.to_bits()).collect(),
            rows.scales.iter().map(|s| s.to_bits()).collect(),
            sums,
            lap.stuck_rows(),
        )
    }

    /// Without the mesh, `update` and `fresh_rows` give the bits they give with it:
    /// every built-in scheme, both cotangent kernels, every normalisation, on a closed
    /// sphere and an open grid.
    #[test]
    fn rows_without_the_mesh_have_the_bits_of_the_rows_with_it() {
        let sphere = primitives::icosphere(3);
        let grid = primitives::grid(9, 7);
        let schemes: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
        for shape in [sphere, grid] {
            let mesh = shape.mesh().unwrap();
            let x = wobble(&shape.positions, 0.02);
            let y = wobble(&x, 0.03);
            for scheme in schemes {
                for kernel in [CotangentKernel::PerTriangle, CotangentKernel::Ring] {
                    for normalization in [
                        Normalization::WeightSum,
                        Normalization::Area(VertexAreaKind::Barycentric),
                        Normalization::Area(VertexAreaKind::MixedVoronoi),
                    ] {
                        let options = LaplacianOptions::new()
                            .normalization(normalization)
                            .cotangent_kernel(kernel);
                        let mut with = Laplacian::new(&mesh, &x, scheme, options).unwrap();
                        let mut without = with.clone();
                        assert!(without.detach(&mesh, &x, scheme));
                        assert!(without.is_detached());
                        with.update(&mesh, &y, scheme).unwrap();
                        assert!(without.update_detached(&y, scheme));
                        assert_eq!(row_bits(&with), row_bits(&without), "{options:?}");
                        let n = with.n_rows();
                        let a = with.fresh_rows(&mesh, &x, scheme).unwrap();
                        let b = without.fresh_rows_detached(&x, scheme).unwrap();
                        let (mut wa, mut wb) = (vec![0.0; 64], vec![0.0; 64]);
                        for i in 0..n {
                            let sa = a.row(i, &x, &mut wa).map(f64::to_bits);
                            let sb = b.row(i, &x, &mut wb).map(f64::to_bits);
                            assert_eq!(sa, sb, "{options:?}, row {i}");
                            assert_eq!(
                                wa.iter().map(|w| w.to_bits()).collect::<Vec<_>>(),
                                wb.iter().map(|w| w.to_bits()).collect::<Vec<_>>()
                            );
                        }
                    }
                }
            }
        }
    }

    /// `scale` is the scale `row` gives, for rows that fit its buffer on the stack and
    /// for a row that does not (the centre of a fan of 40 triangles).
    #[test]
    fn a_rows_scale_alone_is_the_rows() {
        let n = 40u32;
        let mut positions = vec![DVec3::new(0.0, 0.0, 0.3)];
        positions.extend((0..n).map(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / f64::from(n);
            DVec3::new(t.cos(), t.sin(), 0.05 * (3.0 * t).sin())
        }));
        let fan: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
        let mesh = beltrami_halfedge::HalfedgeMesh::from_polygons(positions.len(), fan).unwrap();
        let schemes: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
        for scheme in schemes {
            let mut lap =
                Laplacian::new(&mesh, &positions, scheme, LaplacianOptions::new()).unwrap();
            let rows = lap.fresh_rows(&mesh, &positions, scheme).unwrap();
            let mut weights = vec![0.0; 64];
            for i in 0..positions.len() {
                let want = rows.row(i, &positions, &mut weights).map(f64::to_bits);
                assert_eq!(rows.scale(i, &positions).map(f64::to_bits), want, "row {i}");
                assert!(want.is_some());
            }
        }
    }

    /// A mesh with polygon faces, a scheme of the caller's own, and positions that do
    /// not match are not detached; an operator that is not detached computes nothing
    /// without the mesh.
    #[test]
    fn what_needs_the_mesh_is_not_detached() {
        let cube = primitives::cube_quads();
        let mesh = cube.mesh().unwrap();
        let options = LaplacianOptions::default();
        let mut lap = Laplacian::new(&mesh, &cube.positions, &Uniform, options).unwrap();
        assert!(!lap.detach(&mesh, &cube.positions, &Uniform));
        assert!(!lap.is_detached());
        assert!(!lap.update_detached(&cube.positions, &Uniform));
        assert!(lap.fresh_rows_detached(&cube.positions, &Uniform).is_none());

        struct Mine;
        impl WeightScheme for Mine {
            fn name(&self) -> &str {
                "mine"
            }
            fn weight(
                &self,
                _: &crate::WeightContext<'_>,
                _: beltrami_halfedge::HalfedgeId,
            ) -> f64 {
                2.0
            }
        }
        let sphere = primitives::icosphere(1);
        let mesh = sphere.mesh().unwrap();
        let x = &sphere.positions;
        let mut lap = Laplacian::new(&mesh, x, &Mine, options).unwrap();
        assert!(!lap.detach(&mesh, x, &Mine));
        assert!(!lap.detach(&mesh, &x[1..], &Uniform));
        assert!(lap.detach(&mesh, x, &Uniform));
        assert!(!lap.update_detached(&x[1..], &Uniform));
        assert!(!lap.update_detached(x, &Mine));
        assert!(lap.update_detached(x, &Uniform));
        assert_eq!(Laplacian::curve_weight_detached(&Mine, x[0], x[1]), None);
        assert_eq!(
            Laplacian::curve_weight_detached(&Uniform, x[0], x[1]),
            Some(1.0)
        );
    }

    /// A non-finite weight is left to `update` with the mesh, which names its halfedge.
    #[test]
    fn a_non_finite_weight_needs_the_mesh() {
        let sphere = primitives::icosphere(1);
        let mesh = sphere.mesh().unwrap();
        let mut x = sphere.positions.clone();
        let options = LaplacianOptions::default();
        let mut lap = Laplacian::new(&mesh, &x, &InverseDistance, options).unwrap();
        assert!(lap.detach(&mesh, &x, &InverseDistance));
        x[3].x = f64::NAN;
        assert!(!lap.update_detached(&x, &InverseDistance));
        assert!(lap.update(&mesh, &x, &InverseDistance).is_err());
    }
}
