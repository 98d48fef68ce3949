//! The assembled Laplace–Beltrami operator: one row per vertex, in one-ring order.
//!
//! `options` (normalisation, negative weights), `layout` (the rows' slots from the
//! mesh: neighbours, halfedges, the faces beside each slot), `assembly` (filling the
//! rows), `fresh` (rows computed one at a time and not stored) and this file (the rows
//! and their arithmetic).

mod assembly;
mod cotangent_plan;
mod fresh;
mod layout;
mod options;

use std::sync::OnceLock;

use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId};

use crate::error::WeightError;
use crate::scheme::WeightScheme;
use cotangent_plan::CotangentPlan;
pub use fresh::FreshRows;
pub use options::{CotangentKernel, LaplacianOptions, NegativeWeights, Normalization};

/// The Laplace–Beltrami operator of a mesh for one weight scheme, stored row by row:
/// row `i` lists the neighbours of vertex `i` in counter-clockwise one-ring order with
/// their weights, plus the row's scale (`1/W_i` or `1/A_i`).
///
/// A row whose weights do not sum to a positive finite value, or whose scale is not
/// positive and finite (an isolated vertex, zero vertex area), is *stuck*: its vertex must not move, and
/// [`laplacian_at`](Self::laplacian_at) returns `None`.
///
/// Sign convention: `L x_i` points from `x_i` towards its (weighted) neighbours, so
/// `x ← x + λ L x` smooths (the heat equation `∂x/∂t = Δx`).
///
/// # Memory
///
/// Per row slot (halfedge) the operator holds its neighbour (4 bytes) and, when
/// stored, its weight (8); per row its offset (4), weight sum (8) and scale (8): about
/// 92 bytes per vertex of a closed triangle mesh (six slots per vertex) with stored
/// weights, 44 without. The cotangent scheme adds its kernel's data: about 120 bytes
/// per vertex for [`CotangentKernel::PerTriangle`] (the default), one bit per slot for
/// [`CotangentKernel::Ring`]. [`heap_bytes`](Self::heap_bytes) gives the exact figure.
/// What is not kept:
///
/// - **Weights of uniform rows**: they are all 1; [`rows`](Self::rows) and
///   [`row`](Self::row) make an array of ones on first use.
/// - **Weights after [`fresh_rows`](Self::fresh_rows)**: the rows it computes replace
///   them, so it releases the stored ones; [`update`](Self::update) stores them again
///   ([`weights_stored`](Self::weights_stored) tells); an operator built by
///   [`new_without_weights`](Self::new_without_weights) starts that way. An integrator
///   that recomputes the weights inside its sweep every iteration thus never needs to
///   hold a weight array.
/// - **Halfedge ids**: the built-in kernels need none, and plug-in schemes read their
///   slots' halfedges from the mesh. They are kept only when two vertices are joined by
///   more than one edge, where a row's neighbour does not name its halfedge (see
///   [`row_halfedges`](Self::row_halfedges)).
/// - **Per-triangle data, with [`CotangentKernel::Ring`]**: that kernel computes each
///   slot's two cotangents from the row's neighbours in one-ring order (triangle `k` of
///   a row is the vertex and its neighbours `k` and `k + 1`), so every corner is
///   computed twice, once in the row of each end of its opposite edge, and nothing per
///   triangle is stored.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, VertexId};
/// use beltrami_weights::{Laplacian, LaplacianOptions, Uniform};
///
/// let hex = primitives::hexagon_fan();
/// let mesh = hex.mesh().unwrap();
/// let lap = Laplacian::new(&mesh, &hex.positions, &Uniform, LaplacianOptions::default()).unwrap();
/// // The centre of a regular hexagon is the average of its neighbours.
/// assert!(lap.laplacian_at(VertexId::new(0), &hex.positions).unwrap().length() < 1e-15);
/// assert_eq!(lap.weight_sum(VertexId::new(0)), 6.0);
/// ```
#[derive(Clone, Debug)]
pub struct Laplacian {
    options: LaplacianOptions,
    /// Row `i` is `offsets[i]..offsets[i + 1]` (halfedge counts fit in `u32`).
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    /// The halfedge of each slot, kept only when a row lists a neighbour twice (two
    /// vertices joined by more than one edge); empty otherwise.
    halfedges: Vec<u32>,
    /// The weights of the last assembly or update; unset after `fresh_rows`, and for
    /// unit weights until asked for (then ones).
    weights: OnceLock<Vec<f64>>,
    /// Per-halfedge scratch for [`WeightScheme::fill_weights`] (schemes without a
    /// built-in kernel); empty until first needed.
    halfedge_weights: Vec<f64>,
    n_halfedges: usize,
    weight_sums: Vec<f64>,
    /// `1/W_i` or `1/A_i`, positive and finite; 0 for a stuck row.
    scales: Vec<f64>,
    stuck: usize,
    /// Every weight is exactly 1 (the uniform kernel), so sweeps need not read them.
    unit_weights: bool,
    /// Bit `s` (word `s / 64`, bit `s % 64`): the face on the left of slot `s` is a
    /// triangle — the ring cotangent kernel's one input besides the rows; built on
    /// first use.
    ring_triangles: Option<Vec<u64>>,
    /// The per-triangle cotangent kernel's data, built on first use.
    cotangent: Option<CotangentPlan>,
    /// Two bits per slot: where the row's vertex stands in the triangle on the slot's
    /// left (see `layout::slot_corners`); kept by [`detach`](Self::detach) for area
    /// normalisation, empty otherwise.
    slot_corners: Vec<u64>,
    /// [`detach`](Self::detach) succeeded: the rows can be recomputed without the mesh.
    detached: bool,
}

