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
const SAFE_LO: f64 = 6.223_015_277_861_142e-61; // 2^-200
/// Above this largest difference component, products of up to four components may
/// overflow; the differences are rescaled by a power of two.
const SAFE_HI: f64 = 1.606_938_044_258_990_3e60; // 2^200
/// The smallest vector length whose square is a normal `f64` (`sqrt(f64::MIN_POSITIVE)`,
/// 2^-511): above it, `v.length()` is accurate to rounding.
const SQRT_MIN: f64 = 1.491_668_146_240_041_3e-154;

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

/// The largest power of two not above `m` (`m` finite and positive), read off the bits.
#[inline]
fn pow2_floor(m: f64) -> f64 {
    debug_assert!(m.is_finite() && m > 0.0);
    let bits = m.to_bits();
    let exponent = (bits >> 52) & 0x7ff;
    if exponent == 0 {
        // Subnormal: keep the highest set bit of the mantissa.
        let mantissa = bits & ((1 << 52) - 1);
        f64::from_bits(1 << (63 - mantissa.leading_zeros()))
    } else {
        f64::from_bits(exponent << 52)
    }
}

/// Differences `p − origin` of points around an origin, expressed as
/// `unit × span(p)` with every span component at most a few units in magnitude, so that
/// dot and cross products of spans (and their squared lengths) neither overflow nor
/// underflow.
///
/// In the common case (largest difference component within 2^±200) the spans are the
/// plain differences and `unit` is 1, so the arithmetic is exactly the textbook one.
/// Otherwise the differences are divided by a power of two (exact), after halving the
/// points first when the plain differences overflow.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    origin: DVec3,
    halve: bool,
    divisor: f64,
}

