//! The closest point of a triangle to a point (Eberly's region method).

use glam::DVec3;

/// Where on a triangle a closest point lies, by local index.
///
/// Corners are numbered 0, 1, 2 in the order the triangle is given; edge `k` joins corner
/// `k` to corner `(k + 1) % 3` (edge 0 = corners 0–1, edge 1 = 1–2, edge 2 = 2–0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TriangleFeature {
    /// The interior of the triangle: the closest point is the orthogonal projection.
    Interior,
    /// The relative interior of edge `k`.
    Edge(usize),
    /// Corner `k`.
    Vertex(usize),
}

/// The closest point of a triangle to a query point. See [`closest_point_on_triangle`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePoint {
    /// The closest point, in the positions' unit.
    pub point: DVec3,
    /// `|p − point|²`, in unit².
    pub distance_squared: f64,
    /// The part of the triangle that holds the point.
    pub feature: TriangleFeature,
}

/// The point of triangle `[a, b, c]` closest to `p`, exactly as in Eberly's region
/// method: with `E0 = b − a`, `E1 = c − a` and the triangle parametrised as
/// `a + s E0 + t E1` (`s, t ≥ 0`, `s + t ≤ 1`), the unconstrained minimiser of
/// `|a + s E0 + t E1 − p|²` falls in one of seven regions of the (s, t) plane (the
/// triangle, three edge strips, three corner wedges), and each region tells which edge or
/// corner to minimise over. End points are returned exactly (a corner is a vertex
/// position, bit for bit); an edge point is the projection onto that edge's segment.
///
/// **Degenerate triangles.** When twice the area is at most
/// [`DEGENERACY_RATIO`](beltrami_halfedge::geometry::DEGENERACY_RATIO) times the squared
/// longest edge (collinear or coincident corners, the halfedge crate's rule), the result
/// is the closest of the three edge segments (a zero-length segment is a point); the
/// error of this is at most the triangle's width, below `1e-12 ×` its longest edge. The
/// result is finite for all finite inputs whose coordinates stay below about `1e60` in
/// magnitude (products of four coordinates must not overflow); it is never NaN for finite
/// inputs.
///
/// # Examples
/// ```
/// use beltrami_metrics::distance::{TriangleFeature, closest_point_on_triangle};
/// use glam::DVec3;
///
/// let triangle = [DVec3::ZERO, DVec3::X, DVec3::Y];
/// let above = closest_point_on_triangle(DVec3::new(0.25, 0.25, 2.0), triangle);
/// assert_eq!(above.point, DVec3::new(0.25, 0.25, 0.0));
/// assert_eq!(above.distance_squared, 4.0);
/// assert_eq!(above.feature, TriangleFeature::Interior);
///
/// let beyond_corner = closest_point_on_triangle(DVec3::new(2.0, -1.0, 0.0), triangle);
/// assert_eq!(beyond_corner.point, DVec3::X);
/// assert_eq!(beyond_corner.feature, TriangleFeature::Vertex(1));
/// ```
///
/// # References
/// D. Eberly: *Distance Between Point and Triangle in 3D*. Geometric Tools, 1999
/// (revised 2020).
#[must_use]
pub fn closest_point_on_triangle(p: DVec3, triangle: [DVec3; 3]) -> TrianglePoint {
    PreparedTriangle::new(triangle).closest_point(p)
}

/// A triangle with the quantities of Eberly's method that do not depend on the query point,
/// computed once: a search evaluates each reference triangle for many points. The results
/// are those of [`closest_point_on_triangle`] bit for bit (it is this type's method on a
/// triangle prepared on the spot).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedTriangle {
    /// The corners, in the triangle's order.
    pub(crate) corners: [DVec3; 3],
    /// `|E0|²`, `E0 · E1`, `|E1|²`.
    aa: f64,
    bb: f64,
    cc: f64,
    /// `|E0 × E1|²`, NaN for a degenerate triangle (see [`closest_point_on_triangle`]).
    det: f64,
}

impl PreparedTriangle {
    /// Prepares `triangle` (corners `a`, `b`, `c`).
    pub(crate) fn new(triangle: [DVec3; 3]) -> Self {
        let [a, b, c] = triangle;
        let e0 = b - a;
        let e1 = c - a;
        let e2 = c - b;
        let aa = e0.dot(e0);
        let cc = e1.dot(e1);
        let longest2 = aa.max(cc).max(e2.dot(e2));
        // |E0 × E1|² (twice the area, squared) equals Eberly's det = aa·cc − bb² (Lagrange's
        // identity), without the cancellation of the difference.
        let det = e0.cross(e1).length_squared();
        let bound = beltrami_halfedge::geometry::DEGENERACY_RATIO * longest2;
        let degenerate = det <= bound * bound || det.is_nan();
        Self {
            corners: triangle,
            aa,
            bb: e0.dot(e1),
            cc,
            det: if degenerate { f64::NAN } else { det },
        }
    }

