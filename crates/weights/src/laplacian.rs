//! The assembled Laplace–Beltrami operator: one row per vertex, in one-ring order.

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId};

use rayon::prelude::*;

use crate::PAR_CHUNK;
use crate::error::WeightError;
use crate::scheme::{WeightContext, WeightScheme};

/// How a row of weights is normalised.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Normalization {
    /// `L x_i = Σ_j w_ij x_j / W_i − x_i` with `W_i = Σ_j w_ij` (the paper's Eq. 2).
    /// Dimensionless: `L x_i` is the vector from `x_i` to the weighted neighbour average,
    /// so a step `λ ∈ (0, 1]` moves a vertex a fraction λ of the way there. The default.
    #[default]
    WeightSum,
    /// `L x_i = (1 / A_i) Σ_j w_ij (x_j − x_i)` with `A_i` the vertex area (the paper's
    /// Eq. 6 for cotangent weights, where `w_ij = ½(cot α + cot β)` makes this
    /// `1/(2A_i) Σ (cot α + cot β)(x_j − x_i)`). `L x` has units of 1/length (for the
    /// cotangent scheme it approximates the mean-curvature normal `−2H n`), so a step
    /// is a diffusion time in length² and must be small for explicit stability.
    Area(VertexAreaKind),
}

/// What happens to a negative weight (only the cotangent scheme produces them, when the
/// two angles opposite an edge sum to more than π). Applied to each halfedge weight —
/// for the cotangent scheme, to the summed edge weight `½(cot α + cot β)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum NegativeWeights {
    /// Use the weight as computed (the mathematically faithful operator; OpenMesh and
    /// libigl do this). A row whose weights sum to ≤ 0 cannot move.
    #[default]
    Keep,
    /// Replace it by 0 (pmp-library's explicit smoothing does this): every update stays
    /// a convex combination of the neighbours.
    Clamp,
    /// Replace it by its absolute value (what the paper mentions).
    Abs,
}

impl NegativeWeights {
    #[inline]
    fn apply(self, w: f64) -> f64 {
        match self {
            Self::Keep => w,
            Self::Clamp => w.max(0.0),
            Self::Abs => w.abs(),
        }
    }
}

/// Options of a [`Laplacian`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LaplacianOptions {
    /// Row normalisation.
    pub normalization: Normalization,
    /// Treatment of negative weights.
    pub negative: NegativeWeights,
}

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
    /// Per-halfedge scratch for [`WeightScheme::fill_weights`].
    halfedge_weights: Vec<f64>,
    weight_sums: Vec<f64>,
    /// `1/W_i` or `1/A_i`, positive and finite; 0 for a stuck row.
    scales: Vec<f64>,
    stuck: usize,
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
    /// O(H) time and memory.
    pub fn new(
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
        options: LaplacianOptions,
    ) -> Result<Self, WeightError> {
        let n = mesh.n_vertices();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut neighbours = Vec::with_capacity(mesh.n_halfedges());
        let mut halfedges = Vec::with_capacity(mesh.n_halfedges());
        offsets.push(0);
        for v in mesh.vertices() {
            for h in mesh.halfedges_around_vertex(v) {
                neighbours.push(mesh.to_vertex(h).raw());
                halfedges.push(h.raw());
            }
            offsets.push(u32::try_from(neighbours.len()).expect("halfedge ids are u32"));
        }
        let mut lap = Self {
            options,
            offsets,
            weights: vec![0.0; neighbours.len()],
            neighbours,
            halfedges,
            halfedge_weights: vec![0.0; mesh.n_halfedges()],
            weight_sums: vec![0.0; n],
            scales: vec![0.0; n],
            stuck: 0,
        };
        lap.update(mesh, positions, scheme)?;
        Ok(lap)
    }

    /// Recomputes the weights and scales from new positions, reusing the buffers. The
    /// mesh must be the one the operator was assembled on.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    ///
    /// # Panics
    /// If `mesh` has a different number of vertices or halfedges than at assembly.
    pub fn update(
        &mut self,
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
    ) -> Result<(), WeightError> {
        assert_eq!(
            mesh.n_halfedges(),
            self.halfedge_weights.len(),
            "a different mesh"
        );
        assert_eq!(mesh.n_vertices(), self.scales.len(), "a different mesh");
        let geometry = Geometry::new(mesh, positions)?;
        let ctx = WeightContext::new(geometry);
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
        let negative = self.options.negative;
        let halfedge_weights = &self.halfedge_weights;
        self.weights
            .par_chunks_mut(PAR_CHUNK)
            .zip(self.halfedges.par_chunks(PAR_CHUNK))
            .for_each(|(ws, hs)| {
                for (w, &h) in ws.iter_mut().zip(hs) {
                    *w = negative.apply(halfedge_weights[h as usize]);
                }
            });
        let areas = match self.options.normalization {
            Normalization::WeightSum => None,
            Normalization::Area(kind) => Some(geometry.vertex_areas(kind)?),
        };
        let areas = areas.as_ref().map(|a| a.as_slice());
        let (offsets, weights) = (&self.offsets, &self.weights);
        // Rows are independent: fixed-size chunks in parallel, each row summed in row
        // order, so the bits do not depend on the thread count.
        self.stuck = self
            .weight_sums
            .par_chunks_mut(PAR_CHUNK)
            .zip(self.scales.par_chunks_mut(PAR_CHUNK))
            .enumerate()
            .map(|(c, (sums, scales))| {
                let first = c * PAR_CHUNK;
                let mut stuck = 0;
                for (k, (sum_out, scale_out)) in sums.iter_mut().zip(scales).enumerate() {
                    let i = first + k;
                    let row = &weights[offsets[i] as usize..offsets[i + 1] as usize];
                    let sum: f64 = row.iter().sum();
                    *sum_out = sum;
                    let scale = match areas {
                        None => 1.0 / sum,
                        Some(a) => 1.0 / a[i],
                    };
                    // A row moves only when its weights sum to a positive finite value
                    // (for either normalisation: a non-positive sum would push the
                    // vertex away from its neighbours) and its scale is positive and
                    // finite.
                    let movable = !row.is_empty()
                        && sum.is_finite()
                        && sum > 0.0
                        && scale.is_finite()
                        && scale > 0.0;
                    *scale_out = if movable { scale } else { 0.0 };
                    stuck += usize::from(!movable);
                }
                stuck
            })
            .sum();
        Ok(())
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
    #[must_use]
    pub fn row_halfedges(&self, v: VertexId) -> &[u32] {
        &self.halfedges[self.range(v.index())]
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
    fn range(&self, i: usize) -> std::ops::Range<usize> {
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

    /// Calls `f(i, x_i, L x_i)` for every row `i` in `rows`, in increasing order, with
    /// `L x_i` exactly as [`laplacian_at`](Self::laplacian_at) computes it (`None` for a
    /// stuck row). The normalisation is chosen once for the whole range, which makes
    /// this the fast path for sweeps over many rows.
    ///
    /// # Panics
    /// If `rows` reaches past the last row or `positions` is shorter than the mesh's
    /// vertex count.
    #[inline]
    pub fn for_each_row<F>(&self, rows: std::ops::Range<usize>, positions: &[DVec3], mut f: F)
    where
        F: FnMut(usize, DVec3, Option<DVec3>),
    {
        match self.options.normalization {
            Normalization::WeightSum => {
                for i in rows {
                    f(i, positions[i], self.weight_sum_row(i, positions));
                }
            }
            Normalization::Area(_) => {
                for i in rows {
                    f(i, positions[i], self.area_row(i, positions));
                }
            }
        }
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
