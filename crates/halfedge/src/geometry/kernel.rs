//! Point-level arithmetic shared by the geometry queries: scaled difference frames,
//! normalisation, corner dot and cross products, triangle measures, compensated sums.
//!
//! Everything here is private to the module. The public queries in the sibling files only
//! gather points from the mesh and call these functions, so that every rule (degeneracy,
//! the OpenMesh normal, the overflow fallback) lives in one place.

use glam::DVec3;

use super::DEGENERACY_RATIO;

/// Below this largest difference component, products of up to four components may
/// underflow; the differences are rescaled by a power of two.
pub(super) const SAFE_LO: f64 = 6.223_015_277_861_142e-61; // 2^-200
/// Above this largest difference component, products of up to four components may
/// overflow; the differences are rescaled by a power of two.
pub(super) const SAFE_HI: f64 = 1.606_938_044_258_990_3e60; // 2^200
/// The smallest vector length whose square is a normal `f64` (`sqrt(f64::MIN_POSITIVE)`,
/// 2^-511): above it, `v.length()` is accurate to rounding.
pub(super) const SQRT_MIN: f64 = 1.491_668_146_240_041_3e-154;

/// The largest absolute component of `v`, NaN when a component is NaN.
#[inline]
fn max_abs(v: DVec3) -> f64 {
    let a = v.abs();
    if a.is_nan() {
        f64::NAN
    } else {
        a.x.max(a.y).max(a.z)
    }
}

/// `floor(log2 m)` for finite positive `m`, read off the bits (subnormals included).
#[inline]
fn exponent_floor(m: f64) -> i32 {
    debug_assert!(m.is_finite() && m > 0.0);
    let bits = m.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        let mantissa = bits & ((1 << 52) - 1);
        63 - mantissa.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    }
}

/// `2^e` for `e` in `[-1074, 1023]`, exactly.
#[inline]
fn pow2(e: i32) -> f64 {
    debug_assert!((-1074..=1023).contains(&e));
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::from_bits(1 << (e + 1074))
    }
}

/// `x · 2^e` for any `e`, exact unless the result overflows or underflows.
#[inline]
pub(super) fn ldexp(mut x: f64, mut e: i32) -> f64 {
    while e > 1023 {
        x *= pow2(1023);
        e -= 1023;
    }
    while e < -1022 {
        x *= pow2(-1022);
        e += 1022;
    }
    x * pow2(e)
}

/// The largest power of two not above `m` (`m` finite and positive).
#[inline]
fn pow2_floor(m: f64) -> f64 {
    pow2(exponent_floor(m))
}

/// Differences `p − origin` of points around an origin, expressed as
/// `2^exponent × span(p)` with every span component at most a few units in magnitude, so
/// that dot and cross products of spans (and their squared lengths) neither overflow nor
/// underflow.
///
/// In the common case (largest difference component within 2^±200) the spans are the
/// plain differences and the exponent is 0, so the arithmetic is exactly the textbook
/// one. Otherwise the differences are divided by a power of two (exact), after halving the
/// points first when the plain differences overflow.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    origin: DVec3,
    halve: bool,
    /// `2^shift`, the power of two the (possibly halved) differences are divided by.
    divisor: f64,
    shift: i32,
}

impl Frame {
    /// The frame for the given points around `origin`.
    #[inline]
    pub(super) fn new(origin: DVec3, points: &[DVec3]) -> Self {
        let m = points
            .iter()
            .fold(0.0f64, |m, &p| nan_max(m, max_abs(p - origin)));
        if (SAFE_LO..=SAFE_HI).contains(&m) {
            // The common case, kept small so that it inlines into the hot loops.
            return Self {
                origin,
                halve: false,
                divisor: 1.0,
                shift: 0,
            };
        }
        Self::unusual(origin, points, m)
    }