    /// The point of the triangle closest to `p` (see [`closest_point_on_triangle`]).
    #[inline]
    pub(crate) fn closest_point(&self, p: DVec3) -> TrianglePoint {
        let triangle = self.corners;
        let Self {
            aa, bb, cc, det, ..
        } = *self;
        if det.is_nan() {
            return closest_on_edges(p, triangle);
        }
        let [a, b, c] = triangle;
        let e0 = b - a;
        let e1 = c - a;
        let d = a - p;
        let dd = e0.dot(d);
        let ee = e1.dot(d);
        let s = bb * ee - cc * dd;
        let t = bb * dd - aa * ee;

        if s + t <= det {
            if s < 0.0 {
                if t < 0.0 {
                    // Region 4: the corner wedge at a; the minimum is on edge 0 or edge 2.
                    if dd < 0.0 {
                        on_edge(p, triangle, 0)
                    } else {
                        on_edge(p, triangle, 2)
                    }
                } else {
                    // Region 3: beyond edge 2 (s = 0).
                    on_edge(p, triangle, 2)
                }
            } else if t < 0.0 {
                // Region 5: beyond edge 0 (t = 0).
                on_edge(p, triangle, 0)
            } else {
                // Region 0: the projection lies inside, or exactly on the boundary (then the
                // closest edge names the feature).
                if s == 0.0 || t == 0.0 || s + t == det {
                    return closest_on_edges(p, triangle);
                }
                let point = a + e0 * (s / det) + e1 * (t / det);
                TrianglePoint {
                    point,
                    distance_squared: (p - point).length_squared(),
                    feature: TriangleFeature::Interior,
                }
            }
        } else if s < 0.0 {
            // Region 2: the corner wedge at c; the minimum is on edge 1 or edge 2.
            let tmp0 = bb + dd;
            let tmp1 = cc + ee;
            if tmp1 > tmp0 {
                on_edge(p, triangle, 1)
            } else {
                on_edge(p, triangle, 2)
            }
        } else if t < 0.0 {
            // Region 6: the corner wedge at b; the minimum is on edge 1 or edge 0.
            let tmp0 = bb + ee;
            let tmp1 = aa + dd;
            if tmp1 > tmp0 {
                on_edge(p, triangle, 1)
            } else {
                on_edge(p, triangle, 0)
            }
        } else {
            // Region 1: beyond edge 1 (s + t = 1).
            on_edge(p, triangle, 1)
        }
    }
}

/// The closest point of edge `k` (corners `k` and `k + 1`) to `p`.
#[inline]
fn on_edge(p: DVec3, triangle: [DVec3; 3], k: usize) -> TrianglePoint {
    let (from, to) = (k, (k + 1) % 3);
    let (point, at) = closest_on_segment(p, triangle[from], triangle[to]);
    let feature = match at {
        SegmentPart::Start => TriangleFeature::Vertex(from),
        SegmentPart::End => TriangleFeature::Vertex(to),
        SegmentPart::Inside => TriangleFeature::Edge(k),
    };
    TrianglePoint {
        point,
        distance_squared: (p - point).length_squared(),
        feature,
    }
}

/// The closest of the three edges (for a degenerate triangle); on ties the lower edge.
fn closest_on_edges(p: DVec3, triangle: [DVec3; 3]) -> TrianglePoint {
    let mut best = on_edge(p, triangle, 0);
    for k in 1..3 {
        let candidate = on_edge(p, triangle, k);
        if candidate.distance_squared < best.distance_squared {
            best = candidate;
        }
    }
    best
}

/// Where the closest point of a segment lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SegmentPart {
    Start,
    Inside,
    End,
}

/// The point of segment `[a, b]` closest to `p`: the projection clamped to the segment.
/// End points are returned exactly; a zero-length segment gives `a`.
#[inline]
fn closest_on_segment(p: DVec3, a: DVec3, b: DVec3) -> (DVec3, SegmentPart) {
    let ab = b - a;
    let along = (p - a).dot(ab);
    if along <= 0.0 || along.is_nan() {
        return (a, SegmentPart::Start);
    }
    let length2 = ab.dot(ab);
    if along >= length2 {
        return (b, SegmentPart::End);
    }
    (a + ab * (along / length2), SegmentPart::Inside)
}
