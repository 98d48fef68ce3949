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
//!
//! The batched entry points ([`triangle_cotangents`], [`inverse_distances`]) do the same
//! operations two triangles or two row slots at a time in SSE2 lanes (`wide::f64x2`,
//! see `lanes.rs`): IEEE add, multiply, divide and square root are exact per lane, so
//! every lane has the scalar bits.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::DEGENERACY_RATIO;

use wide::{CmpGe, CmpGt, CmpLe, CmpLt};

use crate::lanes::V3;

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

/// 2^-398: a squared edge length at least this has a component of at least 2^-200.
const SQUARED_LO: f64 = f64::from_bits((1023 - 398) << 52);
/// 2^400: a squared edge length below this has every component below 2^200.
const SQUARED_HI: f64 = f64::from_bits((1023 + 400) << 52);

/// The lane type of the batched triangle kernel.
type Lanes = wide::f64x2;
/// Triangles per batch of [`triangle_cotangents`] (the lanes of [`Lanes`]).
const TRIANGLE_LANES: usize = 2;

/// [`face_cotangents`] for [`TRIANGLE_LANES`] triangles at once, lane by lane the same
/// operations. Returns the cotangents opposite the halfedges ending at `p0`, `p1`, `p2`
/// and a mask of the lanes whose three edge vectors are all plain (finite, largest
/// component in `[2^-200, 2^200]`); other lanes' values are meaningless.
#[inline(always)]
fn face_cotangents_lanes(p0: V3<Lanes>, p1: V3<Lanes>, p2: V3<Lanes>) -> ([Lanes; 3], Lanes) {
    let s1 = p1 - p0;
    let s2 = p2 - p0;
    let e = p2 - p1;
    let (q1, q2, qe) = (s1.dot(s1), s2.dot(s2), e.dot(e));
    // Plain edges, from the squared lengths: `|s|² ≥ 2^-398` implies a component of at
    // least 2^-200 (three squares below 2^-400 round to at most 3 · 2^-400), and
    // `|s|² < 2^400` implies every component below 2^200 (a larger square rounds to at
    // least 2^400). NaN and infinite components fail the second test.
    let in_range =
        |q: Lanes| q.cmp_ge(Lanes::splat(SQUARED_LO)) & q.cmp_lt(Lanes::splat(SQUARED_HI));
    let plain = in_range(q1) & in_range(q2) & in_range(qe);
    // Degeneracy, in the frame at p0 (the geometry's `is_degenerate`). The squared
    // lengths are finite and not NaN in plain lanes, where `fast_max` is `f64::max`.
    let s3 = s2 - s1;
    let longest2 = q1.fast_max(q2).fast_max(s3.dot(s3));
    let x0 = s1.cross(s2);
    let two_area = x0.dot(x0).sqrt();
    let degenerate = two_area.cmp_le(Lanes::splat(DEGENERACY_RATIO) * longest2) | two_area.is_nan();
    // Corner 1 at p1: u = p2 − p1 = e, v = p0 − p1 = −s1. Negation is exact, so
    // u · v = −(e · s1) and u × v = −(e × s1) bit for bit; the length ignores the sign.
    let x1 = e.cross(s1);
    let cross1 = x1.dot(x1).sqrt();
    // Corner 2 at p2: u = p0 − p2 = −s2, v = p1 − p2 = −e: exactly the products of s2
    // and e (each product of two negated factors is the product of the factors).
    let x2 = s2.cross(e);
    let cross2 = x2.dot(x2).sqrt();
    let keep = !degenerate;
    let c0 = cot_lanes(s1.dot(s2), two_area, keep);
    let c1 = cot_lanes(-e.dot(s1), cross1, keep);
    let c2 = cot_lanes(s2.dot(e), cross2, keep);
    ([c1, c2, c0], plain)
}

/// [`cot`] lane by lane, and +0 where the mask `keep` is clear.
#[inline(always)]
fn cot_lanes(dot: Lanes, cross: Lanes, keep: Lanes) -> Lanes {
    let c = dot / cross;
    let finite = c.abs().cmp_lt(Lanes::splat(f64::INFINITY));
    c & (cross.cmp_gt(Lanes::splat(0.0)) & finite & keep)
}