/// The rows of a [`Laplacian`] in compressed sparse row form, borrowed: row `i` holds
/// the slots `offsets[i]..offsets[i + 1]` of `neighbours` (vertex indices, the
/// one-ring counter-clockwise) and `weights` (after the negative-weight policy), and
/// its scale `scales[i]` (`1/W_i` or `1/A_i`; 0 for a stuck row). `L x_i` is
/// `scales[i] · Σ_j w_ij x_j − x_i` (weight sum) or `scales[i] · Σ_j w_ij (x_j − x_i)`
/// (area), summed in slot order (see [`Laplacian::laplacian_at`]).
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct LaplacianRows<'a> {
    /// Row offsets into the slots, `n_rows + 1` entries from 0.
    pub offsets: &'a [u32],
    /// The neighbour vertex index of each slot.
    pub neighbours: &'a [u32],
    /// The weight of each slot.
    pub weights: &'a [f64],
    /// The scale of each row, 0 when it is stuck.
    pub scales: &'a [f64],
    /// Every weight is exactly 1 (uniform weights, no policy changed them), so an
    /// integrator need not read `weights`.
    pub unit_weights: bool,
    /// How the rows are normalised (which of the two formulas above applies).
    pub normalization: Normalization,
}

impl Laplacian {
    /// Assembles the operator of `scheme` on `mesh` at `positions`.
    ///
    /// # Errors
    /// [`WeightError::Topology`] when `positions` does not have one entry per vertex, or
    /// when mixed-Voronoi areas are asked of a mesh with non-triangular faces;
    /// [`WeightError::NonFiniteWeight`] when the scheme returns NaN or an infinity.
    ///
    /// # Complexity
    /// O(H) time and memory, in parallel.
    ///
    /// # Panics
    /// Never: row offsets are sums of halfedge counts, which fit in `u32` as the ids do.
    pub fn new(
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
        options: LaplacianOptions,
    ) -> Result<Self, WeightError> {
        let mut lap = Self::layout(mesh, options);
        lap.update(mesh, positions, scheme)?;
        Ok(lap)
    }

    /// [`new`](Self::new) without keeping the weights: the rows' sums, scales and
    /// stuck count are computed and checked as `new` does (the same errors), each row's
    /// weights in a scratch buffer; the operator is then as after
    /// [`fresh_rows`](Self::fresh_rows) ([`weights_stored`](Self::weights_stored) is
    /// `false` unless the weights are all 1) until [`update`](Self::update) stores them.
    /// For an integrator that computes every row's weights inside its sweeps
    /// ([`FreshRows`]) and so never needs a weight array (8 bytes per slot).
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn new_without_weights(
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
        options: LaplacianOptions,
    ) -> Result<Self, WeightError> {
        let mut lap = Self::layout(mesh, options);
        lap.update_as(mesh, positions, scheme, false)?;
        Ok(lap)
    }

