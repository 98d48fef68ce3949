//! Displacement of the boundary vertices, split along the original vertex normal.

use beltrami_halfedge::geometry::{Geometry, NormalWeighting};

use super::{check_finite_positions, check_same_topology, robust_length};
use crate::MetricsError;

/// How far smoothing moved the boundary vertices, in the unit of the positions.
///
/// With `Δ = y − x` the displacement of a boundary vertex from its original position `x`
/// to its smoothed position `y`, `n` the unit angle-weighted vertex normal of the
/// *original* mesh at that vertex, and `m` the unit inward co-normal of the original
/// boundary there (tangent to the surface, perpendicular to the boundary, pointing into
/// the surface):
///
/// - total: `|Δ|`;
/// - normal part: `Δ · n` (signed: positive when the vertex moved to the side the
///   normal points to), reported as its absolute value and its signed mean;
/// - tangential part: `|Δ − (Δ · n) n|`, the rest of the displacement, in the tangent
///   plane of the original surface;
/// - inward part: `Δ · m` (signed: positive when the boundary moved into the surface,
///   i.e. the surface shrank there; negative when it grew outwards).
///
/// Means are over the [`count`](Self::count) boundary vertices; all fields are 0 when
/// there is none (closed mesh).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryDisplacement {
    /// The number of boundary vertices.
    pub count: usize,
    /// The mean of `|Δ|`.
    pub mean: f64,
    /// The root mean square of `|Δ|`.
    pub rms: f64,
    /// The largest `|Δ|`.
    pub max: f64,
    /// The mean of `|Δ · n|`.
    pub mean_normal: f64,
    /// The largest `|Δ · n|`.
    pub max_normal: f64,
    /// The mean of `Δ · n` (signed).
    pub mean_signed_normal: f64,
    /// The mean of the tangential part `|Δ − (Δ · n) n|`.
    pub mean_tangential: f64,
    /// The largest tangential part.
    pub max_tangential: f64,
    /// The mean of `Δ · m` along the inward co-normal (signed, positive inwards).
    pub mean_inward: f64,
}

/// The displacement of the boundary vertices of `smoothed` from those of `original`,
/// total and split into the part along the original vertex normal and the tangential
/// part (see [`BoundaryDisplacement`] for the formulas).
///
/// The normal is the angle-weighted vertex normal of the *original* mesh
/// ([`NormalWeighting::Angle`], Thürmer and Wüthrich): it is the direction that does not
/// depend on how the surface is triangulated (a planar region gives its plane normal
/// whatever the triangle shapes), and taking it on the original makes the split a
/// property of the reference surface, not of the result being judged. Where that normal
/// is undefined (all faces of the vertex degenerate) the normal part is 0 and the whole
/// displacement counts as tangential.
///
/// The inward co-normal at a boundary vertex `v` with boundary neighbours `p` (before it
/// along the boundary loop) and `q` (after it) is the unit vector along
/// `(q − p) × n`: boundary loops run clockwise seen from the side the normals point to, so
/// this vector points into the surface. It is 0 where undefined.
///
/// # Errors
/// - [`MetricsError::TopologyMismatch`] when the meshes do not share their topology;
/// - [`MetricsError::NonFinite`] with `what = "position"` for a non-finite position, or
///   `what = "displacement"` when a displacement `y − x` overflows.
///
/// # Complexity
/// O(V + H).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::distortion::boundary_displacement;
///
/// let grid = primitives::grid(2, 2);
/// let mesh = grid.mesh()?;
/// // Move every vertex by (0.3, 0, 0.4): normal part 0.4, tangential part 0.3.
/// let moved: Vec<DVec3> = grid.positions.iter().map(|&p| p + DVec3::new(0.3, 0.0, 0.4)).collect();
/// let d = boundary_displacement(&Geometry::new(&mesh, &grid.positions)?, &Geometry::new(&mesh, &moved)?)?;
/// assert_eq!(d.count, 8);
/// assert!((d.max - 0.5).abs() < 1e-15);
/// assert!((d.mean_normal - 0.4).abs() < 1e-15 && (d.mean_tangential - 0.3).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// G. Thürmer, C. A. Wüthrich: *Computing vertex normals from polygonal facets*. Journal
/// of Graphics Tools 3(1), 1998.
pub fn boundary_displacement(
    original: &Geometry<'_>,
    smoothed: &Geometry<'_>,
) -> Result<BoundaryDisplacement, MetricsError> {
    let mesh = original.mesh();
    check_same_topology(mesh, smoothed.mesh())?;
    check_finite_positions(original.positions())?;
    check_finite_positions(smoothed.positions())?;

    let mut count = 0usize;
    let (mut sum, mut sum_sq, mut max) = (0.0, 0.0, 0.0f64);
    let (mut sum_normal, mut max_normal, mut sum_signed_normal) = (0.0, 0.0f64, 0.0);
    let (mut sum_tangential, mut max_tangential) = (0.0, 0.0f64);
    let mut sum_inward = 0.0;
    for v in mesh.vertices() {
        // The outgoing halfedge of a boundary vertex is its boundary halfedge; isolated
        // vertices have none and are not on the surface.
        let Some(out) = mesh.outgoing_halfedge(v) else {
            continue;
        };
        if !mesh.is_boundary_halfedge(out) {
            continue;
        }
        let delta = smoothed.position(v) - original.position(v);
        if !delta.is_finite() {
            return Err(MetricsError::NonFinite {
                what: "displacement",
                index: v.index(),
            });
        }
        let n = original.vertex_normal(v, NormalWeighting::Angle);
        let along = delta.dot(n);
        let tangential = robust_length(delta - along * n);
        let next = original.position(mesh.to_vertex(out));
        let previous = original.position(mesh.from_vertex(mesh.prev(out)));
        let inward = (next - previous).cross(n).normalize_or_zero();
        let length = robust_length(delta);

        count += 1;
        sum += length;
        sum_sq += length * length;
        max = max.max(length);
        sum_normal += along.abs();
        max_normal = max_normal.max(along.abs());
        sum_signed_normal += along;
        sum_tangential += tangential;
        max_tangential = max_tangential.max(tangential);
        sum_inward += delta.dot(inward);
    }
    if count == 0 {
        return Ok(BoundaryDisplacement {
            count,
            mean: 0.0,
            rms: 0.0,
            max: 0.0,
            mean_normal: 0.0,
            max_normal: 0.0,
            mean_signed_normal: 0.0,
            mean_tangential: 0.0,
            max_tangential: 0.0,
            mean_inward: 0.0,
        });
    }
    let n = count as f64;
    Ok(BoundaryDisplacement {
        count,
        mean: sum / n,
        rms: (sum_sq / n).sqrt(),
        max,
        mean_normal: sum_normal / n,
        max_normal,
        mean_signed_normal: sum_signed_normal / n,
        mean_tangential: sum_tangential / n,
        max_tangential,
        mean_inward: sum_inward / n,
    })
}
