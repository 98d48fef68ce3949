//! How the rows of a [`Laplacian`](crate::Laplacian) are normalised and what happens to
//! negative weights.

use beltrami_halfedge::geometry::VertexAreaKind;

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
    pub(crate) fn apply(self, w: f64) -> f64 {
        match self {
            Self::Keep => w,
            Self::Clamp => w.max(0.0),
            Self::Abs => w.abs(),
        }
    }
}

/// How the cotangent scheme's kernel finds each row slot's two cotangents. Both give
/// the same bits (each cotangent is the geometry's for its corner); they trade memory
/// for time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum CotangentKernel {
    /// Each triangle's three cotangents once per update, in parallel, into a table
    /// that every row slot then gathers its two from: the fastest, and about 120 bytes
    /// per vertex of a triangle mesh more (the triangles' vertices, the table and each
    /// slot's two indices into it). The default.
    #[default]
    PerTriangle,
    /// Each row's cotangents from its neighbours in one-ring order (triangle `k` of a
    /// row is the vertex and its neighbours `k` and `k + 1`): nothing per triangle is
    /// stored (one bit per slot says whether its left face is a triangle), but every
    /// corner is computed twice, once in the row of each end of its opposite edge —
    /// twice the kernel's cross products, square roots and divisions (smoothing the
    /// level-7 sphere with the weights computed inside the sweep: 1045 against 515
    /// instructions per vertex-iteration, about 1.4× the time). For meshes that must
    /// fit in little memory.
    Ring,
}

/// Options of a [`Laplacian`](crate::Laplacian). The default is weight-sum
/// normalisation ([`Normalization::WeightSum`]) with negative weights kept
/// ([`NegativeWeights::Keep`]) and the per-triangle cotangent kernel
/// ([`CotangentKernel::PerTriangle`]).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::VertexAreaKind;
/// use beltrami_weights::{LaplacianOptions, NegativeWeights, Normalization};
/// let options = LaplacianOptions::new()
///     .normalization(Normalization::Area(VertexAreaKind::MixedVoronoi))
///     .negative(NegativeWeights::Clamp);
/// assert_eq!(options.negative, NegativeWeights::Clamp);
/// assert_eq!(LaplacianOptions::default().normalization, Normalization::WeightSum);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct LaplacianOptions {
    /// Row normalisation (default [`Normalization::WeightSum`]).
    pub normalization: Normalization,
    /// Treatment of negative weights (default [`NegativeWeights::Keep`]).
    pub negative: NegativeWeights,
    /// The cotangent scheme's kernel (default [`CotangentKernel::PerTriangle`]); the
    /// same weights either way.
    pub cotangent_kernel: CotangentKernel,
}

impl LaplacianOptions {
    /// The defaults: weight-sum normalisation, negative weights kept.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets the row normalisation.
    #[must_use]
    pub fn normalization(mut self, normalization: Normalization) -> Self {
        self.normalization = normalization;
        self
    }

    /// Sets the treatment of negative weights.
    #[must_use]
    pub fn negative(mut self, negative: NegativeWeights) -> Self {
        self.negative = negative;
        self
    }

    /// Sets the cotangent scheme's kernel.
    #[must_use]
    pub fn cotangent_kernel(mut self, kernel: CotangentKernel) -> Self {
        self.cotangent_kernel = kernel;
        self
    }
}