/// The cotangents of many triangles: for triangle `k` (vertex ids into `positions`, in
/// face order), `out[3k..3k + 3]` gets [`face_cotangents`]' three values, or
/// `fallback(k)` where that is `None` (an edge outside the plain range; the caller asks
/// the geometry). The bits are [`face_cotangents`]', computed [`TRIANGLE_LANES`]
/// triangles at a time.
///
/// # Panics
/// If `out.len() != 3 * triangles.len()` or a vertex id is out of bounds.
pub(crate) fn triangle_cotangents<FB>(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    out: &mut [f64],
    mut fallback: FB,
) where
    FB: FnMut(usize) -> [f64; 3],
{
    assert_eq!(
        out.len(),
        3 * triangles.len(),
        "three cotangents per triangle"
    );
    const N: usize = TRIANGLE_LANES;
    let mut scalar = |k: usize, t: [u32; 3], out: &mut [f64]| {
        let (a, b, c) = (
            positions[t[0] as usize],
            positions[t[1] as usize],
            positions[t[2] as usize],
        );
        let cots = face_cotangents(a, b, c).unwrap_or_else(|| fallback(k));
        out.copy_from_slice(&cots);
    };
    let batches = triangles.chunks_exact(N);
    let tail = batches.remainder();
    let mut outs = out.chunks_exact_mut(3 * N);
    for (b, (tris, out)) in batches.zip(&mut outs).enumerate() {
        let mut p = [[[0.0; N]; 3]; 3];
        for (l, t) in tris.iter().enumerate() {
            for (p, &v) in p.iter_mut().zip(t) {
                let q = positions[v as usize];
                p[0][l] = q.x;
                p[1][l] = q.y;
                p[2][l] = q.z;
            }
        }
        let v = |[x, y, z]: [[f64; N]; 3]| V3 {
            x: Lanes::from(x),
            y: Lanes::from(y),
            z: Lanes::from(z),
        };
        let ([c1, c2, c0], plain) = face_cotangents_lanes(v(p[0]), v(p[1]), v(p[2]));
        if plain.all() {
            let (c1, c2, c0) = (c1.to_array(), c2.to_array(), c0.to_array());
            for (l, o) in out.chunks_exact_mut(3).enumerate() {
                o.copy_from_slice(&[c1[l], c2[l], c0[l]]);
            }
        } else {
            for (l, o) in out.chunks_exact_mut(3).enumerate() {
                scalar(b * N + l, tris[l], o);
            }
        }
    }
    let first = triangles.len() - tail.len();
    for (l, (&t, o)) in tail
        .iter()
        .zip(outs.into_remainder().chunks_exact_mut(3))
        .enumerate()
    {
        scalar(first + l, t, o);
    }
}

/// Inverse-distance weights of one row: `out[k] = apply(1 / (|x_j − x_i| + ε))` for
/// `j = neighbours[k]`, with the distance `geometry::distance(x_i, x_j)` (its plain
/// `(x_j − x_i).length()` computed two slots at a time; the geometry's function for a
/// slot outside that range) and ε = [`DISTANCE_EPSILON`](crate::DISTANCE_EPSILON).
/// `apply` is the caller's negative-weight policy.
///
/// # Panics
/// If `out` is shorter than `neighbours` or a neighbour is out of bounds.
#[inline]
pub(crate) fn inverse_distances<A>(
    xi: DVec3,
    positions: &[DVec3],
    neighbours: &[u32],
    out: &mut [f64],
    apply: A,
) where
    A: Fn(f64) -> f64,
{
    const N: usize = DISTANCE_LANES;
    let eps = crate::DISTANCE_EPSILON;
    let scalar = |xj: DVec3| {
        let d =
            plain_distance(xi, xj).unwrap_or_else(|| beltrami_halfedge::geometry::distance(xi, xj));
        apply(1.0 / (d + eps))
    };
    let out = &mut out[..neighbours.len()];
    let pairs = neighbours.chunks_exact(N);
    let tail = pairs.remainder();
    let mut outs = out.chunks_exact_mut(N);
    let origin = V3 {
        x: Lanes::splat(xi.x),
        y: Lanes::splat(xi.y),
        z: Lanes::splat(xi.z),
    };
    for (js, w) in pairs.zip(&mut outs) {
        let xj: [DVec3; N] = std::array::from_fn(|l| positions[js[l] as usize]);
        let d = V3 {
            x: Lanes::from(std::array::from_fn::<_, N, _>(|l| xj[l].x)),
            y: Lanes::from(std::array::from_fn::<_, N, _>(|l| xj[l].y)),
            z: Lanes::from(std::array::from_fn::<_, N, _>(|l| xj[l].z)),
        } - origin;
        let len = d.dot(d).sqrt();
        // `plain_distance`'s range test (NaN fails both comparisons).
        let plain = len.cmp_ge(Lanes::splat(SQRT_MIN)) & len.cmp_lt(Lanes::splat(f64::INFINITY));
        if plain.all() {
            let inv = (Lanes::splat(1.0) / (len + Lanes::splat(eps))).to_array();
            for (w, inv) in w.iter_mut().zip(inv) {
                *w = apply(inv);
            }
        } else {
            for (w, xj) in w.iter_mut().zip(xj) {
                *w = scalar(xj);
            }
        }
    }
    for (w, &j) in outs.into_remainder().iter_mut().zip(tail) {
        *w = scalar(positions[j as usize]);
    }
}

