//! The curvature-adaptive sizing field of Dunyach et al. (2013), as pmp-library's
//! `adaptive_remeshing` computes it: the edge length whose chord deviates by the allowed
//! error from a circle of the largest principal curvature radius, clamped to
//! `[min_edge, max_edge]`.

use std::f64::consts::PI;

use beltrami_halfedge::edit::EdgeProperty;
use beltrami_halfedge::{DVec3, EditMesh, HalfedgeId, VertexId};

use super::curves::feature_count;
use super::{AdaptiveLengths, AdaptiveSizing};

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

/// The largest absolute principal curvature at each vertex (indexed by vertex index,
/// `vertex_capacity` long): estimated at interior vertices off the features, then
/// smoothed twice over the neighbours whose curvature is known (which also gives feature
/// and boundary vertices a value); `-1` where no value is known.
pub(super) fn curvature_field(mesh: &EditMesh, feature: EdgeProperty<bool>) -> Vec<f64> {
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
}

/// The chord length `h = sqrt(6 e r − 3 e²)` whose chord deviates by `e` from a circle
/// of radius `r = 1/c` (`√3 e` when `e ≥ r`; `None` for a flat `c ≤ 0`).
fn chord_length(c: f64, e: f64) -> Option<f64> {
    if c <= 0.0 {
        None
    } else if e < 1.0 / c {
        Some((6.0 * e / c - 3.0 * e * e).sqrt())
    } else {
        Some(3f64.sqrt() * e)
    }
}

/// The deviation `e` of a chord of length `h` from a circle of curvature `c > 0`: the
/// inverse of [`chord_length`], `e = (1 − sqrt(1 − c²h²/3)) / c`, written without the
/// cancellation for small `c h`; `h / √3` when `c h ≥ √3`.
fn chord_error(c: f64, h: f64) -> f64 {
    let x = c * c * h * h / 3.0;
    if x >= 1.0 {
        h / 3f64.sqrt()
    } else {
        c * h * h / 3.0 / (1.0 + (1.0 - x).sqrt())
    }
}

/// The values of an adaptive run: those given, and the others derived from the input's
/// mean edge length `mean_edge` and its (smoothed) `curvature` field as
/// [`AdaptiveSizing`] documents.
pub(super) fn resolve(given: AdaptiveSizing, curvature: &[f64], mean_edge: f64) -> AdaptiveLengths {
    let min_edge = given
        .min_edge
        .unwrap_or_else(|| (mean_edge / 4.0).min(given.max_edge.unwrap_or(f64::INFINITY)));
    let max_edge = given
        .max_edge
        .unwrap_or_else(|| (4.0 * mean_edge).max(min_edge));
    let approx_error = given.approx_error.unwrap_or_else(|| {
        let floor = 1e-6 / mean_edge;
        let mut curved: Vec<f64> = curvature.iter().copied().filter(|&c| c > floor).collect();
        if curved.is_empty() {
            return mean_edge;
        }
        let middle = curved.len() / 2;
        let (_, median, _) = curved.select_nth_unstable_by(middle, f64::total_cmp);
        chord_error(*median, mean_edge)
    });
    AdaptiveLengths {
        min_edge,
        max_edge,
        approx_error,
    }
}

/// The target edge length at each vertex of a `curvature` field
/// ([`curvature_field`]): the length of a chord that deviates by the approximation
/// error from a circle of radius `1/curvature` ([`chord_length`]), clamped to
/// `[min_edge, max_edge]`; `max_edge` where the curvature is zero or unknown.
pub(super) fn lengths(curvature: &[f64], sizing: AdaptiveLengths) -> Vec<f64> {
    curvature
        .iter()
        .map(|&c| {
            chord_length(c, sizing.approx_error)
                .unwrap_or(sizing.max_edge)
                .clamp(sizing.min_edge, sizing.max_edge)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chord_error_inverts_the_chord_length() {
        for (c, h) in [(1.0, 0.1), (3.0, 0.01), (0.5, 1.0), (1e-4, 2.0), (2.0, 0.8)] {
            let e = chord_error(c, h);
            let back = chord_length(c, e).unwrap();
            assert!(
                (back - h).abs() <= 1e-12 * h,
                "c {c} h {h}: e {e} gives {back}"
            );
        }
        // Beyond the half circle the chord is √3 e.
        assert_eq!(chord_error(1.0, 3.0), 3.0 / 3f64.sqrt());
    }

    #[test]
    fn missing_values_come_from_the_mean_edge_and_the_median_curvature() {
        let curvature = [-1.0, 0.0, 1.0, 2.0, 4.0];
        let derived = resolve(AdaptiveSizing::default(), &curvature, 0.1);
        assert_eq!(derived.min_edge, 0.025);
        assert_eq!(derived.max_edge, 0.4);
        // The median of 1, 2 and 4 is 2: a vertex of curvature 2 gets the mean edge.
        let at_median = chord_length(2.0, derived.approx_error).unwrap();
        assert!((at_median - 0.1).abs() < 1e-15, "{at_median}");
        let field = lengths(&curvature, derived);
        assert_eq!(field[0], 0.4, "unknown curvature: the largest length");
        assert_eq!(field[1], 0.4, "flat: the largest length");
        assert!(field[2] > 0.1 && field[4] < 0.1, "{field:?}");

        // Given values are kept, and the derived ones respect them.
        let given = AdaptiveSizing {
            min_edge: None,
            max_edge: Some(0.01),
            approx_error: Some(0.5),
        };
        let kept = resolve(given, &curvature, 0.1);
        assert_eq!(
            (kept.min_edge, kept.max_edge, kept.approx_error),
            (0.01, 0.01, 0.5)
        );
        let given = AdaptiveSizing {
            min_edge: Some(1.0),
            ..AdaptiveSizing::default()
        };
        let kept = resolve(given, &curvature, 0.1);
        assert_eq!((kept.min_edge, kept.max_edge), (1.0, 1.0));

        // A flat surface: no curvature to take a median of.
        let flat = resolve(AdaptiveSizing::default(), &[0.0, 0.0, -1.0], 0.1);
        assert_eq!(flat.approx_error, 0.1);
        assert_eq!(lengths(&[0.0, -1.0], flat), vec![0.4, 0.4]);
    }
}
