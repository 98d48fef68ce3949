//! The assembled Laplace–Beltrami operator: one row per vertex, in one-ring order.

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::{DVec3, FaceId, HalfedgeId, HalfedgeMesh, TopologyError, VertexId};

use rayon::prelude::*;
use wide::f64x2;

use crate::error::WeightError;
use crate::scheme::{WeightContext, WeightKernel, WeightScheme};
use crate::{PAR_CHUNK, kernels};

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
    /// Per-halfedge scratch for [`WeightScheme::fill_weights`] (schemes without a
    /// [`WeightKernel`]); empty until first needed.
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

/// What [`Laplacian::sweep_rows`] found besides the new positions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RowSweep {
    /// The rows of the range that are stuck (their vertex kept its position).
    pub stuck: usize,
    /// The sum of the new positions, in row order: finite when every new position is
    /// (a cheap test; a non-finite sum can also come from overflow, so a caller that
    /// sees one looks at the positions themselves).
    pub sum: DVec3,
}

/// The cotangent kernel's per-face data: cotangents are computed once per triangle,
/// in parallel, into `face_cots`, then every row slot gathers its two.
#[derive(Clone, Debug)]
struct CotangentPlan {
    /// Vertex ids of each triangle in face order, triangles sorted by their smallest
    /// vertex id (so that a chunk of triangles reads nearby positions).
    triangles: Vec<[u32; 3]>,
    /// The face id of each triangle, for the geometry fallback.
    face_ids: Vec<u32>,
    /// Per row slot (halfedge `h`), the indices in `face_cots` of the cotangents
    /// opposite `h` and opposite its twin; `3 × triangles.len()` (the trailing 0) for a
    /// boundary halfedge or a face that is not a triangle.
    slot_cots: Vec<[u32; 2]>,
    /// The three cotangents of each triangle (opposite the halfedges ending at its
    /// first, second and third vertex), then one 0.
    face_cots: Vec<f64>,
}

/// Triangles per parallel work unit of the cotangent kernel (fixed, like `PAR_CHUNK`).
const FACE_CHUNK: usize = 4096;

impl CotangentPlan {
    /// The plan for `mesh` with rows in `halfedges` order, or `None` when the indices
    /// do not fit in `u32`.
    fn new(mesh: &HalfedgeMesh, halfedges: &[u32]) -> Option<Self> {
        let n_faces = mesh.n_faces();
        u32::try_from(3 * n_faces).ok()?;
        // Each triangle's vertices in face order and its smallest vertex id (the sort
        // key), in parallel; `None` for a face that is not a triangle.
        let corners: Vec<Option<[u32; 3]>> = (0..n_faces)
            .into_par_iter()
            .with_min_len(PAR_CHUNK)
            .map(|f| {
                let h0 = mesh.face_halfedge(FaceId::new(f as u32));
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                (mesh.next(h2) == h0).then(|| {
                    [
                        mesh.to_vertex(h0).raw(),
                        mesh.to_vertex(h1).raw(),
                        mesh.to_vertex(h2).raw(),
                    ]
                })
            })
            .collect();
        // Triangles by their smallest vertex id (a counting sort: stable, O(F + V)).
        let mut counts = vec![0u32; mesh.n_vertices() + 1];
        for t in corners.iter().flatten() {
            counts[t[0].min(t[1]).min(t[2]) as usize + 1] += 1;
        }
        for i in 1..counts.len() {
            counts[i] += counts[i - 1];
        }
        let n_triangles = counts[mesh.n_vertices()] as usize;
        let sentinel = u32::try_from(3 * n_triangles).ok()?;
        let mut face_ids = vec![0u32; n_triangles];
        let mut triangles = vec![[0u32; 3]; n_triangles];
        // Where the cotangent opposite each halfedge lands in `face_cots` (the sentinel
        // for a boundary halfedge or a face that is not a triangle): triangle `p`'s
        // halfedges in face order take `3p`, `3p + 1`, `3p + 2`.
        let mut cot_of = vec![sentinel; mesh.n_halfedges()];
        for (f, t) in corners.iter().enumerate() {
            if let Some(t) = t {
                let slot = &mut counts[t[0].min(t[1]).min(t[2]) as usize];
                let p = *slot;
                *slot += 1;
                face_ids[p as usize] = f as u32;
                triangles[p as usize] = *t;
                let h0 = mesh.face_halfedge(FaceId::new(f as u32));
                let h1 = mesh.next(h0);
                cot_of[h0.index()] = 3 * p;
                cot_of[h1.index()] = 3 * p + 1;
                cot_of[mesh.next(h1).index()] = 3 * p + 2;
            }
        }
        drop(corners);
        let slot_cots: Vec<[u32; 2]> = halfedges
            .par_iter()
            .with_min_len(PAR_CHUNK)
            .map(|&h| {
                let h = HalfedgeId::new(h);
                [cot_of[h.index()], cot_of[h.twin().index()]]
            })
            .collect();
        Some(Self {
            triangles,
            face_ids,
            slot_cots,
            face_cots: vec![0.0; 3 * n_triangles + 1],
        })
    }

