//! Exact integrals of a linear field over a triangle, per unit area, and the in-plane
//! gradient; plus the compensated sum and power-of-two scaling they are accumulated with.
//!
//! With barycentric coordinates `λ₁, λ₂, λ₃` on a triangle `T` of area `A`,
//! `∫_T λ₁^p λ₂^q λ₃^s dA = 2A p! q! s! / (p + q + s + 2)!`. Expanding
//! `r = a λ₁ + b λ₂ + c λ₃` to the power `k` with the multinomial theorem, the
//! multinomial coefficients cancel the factorials of the monomial integrals, leaving
//! `∫_T r^k dA = 2A k! / (k + 2)! · h_k(a, b, c)`, where `h_k` is the complete homogeneous
//! symmetric polynomial of degree `k` (the sum of all monomials of degree `k`).

use beltrami_halfedge::DVec3;

/// `(1/A) ∫_T r^k dA` for `k = 1, 2, 3, 4` of the linear interpolant of the vertex values
/// `[a, b, c]`:
///
/// - `k = 1`: `(a + b + c) / 3`;
/// - `k = 2`: `h₂ / 6` with `h₂ = a² + b² + c² + ab + bc + ca = ((a+b)² + (b+c)² + (c+a)²) / 2`
///   (evaluated in the second form, a sum of squares, so it is never negative);
/// - `k = 3`: `h₃ / 10` with `h₃ = Σ a³ + Σ a²b (six terms) + abc`;
/// - `k = 4`: `h₄ / 15` with `h₄` the sum of the fifteen monomials of degree 4.
pub(super) fn mean_powers([a, b, c]: [f64; 3]) -> [f64; 4] {
    let (ab, bc, ca) = (a + b, b + c, c + a);
    let h2 = 0.5 * (ab * ab + bc * bc + ca * ca);
    [
        (a + b + c) / 3.0,
        h2 / 6.0,
        complete_homogeneous(3, a, b, c) / 10.0,
        complete_homogeneous(4, a, b, c).max(0.0) / 15.0,
    ]
}

/// `h_k(a, b, c) = Σ_{i+j+l=k} a^i b^j c^l`.
fn complete_homogeneous(k: i32, a: f64, b: f64, c: f64) -> f64 {
    let mut sum = 0.0;
    for i in 0..=k {
        for j in 0..=k - i {
            sum += a.powi(i) * b.powi(j) * c.powi(k - i - j);
        }
    }
    sum
}

/// `(1/A) ∫_T |r| dA` of the linear interpolant of `[a, b, c]`, exactly.
///
/// When the values do not change sign it is `|a + b + c| / 3`. Otherwise the zero line
/// cuts off the corner of the one vertex `l` whose sign differs from the other two
/// (`o₁`, `o₂`; a zero value goes with either side): the corner triangle has the fractions
/// `t₁ = l / (l − o₁)` and `t₂ = l / (l − o₂)` of the two edges at `l`, area `t₁ t₂ A`,
/// and `r` falls linearly from `l` to 0 over it, so `∫_corner |r| = |l| t₁ t₂ A / 3`. With
/// `S = ∫_T r dA` and `σ` the sign of `l`, the rest of the triangle holds
/// `∫ |r| = ∫_corner |r| − σ S`, hence
/// `(1/A) ∫_T |r| dA = 2 |l| t₁ t₂ / 3 − σ (a + b + c) / 3`.
pub(super) fn mean_abs([a, b, c]: [f64; 3]) -> f64 {
    let values = [a, b, c];
    let positive = values.iter().filter(|&&v| v > 0.0).count();
    let negative = values.iter().filter(|&&v| v < 0.0).count();
    let sum = (a + b + c) / 3.0;
    if positive == 0 || negative == 0 {
        return sum.abs();
    }
    // The lone vertex: the only positive one, or else the only negative one.
    let lone = |is_lone: fn(f64) -> bool| {
        let k = values.iter().position(|&v| is_lone(v)).unwrap_or(0);
        (values[k], values[(k + 1) % 3], values[(k + 2) % 3])
    };
    let (l, o1, o2) = if positive == 1 {
        lone(|v| v > 0.0)
    } else {
        lone(|v| v < 0.0)
    };
    // l and the others have opposite signs (or the others are 0), so both fractions lie
    // in (0, 1] and no denominator vanishes.
    let t1 = l / (l - o1);
    let t2 = l / (l - o2);
    let sigma = l.signum();
    2.0 * l.abs() * t1 * t2 / 3.0 - sigma * sum
}

