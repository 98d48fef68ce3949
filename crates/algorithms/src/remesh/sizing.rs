//! The curvature-adaptive sizing field of Dunyach et al. (2013), as pmp-library's
//! `adaptive_remeshing` computes it: the edge length whose chord deviates by the allowed
//! error from a circle of the largest principal curvature radius, clamped to
//! `[min_edge, max_edge]`.

use std::f64::consts::PI;

use beltrami_halfedge::edit::EdgeProperty;
use beltrami_halfedge::{DVec3, EditMesh, HalfedgeId, VertexId};

use super::curves::feature_count;

/// The cotangent of the angle opposite `h` in its triangle; 0 on the boundary or for a
/// degenerate corner.
fn opposite_cot(mesh: &EditMesh, h: HalfedgeId) -> f64 {
    let Some(o) = mesh.opposite_vertex(h) else {
        return 0.0;
    };
    let u = mesh.position(mesh.from_vertex(h)) - mesh.position(o);
    let v = mesh.position(mesh.to_vertex(h)) - mesh.position(o);
    let c = u.dot(v) / u.cross(v).length();
    if c.is_finite() { c } else { 0.0 }
}

/// The largest absolute principal curvature at interior vertex `v`, from the mean
/// curvature (cotangent Laplacian) and the Gaussian curvature (angle defect), both over
/// the barycentric area: `|H| + sqrt(max(H² − K, 0))`. `None` where the area vanishes.
fn max_abs_curvature(mesh: &EditMesh, v: VertexId) -> Option<f64> {
    let p = mesh.position(v);
    let mut laplace = DVec3::ZERO;
    let mut area = 0.0;
    let mut angles = 0.0;
    for h in mesh.halfedges_around_vertex(v) {
        let w = mesh.position(mesh.to_vertex(h));
        let weight = opposite_cot(mesh, h) + opposite_cot(mesh, h.twin());
        laplace += weight * (w - p);
        if let Some(o) = mesh.opposite_vertex(h) {
            let q = mesh.position(o);
            area += (w - p).cross(q - p).length() / 6.0;
            let angle = (w - p).angle_between(q - p);
            if angle.is_finite() {
                angles += angle;
            }
        }
    }
    if area.is_nan() || area <= 0.0 {
        return None;
    }
    let h = laplace.length() / (4.0 * area);
    let k = (2.0 * PI - angles) / area;
    let c = h + (h * h - k).max(0.0).sqrt();
    c.is_finite().then_some(c)
}

/// The target edge length at each vertex (indexed by vertex index, `vertex_capacity`
/// long): the curvature at interior vertices off the features, smoothed twice over the
/// neighbours whose curvature is known (which also gives feature and boundary vertices
/// a value), then turned into the length `h = sqrt(6 e r − 3 e²)` of a chord that
/// deviates by `e = approx_error` from a circle of radius `r = 1/curvature` (`√3 e`
/// when `e ≥ r`), clamped to `[min_edge, max_edge]`.
pub(super) fn sizing_field(
    mesh: &EditMesh,
    feature: EdgeProperty<bool>,
    min_edge: f64,
    max_edge: f64,
    approx_error: f64,
) -> Vec<f64> {
    let n = mesh.vertex_capacity();
    let mut curvature = vec![-1.0; n];
    for v in mesh.vertices() {
        if feature_count(mesh, feature, v) == 0
            && !mesh.is_boundary_vertex(v)
            && let Some(c) = max_abs_curvature(mesh, v)
        {
            curvature[v.index()] = c;
        }
    }
    for _ in 0..2 {
        let mut next = curvature.clone();
        for v in mesh.vertices() {
            let known = std::iter::once(v)
                .chain(mesh.vertices_around_vertex(v))
                .map(|w| curvature[w.index()])
                .filter(|&c| c >= 0.0);
            let (sum, count) = known.fold((0.0, 0usize), |(s, k), c| (s + c, k + 1));
            if count > 0 {
                next[v.index()] = sum / count as f64;
            }
        }
        curvature = next;
    }
    curvature
        .into_iter()
        .map(|c| {
            let e = approx_error;
            let h = if c <= 0.0 {
                max_edge
            } else if e < 1.0 / c {
                (6.0 * e / c - 3.0 * e * e).sqrt()
            } else {
                3f64.sqrt() * e
            };
            h.clamp(min_edge, max_edge)
        })
        .collect()
}