    /// Recomputes `face_cots` from `positions` (in parallel, fixed chunks; each
    /// triangle's bits are the geometry's).
    fn refresh(&mut self, geometry: &Geometry<'_>) {
        let positions = geometry.positions();
        let n = self.triangles.len();
        self.face_cots[..3 * n]
            .par_chunks_mut(3 * FACE_CHUNK)
            .zip(self.triangles.par_chunks(FACE_CHUNK))
            .zip(self.face_ids.par_chunks(FACE_CHUNK))
            .for_each(|((out, tris), ids)| {
                kernels::triangle_cotangents(positions, tris, out, |k| {
                    let t = geometry
                        .face_opposite_cotangents(FaceId::new(ids[k]))
                        .expect("a triangle");
                    [t[0].1, t[1].1, t[2].1]
                });
            });
    }
}

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
        let scale = match areas {
            None => 1.0 / sum,
            Some(a) => 1.0 / a[i],
        };
        // A row moves only when its weights sum to a positive finite value (for either
        // normalisation: a non-positive sum would push the vertex away from its
        // neighbours) and its scale is positive and finite.
        let movable =
            !row.is_empty() && sum.is_finite() && sum > 0.0 && scale.is_finite() && scale > 0.0;
        *scale_out = if movable { scale } else { 0.0 };
        tally.stuck += usize::from(!movable);
    }
    tally
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

    /// Recomputes the weights and scales from new positions, reusing the buffers. The
    /// mesh must be the one the operator was assembled on.
    ///
    /// The built-in schemes (those with a [`WeightKernel`]) are computed row by row:
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
        let kernel = scheme.kernel();
        self.unit_weights = false;
        let tally = match kernel {
            Some(WeightKernel::Uniform) => {
                let tally = row_pass(offsets, areas, rows, &|_, _, w: &mut [f64]| {
                    w.fill(negative.apply(1.0));
                    row_sum_of(w)
                });
                self.unit_weights = negative.apply(1.0) == 1.0;
                Some(tally)
            }
            Some(WeightKernel::InverseDistance) => {
                let neighbours = &self.neighbours;
                Some(row_pass(offsets, areas, rows, &|i, s, w: &mut [f64]| {
                    let nb = &neighbours[s..s + w.len()];
                    kernels::inverse_distances(positions[i], positions, nb, w, |w| {
                        negative.apply(w)
                    });
                    row_sum_of(w)
                }))
            }
            Some(WeightKernel::Cotangent) => {
                if self.cotangent.is_none() {
                    self.cotangent = CotangentPlan::new(mesh, &self.halfedges);
                }
                match &mut self.cotangent {
                    Some(plan) => {
                        plan.refresh(&geometry);
                        let (slot_cots, face_cots) = (&plan.slot_cots[..], &plan.face_cots[..]);
                        Some(row_pass(offsets, areas, rows, &|_, s, w: &mut [f64]| {
                            let pairs = &slot_cots[s..s + w.len()];
                            let cot = |[a, b]: [u32; 2]| {
                                0.5 * (face_cots[a as usize] + face_cots[b as usize])
                            };
                            // The policy is chosen once per row, not per slot; the sum is
                            // `row_sum_of`'s fold, in the same loop.
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
                        }))
                    }
                    None => None,
                }
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
    /// stuck row). The normalisation is chosen once for the whole range and the rows'
    /// neighbours and weights are walked as contiguous slices, which makes this the fast
    /// path for sweeps over many rows.
    ///
    /// # Panics
    /// If `rows` reaches past the last row or `positions` is shorter than the mesh's
    /// vertex count.
    #[inline]
    pub fn for_each_row<F>(&self, rows: std::ops::Range<usize>, positions: &[DVec3], mut f: F)
    where
        F: FnMut(usize, DVec3, Option<DVec3>),
    {
        let bounds = &self.offsets[rows.start..=rows.end.max(rows.start)];
        let slots = bounds[0] as usize..bounds[bounds.len() - 1] as usize;
        let neighbours = &self.neighbours[slots.clone()];
        let weights = &self.weights[slots];
        let scales = &self.scales[rows.clone()];
        let xs = &positions[rows.clone()];
        let area = matches!(self.options.normalization, Normalization::Area(_));
        let unit = self.unit_weights;
        let mut neighbours = neighbours;
        let mut weights = weights;
        // One loop with a single call of `f`, so that the caller's closure inlines; the
        // row arithmetic is chosen by loop-invariant flags (perfectly predicted).
        for (k, ((b, &scale), &xi)) in bounds.windows(2).zip(scales).zip(xs).enumerate() {
            let len = (b[1] - b[0]) as usize;
            let (nb, nb_rest) = neighbours.split_at(len);
            let (ws, ws_rest) = weights.split_at(len);
            neighbours = nb_rest;
            weights = ws_rest;
            let l = if scale > 0.0 {
                Some(row_sum(area, unit, xi, nb, ws, positions, scale))
            } else {
                None
            };
            f(rows.start + k, xi, l);
        }
    }

    /// One explicit diffusion step over the rows `first..first + out.len()`: writes
    /// `out[k] = x_i + λ · L x_i` for `i = first + k`, with `L x_i` exactly as
    /// [`laplacian_at`](Self::laplacian_at) computes it and `x_i + (L x_i) · λ` rounded
    /// coordinate by coordinate (the bits of the `DVec3` expression), or `x_i` for a
    /// stuck row. `positions` are read, never written (a Jacobi step).
    ///
    /// This is the explicit smoother's inner loop: one tight pass per normalisation and
    /// weight kind, with every row treated alike (a caller whose vertices do not all
    /// move overwrites those afterwards; [`RowSweep::stuck`] counts every stuck row in
    /// the range).
    ///
    /// # Panics
    /// If the rows reach past the last row or `positions` is shorter than the mesh's
    /// vertex count.
    pub fn sweep_rows(
        &self,
        first: usize,
        positions: &[DVec3],
        lambda: f64,
        out: &mut [DVec3],
    ) -> RowSweep {
        let area = matches!(self.options.normalization, Normalization::Area(_));
        match (area, self.unit_weights) {
            (false, true) => self.sweep_rows_as::<false, true>(first, positions, lambda, out),
            (false, false) => self.sweep_rows_as::<false, false>(first, positions, lambda, out),
            (true, true) => self.sweep_rows_as::<true, true>(first, positions, lambda, out),
            (true, false) => self.sweep_rows_as::<true, false>(first, positions, lambda, out),
        }
    }

    /// [`sweep_rows`](Self::sweep_rows) for one normalisation (`AREA`) and weight kind
    /// (`UNIT`: every weight is 1 and none is read). Few values live across the row loop,
    /// so that they stay in registers; the row's slots are one running offset.
    #[inline(always)]
    fn sweep_rows_as<const AREA: bool, const UNIT: bool>(
        &self,
        first: usize,
        positions: &[DVec3],
        lambda: f64,
        out: &mut [DVec3],
    ) -> RowSweep {
        let n = out.len();
        let bounds = &self.offsets[first..=first + n];
        let base = bounds[0] as usize;
        let slots = base..bounds[n] as usize;
        let neighbours = &self.neighbours[slots.clone()];
        let weights = if UNIT { &[][..] } else { &self.weights[slots] };
        let scales = &self.scales[first..first + n];
        let xs = &positions[first..first + n];
        let mut stuck = 0;
        let mut sum = Xy::ZERO;
        let mut a = 0;
        for (((o, &xi), &scale), &end) in out.iter_mut().zip(xs).zip(scales).zip(&bounds[1..]) {
            let b = end as usize - base;
            let nb = &neighbours[a..b];
            let ws = if UNIT { &[][..] } else { &weights[a..b] };
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
        RowSweep {
            stuck,
            sum: sum.to_dvec3(),
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

/// `L x_i` of a movable row (see [`Laplacian::laplacian_at`] for the arithmetic):
/// weight sum `(Σ_j w_ij x_j) · scale − x_i`, area `(Σ_j w_ij (x_j − x_i)) · scale`, the
/// sum [`gather_sum`]'s (the same bits as the `DVec3` expressions). The flags are
/// loop-invariant for a caller walking many rows (perfectly predicted).
#[inline(always)]
fn row_sum(
    area: bool,
    unit: bool,
    xi: DVec3,
    nb: &[u32],
    ws: &[f64],
    positions: &[DVec3],
    scale: f64,
) -> DVec3 {
    let x = Xy::from(xi);
    let s = match (area, unit) {
        (false, true) => gather_sum::<false, true>(nb, ws, positions, x),
        (false, false) => gather_sum::<false, false>(nb, ws, positions, x),
        (true, true) => gather_sum::<true, true>(nb, ws, positions, x),
        (true, false) => gather_sum::<true, false>(nb, ws, positions, x),
    };
    if area { s * scale } else { s * scale - x }.to_dvec3()
}

/// The row sum of [`Laplacian::sweep_rows`], from zero in row order: `Σ_j w_j x_j`, or
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