    /// [`Frame::new`] for differences outside the safe range (zero, huge, tiny or NaN).
    #[cold]
    #[inline(never)]
    fn unusual(origin: DVec3, points: &[DVec3], m: f64) -> Self {
        let plain = Self {
            origin,
            halve: false,
            divisor: 1.0,
            shift: 0,
        };
        if m.is_nan() || m == 0.0 || (SAFE_LO..=SAFE_HI).contains(&m) {
            return plain;
        }
        if m.is_finite() {
            let shift = exponent_floor(m);
            return Self {
                divisor: pow2(shift),
                shift,
                ..plain
            };
        }
        // The plain differences overflowed: halve the points first (exact for normal
        // numbers), which keeps every difference of finite points finite.
        let h = points
            .iter()
            .fold(0.0f64, |m, &p| nan_max(m, max_abs(p * 0.5 - origin * 0.5)));
        if !h.is_finite() || h == 0.0 {
            // Non-finite input: leave it to propagate.
            return plain;
        }
        let shift = exponent_floor(h);
        Self {
            origin,
            halve: true,
            divisor: pow2(shift),
            shift,
        }
    }

    /// The scaled difference `(p − origin) / 2^exponent`.
    #[inline]
    pub(super) fn span(&self, p: DVec3) -> DVec3 {
        let d = if self.halve {
            p * 0.5 - self.origin * 0.5
        } else {
            p - self.origin
        };
        // Division by a power of two is exact; by 1 it is the identity.
        d / self.divisor
    }

    /// The scaled edge `(b − a) / 2^exponent` between two of the frame's points (with
    /// the points halved first when the frame halves them): in the common case the
    /// plain difference `b − a`, not `span(b) − span(a)`.
    #[inline]
    pub(super) fn edge(&self, a: DVec3, b: DVec3) -> DVec3 {
        let d = if self.halve { b * 0.5 - a * 0.5 } else { b - a };
        d / self.divisor
    }

    /// The origin of the frame.
    #[inline]
    pub(super) fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The exponent of the length that one span unit stands for, in the positions' unit
    /// (0 in the common case): a span length `l` is the length `l · 2^exponent`.
    #[inline]
    pub(super) fn exponent(&self) -> i32 {
        self.shift + i32::from(self.halve)
    }
}

/// `max` that propagates NaN.
#[inline]
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// `n / |n|` with OpenMesh's arithmetic, `n * (1 / |n|)`, where `|n|` is in the range in
/// which that is accurate; a rescaled equivalent for tiny or huge finite `n`; ZERO for the
/// zero vector and for non-finite `n`.
#[inline]
pub(super) fn unit_or_zero(n: DVec3) -> DVec3 {
    let len = n.length();
    if (SQRT_MIN..f64::INFINITY).contains(&len) {
        return n * (1.0 / len);
    }
    if !n.is_finite() || n == DVec3::ZERO {
        return DVec3::ZERO;
    }
    let m = n / pow2_floor(max_abs(n));
    m * (1.0 / m.length())
}

/// The length of a finite vector, `sqrt(x² + y² + z²)` where that is accurate (the common
/// case, bit for bit), rescaled by a power of two otherwise.
#[inline]
pub(super) fn length(v: DVec3) -> f64 {
    let len = v.length();
    if (SQRT_MIN..f64::INFINITY).contains(&len) || v == DVec3::ZERO || !v.is_finite() {
        return len;
    }
    let p = pow2_floor(max_abs(v));
    (v / p).length() * p
}

/// The distance `|q − p|`, finite whenever it is representable.
#[inline]
pub(super) fn distance(p: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    if d.is_finite() {
        length(d)
    } else {
        length(q * 0.5 - p * 0.5) * 2.0
    }
}

/// Products of the two edge vectors leaving a corner, and the squared length of the
/// opposite edge.
///
/// Every field is the corner's own and symmetric in its two neighbours (a difference
/// and its negation give the same products' magnitudes bit for bit), so a corner's
/// [`cot`](Self::cot) and [`is_degenerate`](Self::is_degenerate) depend only on the
/// corner and its two neighbours — not on where the face starts or in which order its
/// vertices are listed.
#[derive(Clone, Copy, Debug)]
pub(super) struct Corner {
    /// `u · v` in span units².
    pub(super) dot: f64,
    /// `|u × v|` in span units².
    pub(super) cross: f64,
    /// `|u|²` in span units².
    pub(super) uu: f64,
    /// `|v|²` in span units².
    pub(super) vv: f64,
    /// `|w|²` in span units², `w = b − a` the opposite edge ([`Frame::edge`]: the plain
    /// difference of the two neighbours, not `v − u`).
    pub(super) ww: f64,
    /// The exponent of one span unit (see [`Frame::exponent`]).
    pub(super) exponent: i32,
}

