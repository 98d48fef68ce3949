//! The arithmetic of the built-in weight kernels, bit for bit that of
//! `beltrami_halfedge::geometry` in the common case, with the geometry's own functions
//! as the fallback everywhere else.
//!
//! The geometry rescales edge vectors by a power of two when their largest component
//! lies outside `[2^-200, 2^200]` (so that products neither overflow nor underflow) and
//! treats NaN specially. Inside that range its frames are the plain differences, and
//! the expressions below are the geometry's, operation by operation (glam's `dot`,
//! `cross` and `length`, no fused multiply-adds). Outside it, the callers use the
//! geometry.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::DEGENERACY_RATIO;

/// 2^-200: the smallest largest-component of an edge vector the fast paths accept.
const SAFE_LO: f64 = 6.223_015_277_861_142e-61;
/// 2^200: the largest largest-component of an edge vector the fast paths accept.
const SAFE_HI: f64 = 1.606_938_044_258_990_3e60;
/// `sqrt(f64::MIN_POSITIVE)`: above it, `v.length()` is the geometry's length.
const SQRT_MIN: f64 = 1.491_668_146_240_041_3e-154;

/// Whether the largest component of `e` is finite and in `[2^-200, 2^200]`.
#[inline]
fn plain(e: DVec3) -> bool {
    let a = e.abs();
    let m = a.x.max(a.y).max(a.z);
    e.is_finite() && (SAFE_LO..=SAFE_HI).contains(&m)
}

/// `geometry::distance(p, q)` when that is the plain `(q − p).length()`; `None`
/// otherwise.
#[inline]
pub(crate) fn plain_distance(p: DVec3, q: DVec3) -> Option<f64> {
    let len = (q - p).length();
    // A NaN or infinite difference gives a NaN or infinite length, outside the range.
    (SQRT_MIN..f64::INFINITY).contains(&len).then_some(len)
}

/// `(u · v) / |u × v|`, or 0 when that is 0/0-like or not finite: the geometry's
/// corner cotangent from its products.
#[inline]
fn cot(dot: f64, cross: f64) -> f64 {
    if cross > 0.0 {
        let c = dot / cross;
        if c.is_finite() { c } else { 0.0 }
    } else {
        0.0
    }
}

/// The cotangents opposite the three halfedges of triangle `(p0, p1, p2)` (in face
/// order, the halfedges ending at p0, p1, p2), 0 for a degenerate triangle: the bits of
/// `Geometry::face_opposite_cotangents`. `None` when an edge vector is outside the
/// plain range; the caller then asks the geometry.
#[inline]
pub(crate) fn face_cotangents(p0: DVec3, p1: DVec3, p2: DVec3) -> Option<[f64; 3]> {
    // Edge vectors p1 − p0, p2 − p0 and p2 − p1. Every frame of the geometry's
    // degeneracy test and corner products is built from two of them (up to sign, which
    // subtraction reproduces exactly), so when all three are plain so are the frames.
    let s1 = p1 - p0;
    let s2 = p2 - p0;
    if !(plain(s1) && plain(s2) && plain(p2 - p1)) {
        return None;
    }
    // Degeneracy, in the frame at p0 (spans are the plain differences).
    let s3 = s2 - s1;
    let longest2 = s1.dot(s1).max(s2.dot(s2)).max(s3.dot(s3));
    let two_area = s1.cross(s2).length();
    if two_area <= DEGENERACY_RATIO * longest2 || two_area.is_nan() {
        return Some([0.0; 3]);
    }
    // Corner 0 at p0: u = p1 − p0, v = p2 − p0 (its cross product is `two_area`).
    let c0 = cot(s1.dot(s2), two_area);
    // Corner 1 at p1: u = p2 − p1, v = p0 − p1.
    let (u, v) = (p2 - p1, p0 - p1);
    let c1 = cot(u.dot(v), u.cross(v).length());
    // Corner 2 at p2: u = p0 − p2, v = p1 − p2.
    let (u, v) = (p0 - p2, p1 - p2);
    let c2 = cot(u.dot(v), u.cross(v).length());
    // h0 ends at p0, so its opposite corner is p1; h1 ↔ p2; h2 ↔ p0.
    Some([c1, c2, c0])
}