impl Frame {
    /// The frame for the given points around `origin`.
    pub(super) fn new(origin: DVec3, points: &[DVec3]) -> Self {
        let m = points
            .iter()
            .fold(0.0f64, |m, &p| nan_max(m, max_abs(p - origin)));
        let plain = Self {
            origin,
            halve: false,
            divisor: 1.0,
        };
        if m.is_nan() || m == 0.0 || (SAFE_LO..=SAFE_HI).contains(&m) {
            return plain;
        }
        if m.is_finite() {
            return Self {
                divisor: pow2_floor(m),
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
        Self {
            origin,
            halve: true,
            divisor: pow2_floor(h),
        }
    }

    /// The scaled difference `(p − origin) / unit`.
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

    /// The origin of the frame.
    #[inline]
    pub(super) fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The length that one span unit stands for, in the positions' unit (a power of two;
    /// 1 in the common case).
    #[inline]
    pub(super) fn unit(&self) -> f64 {
        if self.halve {
            2.0 * self.divisor
        } else {
            self.divisor
        }
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

/// Products of the two edge vectors leaving a corner.
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
    /// The length of one span unit.
    pub(super) unit: f64,
}

impl Corner {
    /// The products at corner `c` of the edge vectors `u = a − c` and `v = b − c`. The
    /// result does not depend on the order of `a` and `b`.
    #[inline]
    pub(super) fn new(c: DVec3, a: DVec3, b: DVec3) -> Self {
        let frame = Frame::new(c, &[a, b]);
        let (u, v) = (frame.span(a), frame.span(b));
        Self {
            dot: u.dot(v),
            cross: u.cross(v).length(),
            uu: u.dot(u),
            vv: v.dot(v),
            unit: frame.unit(),
        }
    }

    /// The angle between `u` and `v` in radians, in `[0, π]`: `atan2(|u × v|, u · v)`,
    /// accurate for all angles and 0 when an edge has zero length.
    #[inline]
    pub(super) fn angle(&self) -> f64 {
        self.cross.atan2(self.dot)
    }

    /// The cotangent `(u · v) / |u × v|`, or 0 when `u` and `v` are parallel (including
    /// zero-length edges). The caller rules out degenerate triangles first.
    #[inline]
    pub(super) fn cot(&self) -> f64 {
        if self.cross > 0.0 {
            let c = self.dot / self.cross;
            if c.is_finite() { c } else { 0.0 }
        } else {
            0.0
        }
    }
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

    /// `(p1 − p0) × (p2 − p0)` in span units², with the frame's unit.
    #[inline]
    fn double_vector_area(&self) -> (DVec3, f64) {
        let [p0, p1, p2] = self.0;
        let frame = Frame::new(p0, &[p1, p2]);
        (frame.span(p1).cross(frame.span(p2)), frame.unit())
    }

    /// The vector area `½ (p1 − p0) × (p2 − p0)`.
    #[inline]
    pub(super) fn vector_area(&self) -> DVec3 {
        let (c, unit) = self.double_vector_area();
        c * (0.5 * unit) * unit
    }

    /// The area `½ |(p1 − p0) × (p2 − p0)|`.
    #[inline]
    pub(super) fn area(&self) -> f64 {
        let (c, unit) = self.double_vector_area();
        c.length() * (0.5 * unit) * unit
    }

    /// Whether twice the area is at most [`DEGENERACY_RATIO`] times the squared longest
    /// edge (true when all edges have zero length).
    #[inline]
    pub(super) fn is_degenerate(&self) -> bool {
        let [p0, p1, p2] = self.0;
        let frame = Frame::new(p0, &[p1, p2]);
        let (s1, s2) = (frame.span(p1), frame.span(p2));
        let s3 = s2 - s1;
        let longest2 = s1.dot(s1).max(s2.dot(s2)).max(s3.dot(s3));
        let two_area = s1.cross(s2).length();
        two_area <= DEGENERACY_RATIO * longest2 || two_area.is_nan()
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
            (ci.vv * cj.cot() + ci.uu * ck.cot()) * 0.125 * ci.unit * ci.unit
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

    /// `Σ (p_i − p_0) × (p_{i+1} − p_0)` in span units², with the frame's unit. This is
    /// twice the vector area (Newell's vector), evaluated around the first vertex so that
    /// it does not lose digits far from the origin.
    fn double_vector_area(&self) -> (DVec3, f64) {
        let ps = &self.0;
        let frame = Frame::new(ps[0], &ps[1..]);
        let mut c = DVec3::ZERO;
        for w in ps[1..].windows(2) {
            c += frame.span(w[0]).cross(frame.span(w[1]));
        }
        (c, frame.unit())
    }

    /// The vector area: half of Newell's vector.
    pub(super) fn vector_area(&self) -> DVec3 {
        let (c, unit) = self.double_vector_area();
        c * (0.5 * unit) * unit
    }

    /// The area: half the length of Newell's vector.
    pub(super) fn area(&self) -> f64 {
        let (c, unit) = self.double_vector_area();
        c.length() * (0.5 * unit) * unit
    }

    /// Whether twice the area is at most [`DEGENERACY_RATIO`] times the squared longest
    /// edge.
    pub(super) fn is_degenerate(&self) -> bool {
        let ps = &self.0;
        let frame = Frame::new(ps[0], &ps[1..]);
        let mut longest2 = 0.0f64;
        let mut c = DVec3::ZERO;
        for (i, &p) in ps.iter().enumerate() {
            let e = frame.span(ps[(i + 1) % ps.len()]) - frame.span(p);
            longest2 = longest2.max(e.dot(e));
        }
        for w in ps[1..].windows(2) {
            c += frame.span(w[0]).cross(frame.span(w[1]));
        }
        let two_area = c.length();
        two_area <= DEGENERACY_RATIO * longest2 || two_area.is_nan()
    }
}

/// A compensated (Neumaier) sum: the error of each addition is carried along, so the
/// result is accurate to about one rounding however many terms are added.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sum {
    sum: f64,
    compensation: f64,
}

impl Sum {
    /// Adds a term.
    #[inline]
    pub(super) fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.compensation += (self.sum - t) + x;
        } else {
            self.compensation += (x - t) + self.sum;
        }
        self.sum = t;
    }

    /// The sum so far.
    #[inline]
    pub(super) fn value(&self) -> f64 {
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
        assert_eq!(f.unit(), 1.0);
        assert_eq!(f.span(DVec3::new(4.0, 6.0, 3.0)), DVec3::new(3.0, 4.0, 0.0));
    }

    #[test]
    fn frame_rescales_huge_and_tiny_differences() {
        let big = Frame::new(DVec3::ZERO, &[DVec3::new(3e200, 0.0, 0.0)]);
        let s = big.span(DVec3::new(3e200, 0.0, 0.0));
        assert!((1.0..2.0).contains(&s.x));
        assert_eq!(s.x * big.unit(), 3e200);

        let over = Frame::new(DVec3::splat(-1.5e308), &[DVec3::splat(1.5e308)]);
        let s = over.span(DVec3::splat(1.5e308));
        assert!(s.is_finite() && (1.0..2.0).contains(&s.x));
        assert!((s.x * over.unit()).is_infinite()); // 3e308 is not representable

        let tiny = Frame::new(DVec3::ZERO, &[DVec3::new(0.0, 5e-300, 0.0)]);
        let s = tiny.span(DVec3::new(0.0, 5e-300, 0.0));
        assert!((1.0..2.0).contains(&s.y));
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