/// Slots per batch of [`inverse_distances`] (the lanes of [`Lanes`]).
const DISTANCE_LANES: usize = 2;

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::geometry::Geometry;
    use beltrami_halfedge::{FaceId, HalfedgeMesh};

    /// A deterministic generator of numbers in [-1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
        fn point(&mut self) -> DVec3 {
            DVec3::new(self.next(), self.next(), self.next())
        }
    }

    /// Triangles that exercise every branch: ordinary, obtuse (negative cotangents),
    /// degenerate and nearly degenerate on both sides of the threshold, coincident
    /// points, scales near and far outside the plain range, NaN and infinite points.
    fn triangles() -> Vec<[DVec3; 3]> {
        let mut rng = Rng(3);
        let mut out = Vec::new();
        for _ in 0..64 {
            out.push([rng.point(), rng.point(), rng.point()]);
        }
        let (a, b) = (DVec3::new(0.3, -0.2, 0.1), DVec3::new(1.1, 0.4, -0.3));
        let n = DVec3::new(0.2, -0.1, 0.9).cross(b - a).normalize();
        for h in [
            0.0, 1e-14, 1e-13, 0.99e-12, 1e-12, 1.01e-12, 1e-11, 1e-6, 0.5, 3.0,
        ] {
            for t in [-0.7, 0.1, 0.5, 1.6] {
                let c = a + (b - a) * t + n * (h * (b - a).length());
                out.push([a, b, c]);
                out.push([c, a, b]);
            }
        }
        out.push([a, a, b]);
        out.push([a, b, b]);
        out.push([a; 3]);
        out.push([DVec3::ZERO; 3]);
        // Largest edge components around 2^±200 and far outside.
        let base: Vec<[DVec3; 3]> = out.iter().take(16).copied().collect();
        for s in [
            2f64.powi(-201),
            2f64.powi(-200),
            2f64.powi(-199),
            1e-59,
            1e58,
            2f64.powi(199),
            2f64.powi(200),
            1e-170,
            1e170,
            1e-300,
            1e300,
            1e308,
        ] {
            for t in &base {
                out.push(t.map(|p| p * s));
            }
        }
        // Far from the origin (cancellation in the differences).
        for t in base.iter().take(4) {
            out.push(t.map(|p| p * 1e-9 + DVec3::splat(1e7)));
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let [p, q, r] = base[0];
            out.push([DVec3::new(bad, p.y, p.z), q, r]);
            out.push([p, DVec3::new(q.x, bad, q.z), r]);
            out.push([p, q, DVec3::new(r.x, r.y, bad)]);
            out.push([DVec3::splat(bad), q, r]);
        }
        out.push([
            DVec3::splat(-1.5e308),
            DVec3::splat(1.5e308),
            DVec3::new(1e308, -1e308, 0.0),
        ]);
        out
    }

    /// The triangles as a soup mesh, its positions, and each face's vertices in the
    /// order the Laplacian's cotangent plan stores them (the ends of the face's
    /// halfedges from `face_halfedge`).
    fn soup(tris: &[[DVec3; 3]]) -> (HalfedgeMesh, Vec<DVec3>, Vec<[u32; 3]>) {
        let faces: Vec<[u32; 3]> = (0..tris.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        let mesh = HalfedgeMesh::from_polygons(3 * tris.len(), &faces).unwrap();
        let positions: Vec<DVec3> = tris.iter().flatten().copied().collect();
        let order = mesh
            .faces()
            .map(|f| {
                let h0 = mesh.face_halfedge(f);
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                [h0, h1, h2].map(|h| mesh.to_vertex(h).raw())
            })
            .collect();
        (mesh, positions, order)
    }

    fn geometry_cots(geometry: &Geometry<'_>, f: usize) -> [f64; 3] {
        let t = geometry
            .face_opposite_cotangents(FaceId::new(f as u32))
            .unwrap();
        [t[0].1, t[1].1, t[2].1]
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn scalar_kernel_matches_the_geometry() {
        let tris = triangles();
        let (mesh, positions, order) = soup(&tris);
        let geometry = Geometry::new(&mesh, &positions).unwrap();
        for (f, t) in order.iter().enumerate() {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            if let Some(cots) = face_cotangents(a, b, c) {
                assert_eq!(bits(&cots), bits(&geometry_cots(&geometry, f)), "{f}");
            }
        }
    }

    /// Every slice (each start and length, so every tail length and every mix of
    /// plain, degenerate and fallback lanes in a batch) gives the geometry's bits, and
    /// the fallback is asked exactly for the triangles outside the plain range.
    #[test]
    fn batched_kernel_matches_the_geometry_on_every_slice() {
        let tris = triangles();
        let (mesh, positions, order) = soup(&tris);
        let geometry = Geometry::new(&mesh, &positions).unwrap();
        let want: Vec<f64> = (0..order.len())
            .flat_map(|f| geometry_cots(&geometry, f))
            .collect();
        let mut plain = 0;
        for start in 0..order.len() {
            for len in (0..=9).chain([order.len() - start]) {
                let Some(slice) = order.get(start..start + len) else {
                    continue;
                };
                let mut out = vec![f64::NAN; 3 * len];
                let mut asked = Vec::new();
                triangle_cotangents(&positions, slice, &mut out, |k| {
                    asked.push(k);
                    geometry_cots(&geometry, start + k)
                });
                assert_eq!(
                    bits(&out),
                    bits(&want[3 * start..3 * (start + len)]),
                    "{start}+{len}"
                );
                let expected: Vec<usize> = (0..len)
                    .filter(|&k| {
                        let [a, b, c] = slice[k].map(|v| positions[v as usize]);
                        face_cotangents(a, b, c).is_none()
                    })
                    .collect();
                assert_eq!(asked, expected, "{start}+{len}");
                plain += len - asked.len();
            }
        }
        assert!(plain > 0);
    }

    /// The plain-range test on squared lengths accepts only edges whose largest
    /// component is in [2^-200, 2^200] (so the batched lanes never take a triangle the
    /// geometry would rescale), and accepts the ordinary ones.
    #[test]
    fn squared_range_is_inside_the_plain_range() {
        let mut rng = Rng(11);
        for e in -215..=215 {
            for _ in 0..40 {
                let s = DVec3::new(rng.next(), rng.next(), rng.next()) * 2f64.powi(e);
                let q = s.dot(s);
                let accepted = (SQUARED_LO..SQUARED_HI).contains(&q);
                if accepted {
                    assert!(plain(s), "{s:?}");
                }
                if (-190..=190).contains(&e) && s.abs().max_element() > 0.01 * 2f64.powi(e) {
                    assert!(accepted, "{s:?}");
                }
            }
        }
    }

    /// Every row length (tails), plain and fallback slots mixed in one pair, and the
    /// caller's policy applied to each weight.
    #[test]
    fn batched_inverse_distances_match_the_geometry() {
        let mut rng = Rng(23);
        let mut positions: Vec<DVec3> = (0..40).map(|_| rng.point()).collect();
        let xi = positions[0];
        positions.extend([
            xi,
            xi + DVec3::new(1e-160, 0.0, 0.0),
            xi + DVec3::new(3e-154, 0.0, 0.0),
            DVec3::splat(1e300),
            DVec3::splat(-1e308),
            DVec3::new(f64::NAN, 0.0, 0.0),
            DVec3::new(0.0, f64::INFINITY, 0.0),
        ]);
        let n = positions.len() as u32;
        let neighbours: Vec<u32> = (0..3 * n).map(|k| (k * 7 + 3) % n).collect();
        let apply = |w: f64| if w > 1.0 { w } else { -w };
        for start in 0..neighbours.len() {
            for len in 0..=9 {
                let Some(nb) = neighbours.get(start..start + len) else {
                    continue;
                };
                let mut out = vec![0.0; len + 2];
                inverse_distances(xi, &positions, nb, &mut out, apply);
                let want: Vec<f64> = nb
                    .iter()
                    .map(|&j| {
                        let d = beltrami_halfedge::geometry::distance(xi, positions[j as usize]);
                        apply(1.0 / (d + crate::DISTANCE_EPSILON))
                    })
                    .chain([0.0, 0.0])
                    .collect();
                assert_eq!(bits(&out), bits(&want), "{start}+{len}");
            }
        }
    }
}
