//! What a smoothing run does: step, iterations, boundary, weight updates.

use beltrami_halfedge::VertexId;
use beltrami_weights::LaplacianOptions;

/// How boundary vertices move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Boundary {
    /// Boundary vertices never move; their coordinates stay bit-identical. The default:
    /// a measured patch keeps its outline, as in OpenMesh and pmp-library.
    #[default]
    Fixed,
    /// Boundary vertices are smoothed like interior ones, over their own (one-sided)
    /// one-ring with the scheme's weights. The patch shrinks inwards.
    Free,
    /// Boundary vertices move along the boundary polyline only: each is pulled towards
    /// its two boundary neighbours with 1-D weights
    /// ([`WeightScheme::curve_weight`](beltrami_weights::WeightScheme::curve_weight):
    /// 1 for uniform, `1/edge length` otherwise). Needs weight-sum normalisation.
    Curve,
}

/// When the weights are computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum WeightUpdate {
    /// Recomputed from the current positions before every iteration: the geometric flow
    /// (what the paper times). The default.
    #[default]
    Every,
    /// Computed once from the input positions and frozen: a linear filter (what
    /// OpenMesh's `JacobiLaplaceSmootherT` does).
    Once,
}

/// The parameters of a smoothing run.
///
/// # Examples
/// ```
/// use beltrami_smooth::{Boundary, SmoothConfig, WeightUpdate};
/// let config = SmoothConfig::new(0.8, 100).boundary(Boundary::Free).update(WeightUpdate::Once);
/// assert_eq!(config.lambda, 0.8);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothConfig {
    /// The step λ. With weight-sum normalisation, a fraction in (0, 1]: each iteration
    /// moves a vertex that fraction of the way to its weighted neighbour average. With
    /// area normalisation, a diffusion time per iteration in length² (> 0, small).
    pub lambda: f64,
    /// The number of iterations.
    pub iterations: usize,
    /// How boundary vertices move.
    pub boundary: Boundary,
    /// When weights are computed.
    pub update: WeightUpdate,
    /// Normalisation and negative-weight policy of the Laplacian.
    pub laplacian: LaplacianOptions,
    /// Vertices that never move, whatever the boundary mode.
    pub pinned: Vec<VertexId>,
}

impl Default for SmoothConfig {
    /// The paper's step (λ = 0.8), 10 iterations, fixed boundary, weights recomputed
    /// every iteration, weight-sum normalisation, negative weights kept.
    fn default() -> Self {
        Self::new(0.8, 10)
    }
}

impl SmoothConfig {
    /// λ and the iteration count, every other setting at its default.
    #[must_use]
    pub fn new(lambda: f64, iterations: usize) -> Self {
        Self {
            lambda,
            iterations,
            boundary: Boundary::default(),
            update: WeightUpdate::default(),
            laplacian: LaplacianOptions::default(),
            pinned: Vec::new(),
        }
    }

    /// Sets the boundary mode.
    #[must_use]
    pub fn boundary(mut self, boundary: Boundary) -> Self {
        self.boundary = boundary;
        self
    }

    /// Sets the weight-update policy.
    #[must_use]
    pub fn update(mut self, update: WeightUpdate) -> Self {
        self.update = update;
        self
    }

    /// Sets the Laplacian options.
    #[must_use]
    pub fn laplacian(mut self, laplacian: LaplacianOptions) -> Self {
        self.laplacian = laplacian;
        self
    }

    /// Sets the pinned vertices.
    #[must_use]
    pub fn pinned(mut self, pinned: Vec<VertexId>) -> Self {
        self.pinned = pinned;
        self
    }
}