impl Corner {
    /// The products at corner `c` of the edge vectors `u = a − c` and `v = b − c`. The
    /// result does not depend on the order of `a` and `b`.
    #[inline]
    pub(super) fn new(c: DVec3, a: DVec3, b: DVec3) -> Self {
        let frame = Frame::new(c, &[a, b]);
        let (u, v, w) = (frame.span(a), frame.span(b), frame.edge(a, b));
        Self {
            dot: u.dot(v),
            cross: u.cross(v).length(),
            uu: u.dot(u),
            vv: v.dot(v),
            ww: w.dot(w),
            exponent: frame.exponent(),
        }
    }

    /// Whether the triangle is degenerate as seen from this corner: `|u × v| ≤
    /// DEGENERACY_RATIO · max(|u|², |v|², |w|²)` (twice the area against the longest
    /// edge squared, the corner's own products), or `|u × v|` is NaN.
    #[inline]
    pub(super) fn is_degenerate(&self) -> bool {
        let limit = DEGENERACY_RATIO * self.uu.max(self.vv).max(self.ww);
        // Not `cross > limit`, NaN included (as the lanes' comparison).
        self.cross <= limit || self.cross.is_nan() || limit.is_nan()
    }

    /// The angle between `u` and `v` in radians, in `[0, π]`: `atan2(|u × v|, u · v)`,
    /// accurate for all angles and 0 when an edge has zero length.
    #[inline]
    pub(super) fn angle(&self) -> f64 {
        self.cross.atan2(self.dot)
    }

    /// The cotangent `(u · v) / |u × v|`, or 0 when the triangle is degenerate as seen
    /// from this corner ([`is_degenerate`](Self::is_degenerate), which includes parallel
    /// and zero-length edges) or the quotient is not finite. The one definition of a
    /// cotangent term: the batched and ring kernels repeat this arithmetic lane by lane.
    #[inline]
    pub(super) fn cot(&self) -> f64 {
        if self.is_degenerate() {
            return 0.0;
        }
        let c = self.dot / self.cross;
        if c.is_finite() { c } else { 0.0 }
    }
}

/// The cotangent at corner `c` of the triangle `(c, a, b)`, [`Corner::cot`]: symmetric in
/// `a` and `b`, and the same whichever vertex the face starts at.
#[inline]
pub(super) fn corner_cotangent(c: DVec3, a: DVec3, b: DVec3) -> f64 {
    Corner::new(c, a, b).cot()
}

/// A triangle's three vertex positions in face order.
#[derive(Clone, Copy, Debug)]
pub(super) struct Triangle(pub(super) [DVec3; 3]);

impl Triangle {
    /// The unit normal with OpenMesh's arithmetic:
    /// `n = (p2 − p1) × (p0 − p1)`, `n * (1 / |n|)`, ZERO when `|n| = 0`.
    #[inline]
    pub(super) fn normal(&self) -> DVec3 {
        let [p0, p1, p2] = self.0;
        let frame = Frame::new(p1, &[p2, p0]);
        unit_or_zero(frame.span(p2).cross(frame.span(p0)))
    }

    /// `(p1 − p0) × (p2 − p0)` in span units², with the frame's exponent.
    #[inline]
    pub(super) fn double_vector_area(&self) -> (DVec3, i32) {
        let [p0, p1, p2] = self.0;
        let frame = Frame::new(p0, &[p1, p2]);
        (frame.span(p1).cross(frame.span(p2)), frame.exponent())
    }

    /// The vector area `½ (p1 − p0) × (p2 − p0)`.
    #[inline]
    pub(super) fn vector_area(&self) -> DVec3 {
        let (c, e) = self.double_vector_area();
        scale_area(c * 0.5, e)
    }

    /// The area `½ |(p1 − p0) × (p2 − p0)|`.
    #[inline]
    pub(super) fn area(&self) -> f64 {
        let (c, e) = self.double_vector_area();
        ldexp(c.length() * 0.5, 2 * e)
    }

    /// Whether twice the area is at most [`DEGENERACY_RATIO`] times the squared longest
    /// edge (true when all edges have zero length), as seen from every corner: the
    /// triangle is degenerate when each of its three [`Corner::is_degenerate`]. So the
    /// test does not depend on which vertex the face starts at, and a triangle that is
    /// not degenerate has a corner that is not, whose [`Corner::cot`] is then the only
    /// test left (the three corners' tests differ only by rounding, at the threshold).
    /// An ordinary triangle costs one corner: the first that is not degenerate decides.
    #[inline]
    pub(super) fn is_degenerate(&self) -> bool {
        (0..3).all(|i| self.corner(i).is_degenerate())
    }

