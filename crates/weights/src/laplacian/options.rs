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

/// Options of a [`Laplacian`](crate::Laplacian). The default is weight-sum
/// normalisation ([`Normalization::WeightSum`]) with negative weights kept
/// ([`NegativeWeights::Keep`]).
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
}