/// The gradient of the linear interpolant of `[ra, rb, rc]` on the triangle `[pa, pb, pc]`,
/// in the triangle's own plane, scaled: the result `(g, s)` has `∇r = g · s`. `None` when
/// the triangle has no area or its edges overflow.
///
/// With `e₁ = p_b − p_a`, `e₂ = p_c − p_a` and `N = e₁ × e₂` (twice the vector area),
/// `∇r = [(r_c − r_a) N × e₁ − (r_b − r_a) N × e₂] / |N|²`; it lies in the plane and
/// satisfies `∇r · e₁ = r_b − r_a`, `∇r · e₂ = r_c − r_a`. The edges are first divided
/// by a power of two (exact) so that `|N|²` neither overflows nor underflows.
pub(super) fn gradient([pa, pb, pc]: [DVec3; 3], [ra, rb, rc]: [f64; 3]) -> Option<(DVec3, f64)> {
    let (e1, e2) = (pb - pa, pc - pa);
    let largest = e1.abs().max_element().max(e2.abs().max_element());
    if !(largest.is_finite() && largest > 0.0) {
        return None;
    }
    let scale = pow2_inverse(largest);
    let (e1, e2) = (e1 * scale, e2 * scale);
    let n = e1.cross(e2);
    let nn = n.length_squared();
    if nn == 0.0 {
        return None;
    }
    // With edges multiplied by `scale`, the formula yields ∇r / scale.
    let g = ((rc - ra) * n.cross(e1) - (rb - ra) * n.cross(e2)) / nn;
    Some((g, scale))
}

/// The power of two `2^-e` with `m · 2^-e` in `[1, 2)`, for finite positive `m`; exact to
/// multiply by. For `m` below about `2^-1023` the factor is capped at `2^1023`.
pub(super) fn pow2_inverse(m: f64) -> f64 {
    let bits = m.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let exponent = if biased == 0 {
        // Subnormal: the exponent of the leading mantissa bit.
        let mantissa = bits & ((1 << 52) - 1);
        63 - mantissa.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    };
    let e = (-exponent).min(1023);
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        // 2^-1023 or 2^-1024: subnormal, still exact.
        f64::from_bits(1 << (e + 1074))
    }
}

pub(super) use crate::sum::Sum;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_of_a_constant() {
        assert_eq!(mean_powers([2.0; 3]), [2.0, 4.0, 8.0, 16.0]);
        assert_eq!(mean_abs([-2.0; 3]), 2.0);
    }

    #[test]
    fn abs_with_one_lone_vertex() {
        // (1, −1, −1): the positive corner has area A/4 and mean 1/3 there; the rest holds
        // 5/12 of A in magnitude. Total A/2.
        assert_eq!(mean_abs([1.0, -1.0, -1.0]), 0.5);
        assert_eq!(mean_abs([-1.0, 1.0, 1.0]), 0.5);
        // A zero value on the zero line: (1, 0, −1) is symmetric, the two halves hold 1/6 each.
        assert!((mean_abs([1.0, 0.0, -1.0]) - 1.0 / 3.0).abs() < 1e-16);
    }

    #[test]
    fn pow2_inverse_brings_into_one_two() {
        for m in [1.0, 1.5, 3.0, 1e-300, 1e300, 5e-324, f64::MAX] {
            let s = pow2_inverse(m);
            let scaled = m * s;
            assert!(
                (1.0..2.0).contains(&scaled) || m < 1e-307,
                "{m} -> {scaled}"
            );
            assert_eq!(s.log2().fract(), 0.0, "power of two");
        }
    }
}
