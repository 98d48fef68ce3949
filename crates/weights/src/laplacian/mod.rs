//! The assembled Laplace–Beltrami operator: one row per vertex, in one-ring order.
//!
//! `options` (normalisation, negative weights), `cotangent_plan` (the cotangent
//! kernel's per-face data), `assembly` (filling the rows), `fresh` (rows computed one
//! at a time and not stored) and this file (the rows and their arithmetic).

mod assembly;
mod cotangent_plan;
mod fresh;
mod options;

use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId};
use rayon::prelude::*;

use crate::PAR_CHUNK;
use crate::error::WeightError;
use crate::scheme::WeightScheme;
use cotangent_plan::CotangentPlan;
pub use fresh::FreshRows;
pub use options::{LaplacianOptions, NegativeWeights, Normalization};

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
    halfedges: Vec<u32>,
    weights: Vec<f64>,
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
    /// The per-face data of the cotangent kernel, built on first use.
    cotangent: Option<CotangentPlan>,
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
        let n = mesh.n_vertices();
        let valences: Vec<u32> = (0..n)
            .into_par_iter()
            .with_min_len(PAR_CHUNK)
            .map(|v| {
                mesh.halfedges_around_vertex(VertexId::new(v as u32))
                    .count() as u32
            })
            .collect();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut total: u32 = 0;
        offsets.push(0);
        for &d in &valences {
            total = total.checked_add(d).expect("halfedge ids are u32");
            offsets.push(total);
        }
        let mut neighbours = vec![0u32; total as usize];
        let mut halfedges = vec![0u32; total as usize];
        // Fixed-size chunks of slots; each fills the parts of the rows it overlaps.
        neighbours
            .par_chunks_mut(PAR_CHUNK)
            .zip(halfedges.par_chunks_mut(PAR_CHUNK))
            .enumerate()
            .for_each(|(c, (nb, he))| {
                let start = c * PAR_CHUNK;
                let end = start + nb.len();
                let mut row = offsets.partition_point(|&o| o as usize <= start) - 1;
                let mut s = offsets[row] as usize;
                while s < end {
                    for h in mesh.halfedges_around_vertex(VertexId::new(row as u32)) {
                        if (start..end).contains(&s) {
                            nb[s - start] = mesh.to_vertex(h).raw();
                            he[s - start] = h.raw();
                        }
                        s += 1;
                    }
                    row += 1;
                }
            });
        let mut lap = Self {
            options,
            offsets,
            weights: vec![0.0; neighbours.len()],
            neighbours,
            halfedges,
            halfedge_weights: Vec::new(),
            n_halfedges: mesh.n_halfedges(),
            weight_sums: vec![0.0; n],
            scales: vec![0.0; n],
            stuck: 0,
            unit_weights: false,
            cotangent: None,
        };
        lap.update(mesh, positions, scheme)?;
        Ok(lap)
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
    pub fn row(&self, v: VertexId) -> impl ExactSizeIterator<Item = (VertexId, f64)> + '_ {
        let range = self.range(v.index());
        self.neighbours[range.clone()]
            .iter()
            .zip(&self.weights[range])
            .map(|(&j, &w)| (VertexId::new(j), w))
    }

    /// The halfedges of row `v` (`v → j`), in the order of [`row`](Self::row).
    pub fn row_halfedges(&self, v: VertexId) -> impl ExactSizeIterator<Item = HalfedgeId> + '_ {
        self.halfedges[self.range(v.index())]
            .iter()
            .map(|&h| HalfedgeId::new(h))
    }

    /// The rows in compressed sparse row form, read-only: what a solver or an
    /// integrator of your own (or a conversion to another sparse-matrix type) needs
    /// without copying. See [`LaplacianRows`].
    #[must_use]
    pub fn rows(&self) -> LaplacianRows<'_> {
        LaplacianRows {
            offsets: &self.offsets,
            neighbours: &self.neighbours,
            weights: &self.weights,
            scales: &self.scales,
            unit_weights: self.unit_weights,
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

    /// The slots of row `i` in `neighbours`, `halfedges` and `weights`.
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
    /// If `positions` is shorter than the mesh's vertex count.
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
            .zip(&self.weights[range])
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
            .zip(&self.weights[range])
        {
            s += (positions[j as usize] - xi) * w;
        }
        Some(s * scale)
    }

    /// `L x` for every vertex into `out` (zero for stuck rows).
    ///
    /// # Panics
    /// If `positions` or `out` is shorter than the mesh's vertex count.
    pub fn apply(&self, positions: &[DVec3], out: &mut [DVec3]) {
        for (i, o) in out.iter_mut().enumerate().take(self.n_rows()) {
            *o = self
                .laplacian_at(VertexId::new(i as u32), positions)
                .unwrap_or(DVec3::ZERO);
        }
    }
}
