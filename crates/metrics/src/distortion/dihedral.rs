//! Dihedral angles, feature edges of the reference and their blurring by smoothing.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, EdgeId, EdgeMap, FaceId};

use super::{check_finite_positions, check_same_topology};
use crate::MetricsError;

/// The dihedral angle of edge `e` in degrees: the angle between the unit normals of its
/// two faces, `atan2(|n₁ × n₂|, n₁ · n₂)`, in `[0, 180]`; 0 where the surface is flat
/// across the edge, 90 at a cube's edge, 180 where it folds back onto itself.
///
/// The angle is unsigned: a convex and a concave edge of the same sharpness have the same
/// angle. The `atan2` form is accurate near 0° and 180°, where `acos` of the dot product
/// loses half the digits.
///
/// `None` for a boundary edge (one face only) and when a face normal is undefined (a
/// degenerate face, see [`Geometry::face_normal`], or non-finite positions).
///
/// # Panics
/// If `e` is not an edge of the mesh.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, EdgeId};
/// use beltrami_metrics::distortion::dihedral_angle;
///
/// let cube = primitives::cube();
/// let mesh = cube.mesh()?;
/// let geometry = Geometry::new(&mesh, &cube.positions)?;
/// let angles: Vec<f64> = mesh.edges().filter_map(|e| dihedral_angle(&geometry, e)).collect();
/// assert_eq!(angles.iter().filter(|&&a| (a - 90.0).abs() < 1e-12).count(), 12);
/// assert_eq!(angles.iter().filter(|&&a| a == 0.0).count(), 6); // the face diagonals
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[must_use]
pub fn dihedral_angle(geometry: &Geometry<'_>, e: EdgeId) -> Option<f64> {
    let (f, g) = edge_faces(geometry, e)?;
    angle_between(geometry.face_normal(f), geometry.face_normal(g))
}

/// The dihedral angle of every edge in degrees (see [`dihedral_angle`]), `None` at
/// boundary edges and where a face normal is undefined.
///
/// # Complexity
/// O(F + H); each face normal is computed once.
#[must_use]
pub fn dihedral_angles(geometry: &Geometry<'_>) -> EdgeMap<Option<f64>> {
    let normals = geometry.face_normals();
    EdgeMap::from_vec(
        geometry
            .mesh()
            .edges()
            .map(|e| {
                let (f, g) = edge_faces(geometry, e)?;
                angle_between(normals[f], normals[g])
            })
            .collect(),
    )
}

/// One feature edge of the reference with its dihedral angle before and after smoothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureEdge {
    /// The edge (an edge of the reference mesh).
    pub edge: EdgeId,
    /// Its dihedral angle on the reference, in degrees.
    pub reference_deg: f64,
    /// The angle between the smoothed normals of the same two faces, in degrees.
    pub smoothed_deg: f64,
}

/// Mean, minimum and maximum of a set of angles, in degrees; all 0 for an empty set.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AngleSummary {
    /// The mean angle.
    pub mean: f64,
    /// The smallest angle.
    pub min: f64,
    /// The largest angle.
    pub max: f64,
}

impl AngleSummary {
    fn of(angles: impl Iterator<Item = f64>) -> Self {
        let mut count = 0usize;
        let mut sum = 0.0;
        let mut min = f64::INFINITY;
        let mut max = f64::NEG_INFINITY;
        for a in angles {
            count += 1;
            sum += a;
            min = min.min(a);
            max = max.max(a);
        }
        if count == 0 {
            return Self::default();
        }
        Self {
            mean: sum / count as f64,
            min,
            max,
        }
    }
}

/// How smoothing blurred the sharp edges of a reference: its feature edges with their
/// dihedral angles before and after. See [`feature_edge_distortion`].
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureEdgeDistortion {
    /// The threshold in degrees: feature edges have a reference angle at least this large.
    pub threshold_deg: f64,
    /// The feature edges whose smoothed angle is defined, in edge order. Its length is the
    /// number of edges the statistics are over.
    pub edges: Vec<FeatureEdge>,
    /// The number of feature edges of the reference left out because a face beside them is
    /// degenerate on the smoothed mesh (the smoothed angle is undefined).
    pub undefined: usize,
    /// The reference angles of [`edges`](Self::edges).
    pub reference: AngleSummary,
    /// The smoothed angles of [`edges`](Self::edges).
    pub smoothed: AngleSummary,
    /// The mean loss of sharpness in degrees, `mean(reference − smoothed)` over
    /// [`edges`](Self::edges); positive when smoothing rounded the edges off. 0 when there
    /// is no feature edge.
    pub mean_loss: f64,
}