    /// The corner products at vertex `i` (0, 1 or 2).
    #[inline]
    pub(super) fn corner(&self, i: usize) -> Corner {
        let p = self.0;
        Corner::new(p[i], p[(i + 1) % 3], p[(i + 2) % 3])
    }

    /// The mixed Voronoi area of corner `i` (Meyer et al. 2003, Fig. 4): 0 for a
    /// degenerate triangle; for a non-obtuse triangle the Voronoi area
    /// `⅛ (|p_i p_k|² cot θ_j + |p_i p_j|² cot θ_k)`; for an obtuse triangle `A/2` at the
    /// obtuse corner and `A/4` at the other two.
    pub(super) fn mixed_area(&self, i: usize) -> f64 {
        if self.is_degenerate() {
            return 0.0;
        }
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let (ci, cj, ck) = (self.corner(i), self.corner(j), self.corner(k));
        if ci.dot < 0.0 {
            self.area() * 0.5
        } else if cj.dot < 0.0 || ck.dot < 0.0 {
            self.area() * 0.25
        } else {
            // In corner i's frame: uu = |p_i p_j|², vv = |p_i p_k|².
            ldexp(
                (ci.vv * cj.cot() + ci.uu * ck.cot()) * 0.125,
                2 * ci.exponent,
            )
        }
    }
}

/// A polygon's vertex positions in face order (at least three).
#[derive(Clone, Debug)]
pub(super) struct Polygon(pub(super) Vec<DVec3>);

impl Polygon {
    /// The unit normal by Newell's method with OpenMesh's arithmetic: for consecutive
    /// vertices `a = p_i − p_{i+1}`, `b = p_i + p_{i+1}`, `n += (a.y b.z, a.z b.x, a.x b.y)`,
    /// then `n * (1 / |n|)`. Falls back to the normal of the vector area when the
    /// coordinates are so large or small that those products could overflow or underflow.
    pub(super) fn normal(&self) -> DVec3 {
        let ps = &self.0;
        let m = ps.iter().fold(0.0f64, |m, &p| nan_max(m, max_abs(p)));
        if (SAFE_LO..=SAFE_HI).contains(&m) {
            let mut n = DVec3::ZERO;
            for (i, &p) in ps.iter().enumerate() {
                let q = ps[(i + 1) % ps.len()];
                let (a, b) = (p - q, p + q);
                n.x += a.y * b.z;
                n.y += a.z * b.x;
                n.z += a.x * b.y;
            }
            return unit_or_zero(n);
        }
        let (c, _) = self.double_vector_area();
        unit_or_zero(c)
    }

    /// `Σ (p_i − p_0) × (p_{i+1} − p_0)` in span units², with the frame's exponent. This is
    /// twice the vector area (Newell's vector), evaluated around the first vertex so that
    /// it does not lose digits far from the origin.
    pub(super) fn double_vector_area(&self) -> (DVec3, i32) {
        let ps = &self.0;
        let frame = Frame::new(ps[0], &ps[1..]);
        let mut c = DVec3::ZERO;
        for w in ps[1..].windows(2) {
            c += frame.span(w[0]).cross(frame.span(w[1]));
        }
        (c, frame.exponent())
    }

    /// The vector area: half of Newell's vector.
    pub(super) fn vector_area(&self) -> DVec3 {
        let (c, e) = self.double_vector_area();
        scale_area(c * 0.5, e)
    }

    /// The area: half the length of Newell's vector.
    pub(super) fn area(&self) -> f64 {
        let (c, e) = self.double_vector_area();
        ldexp(c.length() * 0.5, 2 * e)
    }

    /// Whether twice the area is at most [`DEGENERACY_RATIO`] times the squared longest
    /// edge.
    pub(super) fn is_degenerate(&self) -> bool {
        let ps = &self.0;
        // The same frame as in `double_vector_area`.
        let frame = Frame::new(ps[0], &ps[1..]);
        let longest2 = ps
            .iter()
            .zip(ps.iter().cycle().skip(1))
            .map(|(&p, &q)| {
                let e = frame.span(q) - frame.span(p);
                e.dot(e)
            })
            .fold(0.0f64, f64::max);
        let two_area = self.double_vector_area().0.length();
        two_area <= DEGENERACY_RATIO * longest2 || two_area.is_nan()
    }
}

