//! The [`WeightScheme`] trait — the plug-in point — and the [`WeightContext`] it reads.

use std::any::Any;

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, FaceId, HalfedgeId, HalfedgeMesh, VertexId};

/// A rule that gives every halfedge `h = (i → j)` a weight `w_ij`, the coefficient of
/// neighbour `j` in the Laplacian row of vertex `i`.
///
/// Implement [`name`](Self::name) and [`weight`](Self::weight) — about twenty lines —
/// and the scheme runs through the Laplacian, smoothing, the CLI and the study unchanged
/// (register it in a [`WeightRegistry`](crate::WeightRegistry) to choose it by name).
/// The [`WeightContext`] gives the geometry, with degenerate triangles already handled:
/// [`opposite_cotangent`](WeightContext::opposite_cotangent) is 0 for them, never
/// infinite.
///
/// Weights need not be symmetric (`w_ij ≠ w_ji` is allowed) nor positive; the
/// Laplacian's [`NegativeWeights`](crate::NegativeWeights) policy treats negative ones.
/// A weight must be finite for finite positions: a scheme that can divide by a length
/// must guard it (see [`DISTANCE_EPSILON`](crate::DISTANCE_EPSILON)).
///
/// A scheme is a `'static` type (it holds its parameters, not borrowed data), so that
/// the [`Laplacian`](crate::Laplacian) can recognise this crate's built-in schemes by
/// type and evaluate them with specialised kernels that give the same bits.
///
/// # Examples
/// A Gaussian fall-off with edge length, `w = exp(−|x_j − x_i|² / σ²)`:
/// ```
/// use beltrami_weights::{WeightContext, WeightScheme};
/// use beltrami_halfedge::HalfedgeId;
///
/// struct Gaussian { sigma: f64 }
///
/// impl WeightScheme for Gaussian {
///     fn name(&self) -> &str { "gaussian" }
///     fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
///         let d = ctx.edge_vector(h).length();
///         (-(d * d) / (self.sigma * self.sigma)).exp()
///     }
/// }
/// ```
pub trait WeightScheme: Any + Send + Sync {
    /// The name users choose the scheme by (`--weights NAME`): lowercase, no spaces.
    fn name(&self) -> &str;

    /// A one-line description for `--help` and reports.
    fn description(&self) -> &str {
        ""
    }

    /// The weight of halfedge `h`, from `i = from_vertex(h)` to `j = to_vertex(h)`, in
    /// the row of vertex `i`.
    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64;

    /// Fills `out[h]` with the weight of every halfedge `h` (boundary halfedges
    /// included: they still join two vertices). The default calls
    /// [`weight`](Self::weight) for each; built-ins override it with a faster path that
    /// gives the same numbers.
    fn fill_weights(&self, ctx: &WeightContext<'_>, out: &mut [f64]) {
        for (h, w) in ctx.mesh().halfedges().zip(out.iter_mut()) {
            *w = self.weight(ctx, h);
        }
    }

    /// Whether the weights change when the positions change. `false` lets a smoother
    /// skip recomputing them (uniform weights).
    fn depends_on_positions(&self) -> bool {
        true
    }

    /// The weight of boundary halfedge neighbour `h` when a boundary vertex is smoothed
    /// along its boundary curve only (1-D smoothing, `--boundary curve`). The default is
    /// the inverse edge length `1 / (|x_j − x_i| + ε)`; uniform weights use 1.
    fn curve_weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        1.0 / (ctx.edge_length(h) + crate::DISTANCE_EPSILON)
    }
}

/// A built-in weight rule that the [`Laplacian`](crate::Laplacian) evaluates with a
/// specialised kernel, row by row in one-ring order, without a per-halfedge buffer. Each
/// kernel gives the same bits as the scheme's [`weight`](WeightScheme::weight) for
/// every halfedge. Recognised by type, so a scheme of your own always goes through its
/// [`fill_weights`](WeightScheme::fill_weights).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BuiltIn {
    /// `w = 1` ([`Uniform`](crate::Uniform)).
    Uniform,
    /// `w = 1 / (|x_j − x_i| + ε)` ([`InverseDistance`](crate::InverseDistance)).
    InverseDistance,
    /// `w = ½ (cot α + cot β)` ([`Cotangent`](crate::Cotangent)).
    Cotangent,
}

impl BuiltIn {
    /// The built-in rule `scheme` is, if it is one of this crate's schemes.
    pub(crate) fn of(scheme: &dyn WeightScheme) -> Option<Self> {
        let any: &dyn Any = scheme;
        if any.is::<crate::Uniform>() {
            Some(Self::Uniform)
        } else if any.is::<crate::InverseDistance>() {
            Some(Self::InverseDistance)
        } else if any.is::<crate::Cotangent>() {
            Some(Self::Cotangent)
        } else {
            None
        }
    }
}

/// The geometry a [`WeightScheme`] reads: the mesh, the current positions and derived
/// quantities, with degenerate triangles handled in one place.
#[derive(Clone, Copy, Debug)]
pub struct WeightContext<'a> {
    geometry: Geometry<'a>,
}

impl<'a> WeightContext<'a> {
    /// A context over `geometry` (a mesh and matching positions).
    #[must_use]
    pub fn new(geometry: Geometry<'a>) -> Self {
        Self { geometry }
    }

    /// The connectivity.
    #[must_use]
    pub fn mesh(&self) -> &'a HalfedgeMesh {
        self.geometry.mesh()
    }

    /// The geometry view (normals, areas, angles …).
    #[must_use]
    pub fn geometry(&self) -> &Geometry<'a> {
        &self.geometry
    }

    /// The current positions.
    #[must_use]
    pub fn positions(&self) -> &'a [DVec3] {
        self.geometry.positions()
    }

    /// The position of `v`.
    #[must_use]
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.geometry.positions()[v.index()]
    }

    /// `x_j − x_i` for `h = (i → j)`, in the positions' unit.
    #[must_use]
    pub fn edge_vector(&self, h: HalfedgeId) -> DVec3 {
        self.geometry.edge_vector(h)
    }

    /// `|x_j − x_i|` for `h = (i → j)`, in the positions' unit; finite wherever the
    /// distance is representable (see [`Geometry::halfedge_length`]).
    #[must_use]
    pub fn edge_length(&self, h: HalfedgeId) -> f64 {
        self.geometry.halfedge_length(h)
    }

    /// The cotangent of the angle opposite `h` in its triangle, `(u·v)/|u×v|` with `u`,
    /// `v` the edges leaving the opposite corner; 0 for a boundary halfedge and for a
    /// degenerate triangle (see
    /// [`DEGENERACY_RATIO`](beltrami_halfedge::geometry::DEGENERACY_RATIO)).
    #[must_use]
    pub fn opposite_cotangent(&self, h: HalfedgeId) -> f64 {
        self.geometry.opposite_cotangent(h)
    }

    /// The area of face `f`, in the positions' unit squared.
    #[must_use]
    pub fn face_area(&self, f: FaceId) -> f64 {
        self.geometry.face_area(f)
    }

    /// The unit normal of face `f` (zero for a degenerate face).
    #[must_use]
    pub fn face_normal(&self, f: FaceId) -> DVec3 {
        self.geometry.face_normal(f)
    }
}