/// The dihedral angles at the feature edges of `reference` before and after smoothing,
/// which quantifies how much smoothing blurred the sharp edges (on the paper's Block).
///
/// A feature edge is an interior edge whose dihedral angle on the reference (see
/// [`dihedral_angle`]) is at least `threshold_deg` degrees. For each, the smoothed angle
/// is the angle between the normals of the same two faces on `smoothed`; the summary
/// gives the mean, minimum and maximum of both, and the mean loss
/// `Σ (reference − smoothed) / count`. Edges whose faces are degenerate on the reference
/// are never features; those whose smoothed angle is undefined are counted in
/// [`undefined`](FeatureEdgeDistortion::undefined) and left out of every statistic.
///
/// # Errors
/// - [`MetricsError::InvalidParameter`] unless `0 < threshold_deg < 180`;
/// - [`MetricsError::TopologyMismatch`] when the meshes do not share their topology;
/// - [`MetricsError::NonFinite`] for a non-finite position.
///
/// # Complexity
/// O(F + H).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::distortion::feature_edge_distortion;
///
/// let cube = primitives::cube();
/// let mesh = cube.mesh()?;
/// let geometry = Geometry::new(&mesh, &cube.positions)?;
/// let report = feature_edge_distortion(&geometry, &geometry, 45.0)?;
/// assert_eq!(report.edges.len(), 12);
/// assert!((report.reference.mean - 90.0).abs() < 1e-12);
/// assert_eq!(report.mean_loss, 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// X. Sun, P. L. Rosin, R. R. Martin, F. C. Langbein: *Fast and effective
/// feature-preserving mesh denoising*. IEEE TVCG 13(5), 2007 (sharp features under
/// smoothing).
pub fn feature_edge_distortion(
    reference: &Geometry<'_>,
    smoothed: &Geometry<'_>,
    threshold_deg: f64,
) -> Result<FeatureEdgeDistortion, MetricsError> {
    if !(threshold_deg > 0.0 && threshold_deg < 180.0) {
        return Err(MetricsError::InvalidParameter {
            name: "feature-edge threshold",
            reason: "must be an angle in degrees strictly between 0 and 180",
        });
    }
    check_same_topology(reference.mesh(), smoothed.mesh())?;
    check_finite_positions(reference.positions())?;
    check_finite_positions(smoothed.positions())?;

    let before = reference.face_normals();
    let after = smoothed.face_normals();
    let mut edges = Vec::new();
    let mut undefined = 0;
    for e in reference.mesh().edges() {
        let Some((f, g)) = edge_faces(reference, e) else {
            continue;
        };
        let Some(reference_deg) = angle_between(before[f], before[g]) else {
            continue;
        };
        if reference_deg < threshold_deg {
            continue;
        }
        // Faces correspond by index (checked above), so the smoothed angle is taken
        // between the same two faces; edge ids are not assumed to correspond.
        match angle_between(after[f], after[g]) {
            Some(smoothed_deg) => edges.push(FeatureEdge {
                edge: e,
                reference_deg,
                smoothed_deg,
            }),
            None => undefined += 1,
        }
    }
    let mean_loss = if edges.is_empty() {
        0.0
    } else {
        edges
            .iter()
            .map(|e| e.reference_deg - e.smoothed_deg)
            .sum::<f64>()
            / edges.len() as f64
    };
    Ok(FeatureEdgeDistortion {
        threshold_deg,
        reference: AngleSummary::of(edges.iter().map(|e| e.reference_deg)),
        smoothed: AngleSummary::of(edges.iter().map(|e| e.smoothed_deg)),
        edges,
        undefined,
        mean_loss,
    })
}

/// The two faces of an interior edge, `None` for a boundary edge.
fn edge_faces(geometry: &Geometry<'_>, e: EdgeId) -> Option<(FaceId, FaceId)> {
    let mesh = geometry.mesh();
    let [h, t] = e.halfedges();
    Some((mesh.face(h)?, mesh.face(t)?))
}

/// The angle in degrees between two unit normals, `None` when one is zero or not finite.
fn angle_between(n1: DVec3, n2: DVec3) -> Option<f64> {
    let defined = |n: DVec3| n.is_finite() && n != DVec3::ZERO;
    (defined(n1) && defined(n2)).then(|| n1.cross(n2).length().atan2(n1.dot(n2)).to_degrees())
}