/// `a · 4^e`: an area in span units² back in the positions' unit².
#[inline]
fn scale_area(a: DVec3, e: i32) -> DVec3 {
    if e == 0 {
        a
    } else {
        DVec3::new(ldexp(a.x, 2 * e), ldexp(a.y, 2 * e), ldexp(a.z, 2 * e))
    }
}

/// A sum of vectors given as `4^e × v` (areas in span units with their frame exponents),
/// kept as `4^max_e × sum`, so that terms far beyond the range of `f64` add up to a finite
/// vector with the right direction. When every exponent is 0 this is the plain sum.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ScaledSum {
    sum: DVec3,
    exponent: Option<i32>,
}

impl ScaledSum {
    /// Adds `4^e × v`.
    #[inline]
    pub(super) fn add(&mut self, v: DVec3, e: i32) {
        let top = match self.exponent {
            Some(top) if top >= e => top,
            Some(top) => {
                // Rescaling by a power of two is exact (or underflows to 0).
                self.sum = scale_area(self.sum, top - e);
                e
            }
            None => e,
        };
        self.exponent = Some(top);
        self.sum += scale_area(v, e - top);
    }

    /// The direction of the sum ([`unit_or_zero`]).
    #[inline]
    pub(super) fn direction(&self) -> DVec3 {
        unit_or_zero(self.sum)
    }
}

/// A compensated (Neumaier) sum: the error of each addition is carried along, so the
/// result is accurate to about one rounding however many terms are added. Sequential, so
/// a sum over a fixed order of terms does not depend on the thread count.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::CompensatedSum;
/// let mut s = CompensatedSum::default();
/// for x in [1e16, 1.0, -1e16] {
///     s.add(x);
/// }
/// assert_eq!(s.value(), 1.0); // a plain sum gives 0
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct CompensatedSum {
    sum: f64,
    compensation: f64,
}

pub(super) type Sum = CompensatedSum;

impl CompensatedSum {
    /// Adds a term.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.compensation += (self.sum - t) + x;
        } else {
            self.compensation += (x - t) + self.sum;
        }
        self.sum = t;
    }

    /// The sum so far (the plain running sum when it is not finite).
    #[inline]
    #[must_use]
    pub fn value(&self) -> f64 {
        if self.sum.is_finite() {
            self.sum + self.compensation
        } else {
            self.sum
        }
    }
}

/// A compensated sum of vectors, component by component.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct VecSum([Sum; 3]);

impl VecSum {
    /// Adds a term.
    #[inline]
    pub(super) fn add(&mut self, v: DVec3) {
        self.0[0].add(v.x);
        self.0[1].add(v.y);
        self.0[2].add(v.z);
    }