    /// The rows' layout on `mesh`, every row empty of weights (sums and scales 0).
    fn layout(mesh: &HalfedgeMesh, options: LaplacianOptions) -> Self {
        let n = mesh.n_vertices();
        let (offsets, neighbours) = layout::rows(mesh);
        let halfedges = if layout::has_repeated_neighbour(&offsets, &neighbours) {
            layout::slot_halfedges(mesh, &offsets)
        } else {
            Vec::new()
        };
        Self {
            options,
            offsets,
            weights: OnceLock::new(),
            neighbours,
            halfedges,
            halfedge_weights: Vec::new(),
            n_halfedges: mesh.n_halfedges(),
            weight_sums: vec![0.0; n],
            scales: vec![0.0; n],
            stuck: 0,
            unit_weights: false,
            ring_triangles: None,
            cotangent: None,
            slot_corners: Vec::new(),
            detached: false,
        }
    }

    /// The options the operator was assembled with.
    #[must_use]
    pub fn options(&self) -> LaplacianOptions {
        self.options
    }

    /// The number of rows (vertices).
    #[must_use]
    pub fn n_rows(&self) -> usize {
        self.scales.len()
    }

    /// `(neighbour, weight)` pairs of row `v`, counter-clockwise, after the
    /// negative-weight policy.
    ///
    /// # Panics
    /// If the weights are not stored ([`weights_stored`](Self::weights_stored): after
    /// [`fresh_rows`](Self::fresh_rows), until the next [`update`](Self::update)).
    pub fn row(&self, v: VertexId) -> impl ExactSizeIterator<Item = (VertexId, f64)> + '_ {
        let range = self.range(v.index());
        self.neighbours[range.clone()]
            .iter()
            .zip(&self.weights()[range])
            .map(|(&j, &w)| (VertexId::new(j), w))
    }

    /// Row `v`'s neighbours (vertex indices), counter-clockwise: the columns of its
    /// weights, whether or not the weights are stored.
    ///
    /// # Panics
    /// If `v` is not a row.
    #[must_use]
    pub fn neighbours(&self, v: VertexId) -> &[u32] {
        &self.neighbours[self.range(v.index())]
    }

    /// Whether the weights can be read ([`row`](Self::row), [`rows`](Self::rows),
    /// [`laplacian_at`](Self::laplacian_at), [`apply`](Self::apply)): always after
    /// [`new`](Self::new) and [`update`](Self::update); after
    /// [`fresh_rows`](Self::fresh_rows) only for unit weights (which are not stored but
    /// made on demand), until the next `update`.
    #[must_use]
    pub fn weights_stored(&self) -> bool {
        self.unit_weights || self.weights.get().is_some()
    }

    /// The stored weights, or the unit weights made now.
    ///
    /// # Panics
    /// If they are not stored (see [`weights_stored`](Self::weights_stored)).
    #[inline]
    fn weights(&self) -> &[f64] {
        if self.unit_weights {
            return self
                .weights
                .get_or_init(|| vec![1.0; self.neighbours.len()]);
        }
        self.weights.get().expect(
            "the operator's weights were released by `fresh_rows`; `update` stores them again",
        )
    }

    /// The halfedges of row `v` (`v → j`), in the order of [`row`](Self::row), from
    /// the operator alone: available when the mesh joins some two vertices by more than
    /// one edge (where a row's neighbour does not name its halfedge); on other meshes
    /// the operator keeps no halfedge ids (the halfedge of slot `v → j` is then the one
    /// from `v` to `j`), and [`row_halfedges_in`](Self::row_halfedges_in) reads them
    /// from the mesh.
    ///
    /// # Panics
    /// If the operator keeps no halfedge ids (a mesh without multiple edges).
    pub fn row_halfedges(&self, v: VertexId) -> impl ExactSizeIterator<Item = HalfedgeId> + '_ {
        assert!(
            !self.halfedges.is_empty() || self.neighbours.is_empty(),
            "the operator keeps halfedge ids only for meshes with multiple edges; use \
             `row_halfedges_in`"
        );
        self.halfedges[self.range(v.index())]
            .iter()
            .map(|&h| HalfedgeId::new(h))
    }

    /// The halfedges of row `v` (`v → j`), in the order of [`row`](Self::row), from
    /// `mesh` (the one the operator was assembled on): its outgoing halfedges
    /// counter-clockwise, as the rows list them.
    ///
    /// # Panics
    /// If `mesh` has a different number of vertices or halfedges than at assembly.
    pub fn row_halfedges_in<'m>(
        &self,
        mesh: &'m HalfedgeMesh,
        v: VertexId,
    ) -> impl Iterator<Item = HalfedgeId> + 'm {
        assert_eq!(mesh.n_halfedges(), self.n_halfedges, "a different mesh");
        assert_eq!(mesh.n_vertices(), self.scales.len(), "a different mesh");
        mesh.halfedges_around_vertex(v)
    }

    /// The bytes of heap memory the operator holds: the capacities of its arrays
    /// (offsets, neighbours, halfedge ids when kept, weights when stored or made,
    /// the plug-in schemes' per-halfedge scratch, row sums, scales, the cotangent
    /// kernel's triangle bits or the per-triangle kernel's table, the detached slot codes). For a caller that
    /// estimates or reports its memory.
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        size_of::<u32>()
            * (self.offsets.capacity() + self.neighbours.capacity() + self.halfedges.capacity())
            + size_of::<f64>()
                * (self.weights.get().map_or(0, Vec::capacity)
                    + self.halfedge_weights.capacity()
                    + self.weight_sums.capacity()
                    + self.scales.capacity())
            + size_of::<u64>()
                * (self.ring_triangles.as_ref().map_or(0, Vec::capacity)
                    + self.slot_corners.capacity())
            + self.cotangent.as_ref().map_or(0, CotangentPlan::heap_bytes)
    }

    /// The rows in compressed sparse row form, read-only: what a solver or an
    /// integrator of your own (or a conversion to another sparse-matrix type) needs
    /// without copying. See [`LaplacianRows`].
    ///
    /// # Panics
    /// If the weights are not stored ([`weights_stored`](Self::weights_stored)).
    #[must_use]
    pub fn rows(&self) -> LaplacianRows<'_> {
        LaplacianRows {
            offsets: &self.offsets,
            neighbours: &self.neighbours,
            weights: self.weights(),
            scales: &self.scales,
            unit_weights: self.unit_weights,
            normalization: self.options.normalization,
        }
    }

    /// [`rows`](Self::rows) for an integrator that reads no weights when
    /// [`unit_weights`](LaplacianRows::unit_weights) is set: `weights` is then empty
    /// (the array of ones that `rows` makes on first use, 8 bytes per slot, is not
    /// made); otherwise exactly `rows`.
    ///
    /// # Panics
    /// If the weights are not stored and not all 1 (as [`rows`](Self::rows)).
    #[must_use]
    pub fn rows_without_unit_weights(&self) -> LaplacianRows<'_> {
        if !self.unit_weights {
            return self.rows();
        }
        LaplacianRows {
            offsets: &self.offsets,
            neighbours: &self.neighbours,
            weights: &[],
            scales: &self.scales,
            unit_weights: true,
            normalization: self.options.normalization,
        }
    }

    /// `W_i = Σ_j w_ij` of row `v` (after the negative-weight policy).
    #[must_use]
    pub fn weight_sum(&self, v: VertexId) -> f64 {
        self.weight_sums[v.index()]
    }

    /// The row scale, `1/W_i` (weight sum) or `1/A_i` (area); `None` when the row is stuck.
    #[must_use]
    pub fn scale(&self, v: VertexId) -> Option<f64> {
        let s = self.scales[v.index()];
        (s > 0.0).then_some(s)
    }

    /// The slots of row `i` in `neighbours` and `weights`.
    #[inline]
    pub(crate) fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    /// The number of stuck rows (vertices that cannot move).
    #[must_use]
    pub fn stuck_rows(&self) -> usize {
        self.stuck
    }

    /// `L x_v` at `positions`, or `None` when the row is stuck.
    ///
    /// Arithmetic, in this order (so that results are reproducible bit for bit):
    /// weight sum — `s = Σ_j w_ij x_j` in row order, then `s · (1/W_i) − x_i`; area —
    /// `s = Σ_j w_ij (x_j − x_i)` in row order, then `s · (1/A_i)`.
    ///
    /// # Panics
    /// If `positions` is shorter than the mesh's vertex count, or the weights are not
    /// stored ([`weights_stored`](Self::weights_stored)).
    #[inline]
    #[must_use]
    pub fn laplacian_at(&self, v: VertexId, positions: &[DVec3]) -> Option<DVec3> {
        let i = v.index();
        match self.options.normalization {
            Normalization::WeightSum => self.weight_sum_row(i, positions),
            Normalization::Area(_) => self.area_row(i, positions),
        }
    }

    /// `L x_i` of a weight-sum row (see [`laplacian_at`](Self::laplacian_at)).
    #[inline]
    fn weight_sum_row(&self, i: usize, positions: &[DVec3]) -> Option<DVec3> {
        let scale = self.scales[i];
        if scale <= 0.0 {
            return None;
        }
        let range = self.range(i);
        let mut s = DVec3::ZERO;
        for (&j, &w) in self.neighbours[range.clone()]
            .iter()
            .zip(&self.weights()[range])
        {
            s += positions[j as usize] * w;
        }
        Some(s * scale - positions[i])
    }

    /// `L x_i` of an area row (see [`laplacian_at`](Self::laplacian_at)).
    #[inline]
    fn area_row(&self, i: usize, positions: &[DVec3]) -> Option<DVec3> {
        let scale = self.scales[i];
        if scale <= 0.0 {
            return None;
        }
        let range = self.range(i);
        let xi = positions[i];
        let mut s = DVec3::ZERO;
        for (&j, &w) in self.neighbours[range.clone()]
            .iter()
            .zip(&self.weights()[range])
        {
            s += (positions[j as usize] - xi) * w;
        }
        Some(s * scale)
    }

    /// `L x` for every vertex into `out` (zero for stuck rows).
    ///
    /// # Panics
    /// If `positions` or `out` is shorter than the mesh's vertex count, or the weights
    /// are not stored ([`weights_stored`](Self::weights_stored)).
    pub fn apply(&self, positions: &[DVec3], out: &mut [DVec3]) {
        for (i, o) in out.iter_mut().enumerate().take(self.n_rows()) {
            *o = self
                .laplacian_at(VertexId::new(i as u32), positions)
                .unwrap_or(DVec3::ZERO);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Cotangent, Uniform};
    use beltrami_halfedge::primitives;

    /// The sum of the capacities of every array the operator holds.
    fn capacities(l: &Laplacian) -> usize {
        4 * l.offsets.capacity()
            + 4 * l.neighbours.capacity()
            + 4 * l.halfedges.capacity()
            + 8 * l.weights.get().map_or(0, Vec::capacity)
            + 8 * l.halfedge_weights.capacity()
            + 8 * l.weight_sums.capacity()
            + 8 * l.scales.capacity()
            + 8 * l.ring_triangles.as_ref().map_or(0, Vec::capacity)
            + 8 * l.slot_corners.capacity()
            + l.cotangent.as_ref().map_or(0, |p| {
                12 * p.triangles.capacity()
                    + 8 * p.slot_cots.capacity()
                    + 8 * p.face_cots.capacity()
            })
    }

    #[test]
    fn heap_bytes_is_the_sum_of_the_capacities() {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let x = &sphere.positions;
        let options = LaplacianOptions::default();
        let mut lap = Laplacian::new(&mesh, x, &Cotangent, options).unwrap();
        assert_eq!(lap.heap_bytes(), capacities(&lap));
        lap.fresh_rows(&mesh, x, &Cotangent).unwrap();
        assert_eq!(lap.heap_bytes(), capacities(&lap));
        lap.update(&mesh, x, &Uniform).unwrap();
        assert_eq!(lap.heap_bytes(), capacities(&lap));
        let _ = lap.rows();
        assert_eq!(lap.heap_bytes(), capacities(&lap));
        assert!(lap.halfedges.is_empty());
    }
}