    /// The sum so far.
    #[inline]
    pub(super) fn value(&self) -> DVec3 {
        DVec3::new(self.0[0].value(), self.0[1].value(), self.0[2].value())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_plain_in_the_common_range() {
        let f = Frame::new(DVec3::new(1.0, 2.0, 3.0), &[DVec3::new(4.0, 6.0, 3.0)]);
        assert_eq!(f.exponent(), 0);
        assert_eq!(f.span(DVec3::new(4.0, 6.0, 3.0)), DVec3::new(3.0, 4.0, 0.0));
    }

    #[test]
    fn frame_rescales_huge_and_tiny_differences() {
        let big = Frame::new(DVec3::ZERO, &[DVec3::new(3e200, 0.0, 0.0)]);
        let s = big.span(DVec3::new(3e200, 0.0, 0.0));
        assert!((1.0..2.0).contains(&s.x));
        assert_eq!(ldexp(s.x, big.exponent()), 3e200);

        let over = Frame::new(DVec3::splat(-1.5e308), &[DVec3::splat(1.5e308)]);
        let s = over.span(DVec3::splat(1.5e308));
        assert!(s.is_finite() && (1.0..2.0).contains(&s.x));
        assert!(ldexp(s.x, over.exponent()).is_infinite()); // 3e308 is not representable

        let tiny = Frame::new(DVec3::ZERO, &[DVec3::new(0.0, 5e-300, 0.0)]);
        let s = tiny.span(DVec3::new(0.0, 5e-300, 0.0));
        assert!((1.0..2.0).contains(&s.y));
    }

    #[test]
    fn powers_of_two() {
        for m in [1.0, 1.5, 3e200, f64::MAX, f64::MIN_POSITIVE, 5e-324, 3e-310] {
            let p = pow2_floor(m);
            assert!(p <= m && m < 2.0 * p, "{m}");
        }
        assert_eq!(ldexp(1.5, 2000), f64::INFINITY);
        assert_eq!(ldexp(ldexp(ldexp(1.5, 1000), -2000), 1000), 1.5);
        assert_eq!(ldexp(ldexp(1.5, -1050), 1050), 1.5);
        assert_eq!(ldexp(3.0, -1100), 0.0);
    }

    #[test]
    fn scaled_sum_keeps_the_direction() {
        let mut s = ScaledSum::default();
        s.add(DVec3::X, 600);
        s.add(DVec3::Y, 600);
        s.add(DVec3::Z, -600);
        let d = s.direction();
        assert!((d - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-16);
        let mut plain = ScaledSum::default();
        plain.add(DVec3::new(1.0, 2.0, 2.0), 0);
        assert_eq!(plain.direction(), DVec3::new(1.0, 2.0, 2.0) * (1.0 / 3.0));
    }

    #[test]
    fn unit_or_zero_matches_openmesh_and_handles_extremes() {
        let n = DVec3::new(1.0, 2.0, 2.0);
        assert_eq!(unit_or_zero(n), n * (1.0 / 3.0));
        assert_eq!(unit_or_zero(DVec3::ZERO), DVec3::ZERO);
        assert_eq!(unit_or_zero(DVec3::new(f64::NAN, 0.0, 0.0)), DVec3::ZERO);
        for s in [1e-170, 1e-300, 1e170, 1e300] {
            let u = unit_or_zero(n * s);
            assert!((u - n / 3.0).length() < 1e-15, "{s}: {u}");
        }
    }

    #[test]
    fn length_is_robust() {
        assert_eq!(length(DVec3::new(3.0, 4.0, 0.0)), 5.0);
        assert_eq!(
            length(DVec3::new(0.75, 1.0, 0.0) * 2f64.powi(700)),
            1.25 * 2f64.powi(700)
        );
        assert!((length(DVec3::new(3e200, 4e200, 0.0)) / 5e200 - 1.0).abs() < 1e-15);
        assert!((length(DVec3::new(3e-200, 4e-200, 0.0)) / 5e-200 - 1.0).abs() < 1e-15);
        assert_eq!(
            distance(DVec3::splat(-1e308), DVec3::splat(1e308)),
            f64::INFINITY
        );
        let d = distance(DVec3::new(-8e307, 0.0, 0.0), DVec3::new(8e307, 0.0, 0.0));
        assert_eq!(d, 1.6e308);
    }

    #[test]
    fn corner_cotangent_and_angle() {
        let c = Corner::new(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(c.cot(), 1.0);
        assert!((c.angle() - std::f64::consts::FRAC_PI_4).abs() < 1e-16);
        let zero = Corner::new(DVec3::ZERO, DVec3::ZERO, DVec3::X);
        assert_eq!((zero.cot(), zero.angle()), (0.0, 0.0));
    }

    #[test]
    fn neumaier_sum_keeps_small_terms() {
        let mut s = Sum::default();
        for x in [1.0, 1e100, 1.0, -1e100] {
            s.add(x);
        }
        assert_eq!(s.value(), 2.0);
        let mut inf = Sum::default();
        inf.add(f64::MAX);
        inf.add(f64::MAX);
        assert_eq!(inf.value(), f64::INFINITY);
    }

    #[test]
    fn triangle_degeneracy_is_scale_invariant() {
        let t = |h: f64, s: f64| {
            Triangle([DVec3::ZERO, DVec3::X * s, DVec3::new(0.5, h, 0.0) * s]).is_degenerate()
        };
        for s in [1e-250, 1e-3, 1.0, 1e3, 1e250] {
            assert!(!t(1e-9, s), "{s}");
            assert!(t(1e-13, s), "{s}");
            assert!(t(0.0, s), "{s}");
        }
        assert!(Triangle([DVec3::ONE; 3]).is_degenerate());
    }
}
