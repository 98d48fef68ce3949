//! The geometry of a collapse: quadrics, normal cones and triangle shape measures.

use std::f64::consts::PI;

use beltrami_halfedge::DVec3;
use glam::DMat3;

/// A symmetric 4 × 4 quadric `Q(x) = yᵀAy + 2bᵀy + c` of `y = x − origin`, with the
/// total weight of its planes.
///
/// The coefficients are kept relative to an origin near the mesh (the centre of the
/// bounding box of its vertices in a face) because `c` holds the square of each plane's offset from the origin: for a
/// part of size 1 placed 10⁷ from the origin (a machine's coordinates) the terms of
/// `Q(x)` are 10¹⁴ and their rounding (10⁻²) swamps errors of 10⁻⁶. Every quadric that
/// is added to another must have the same origin.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Quadric {
    /// `A` as `xx, xy, xz, yy, yz, zz`.
    pub(super) a: [f64; 6],
    pub(super) b: DVec3,
    pub(super) c: f64,
    pub(super) weight: f64,
    /// The point the coefficients are relative to.
    pub(super) origin: DVec3,
}

impl Quadric {
    /// The zero quadric relative to `origin`.
    pub(super) fn zero(origin: DVec3) -> Self {
        Self {
            origin,
            ..Self::default()
        }
    }

    /// `w (n·(x − p))²`: the plane through `p` with unit normal `n`, relative to
    /// `origin`.
    pub(super) fn plane_through(n: DVec3, p: DVec3, w: f64, origin: DVec3) -> Self {
        Self {
            origin,
            ..Self::plane(n, -n.dot(p - origin), w)
        }
    }

    /// `w (n·x + d)²`, relative to the origin 0.
    pub(super) fn plane(n: DVec3, d: f64, w: f64) -> Self {
        Self {
            a: [
                w * n.x * n.x,
                w * n.x * n.y,
                w * n.x * n.z,
                w * n.y * n.y,
                w * n.y * n.z,
                w * n.z * n.z,
            ],
            b: n * (w * d),
            c: w * d * d,
            weight: w,
            origin: DVec3::ZERO,
        }
    }

    /// `w |x − p|²` relative to `origin`, of plane weight 0 (a pull, not a plane: it
    /// does not count in the mean of [`Quadric::rms`]).
    pub(super) fn point(p: DVec3, w: f64, origin: DVec3) -> Self {
        let y = p - origin;
        Self {
            a: [w, 0.0, 0.0, w, 0.0, w],
            b: -w * y,
            c: w * y.length_squared(),
            weight: 0.0,
            origin,
        }
    }

    pub(super) fn add(&mut self, o: &Self) {
        debug_assert_eq!(self.origin, o.origin, "quadrics of different origins");
        for (a, b) in self.a.iter_mut().zip(o.a) {
            *a += b;
        }
        self.b += o.b;
        self.c += o.c;
        self.weight += o.weight;
    }

    pub(super) fn sum(&self, o: &Self) -> Self {
        let mut s = *self;
        s.add(o);
        s
    }

    pub(super) fn matrix(&self) -> DMat3 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        DMat3::from_cols(
            DVec3::new(xx, xy, xz),
            DVec3::new(xy, yy, yz),
            DVec3::new(xz, yz, zz),
        )
    }

    /// `Q(p)`, clamped at 0 against rounding.
    pub(super) fn eval(&self, p: DVec3) -> f64 {
        let y = p - self.origin;
        let q = y.dot(self.matrix() * y) + 2.0 * self.b.dot(y) + self.c;
        q.max(0.0)
    }

    /// `sqrt(Q(p) / weight)`: the weighted RMS distance to the planes.
    pub(super) fn rms(&self, p: DVec3) -> f64 {
        self.rms_of(self.eval(p))
    }

    /// [`Quadric::rms`] for the value `error = Q(p)`.
    pub(super) fn rms_of(&self, error: f64) -> f64 {
        if self.weight > 0.0 {
            (error / self.weight).sqrt()
        } else {
            0.0
        }
    }

    /// The minimiser of `Q`, `−A⁻¹b`, when `A` is well conditioned: the symmetric
    /// adjugate once, its first column giving the determinant.
    pub(super) fn minimiser(&self) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let scale = self.a.iter().fold(0.0, |s, x| larger(s, x.abs()));
        if scale <= 0.0 {
            return None;
        }
        // The cofactors of the symmetric matrix (the adjugate is symmetric too).
        let c_xx = yy * zz - yz * yz;
        let c_xy = xz * yz - xy * zz;
        let c_xz = xy * yz - xz * yy;
        let det = xx * c_xx + xy * c_xy + xz * c_xz;
        if det.abs() <= 1e-10 * scale * scale * scale {
            return None;
        }
        let c_yy = xx * zz - xz * xz;
        let c_yz = xy * xz - xx * yz;
        let c_zz = xx * yy - xy * xy;
        let b = -self.b;
        let x = DVec3::new(
            c_xx * b.x + c_xy * b.y + c_xz * b.z,
            c_xy * b.x + c_yy * b.y + c_yz * b.z,
            c_xz * b.x + c_yz * b.y + c_zz * b.z,
        ) / det;
        let x = x + self.origin;
        x.is_finite().then_some(x)
    }
}

/// A cone of unit normals: its axis and half opening angle (radians).
#[derive(Clone, Copy, Debug)]
pub(super) struct NormalCone {
    pub(super) center: DVec3,
    pub(super) angle: f64,
}

impl NormalCone {
    pub(super) fn new(n: DVec3) -> Self {
        Self {
            center: n,
            angle: 0.0,
        }
    }

    /// The smallest cone around both (pmp-library's `NormalCone::merge`).
    pub(super) fn merge(self, other: Self) -> Self {
        let dp = self.center.dot(other.center).clamp(-1.0, 1.0);
        if dp > 0.99999 {
            Self {
                center: self.center,
                angle: self.angle.max(other.angle),
            }
        } else if dp < -0.99999 {
            Self {
                center: self.center,
                angle: PI,
            }
        } else {
            let center_angle = dp.acos();
            let min_angle = (-self.angle).min(center_angle - other.angle);
            let max_angle = self.angle.max(center_angle + other.angle);
            let angle = 0.5 * (max_angle - min_angle);
            let axis_angle = 0.5 * (min_angle + max_angle);
            let center = (self.center * (center_angle - axis_angle).sin()
                + other.center * axis_angle.sin())
                / center_angle.sin();
            Self {
                center: center.try_normalize().unwrap_or(self.center),
                angle,
            }
        }
    }
}

/// The larger of `a` and `b`; `a` when `b` is NaN. The same as `f64::max` for the
/// values here (never a NaN `a`), in one instruction rather than its NaN handling:
/// these run in the hottest loops of the decimation.
#[inline]
pub(super) fn larger(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// The smaller of `a` and `b`; `a` when `b` is NaN (see [`larger`]).
#[inline]
pub(super) fn smaller(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// The raw normal `(b − a) × (c − a)` (twice the area).
pub(super) fn cross(t: [DVec3; 3]) -> DVec3 {
    (t[1] - t[0]).cross(t[2] - t[0])
}

/// `ℓ²_max √3 / (4A)`: 1 for an equilateral triangle, infinite for a degenerate one.
pub(super) fn aspect_ratio(t: [DVec3; 3]) -> f64 {
    let l2 = (t[1] - t[0])
        .length_squared()
        .max((t[2] - t[1]).length_squared())
        .max((t[0] - t[2]).length_squared());
    let twice_area = cross(t).length();
    if twice_area > 0.0 {
        l2 * 3f64.sqrt() / (2.0 * twice_area)
    } else {
        f64::INFINITY
    }
}

/// The square of `4A / (√3 ℓ²_max)`, the inverse of [`aspect_ratio`]: 1 for an
/// equilateral triangle, 0 for a degenerate one. (Squared to save a square root per
/// triangle; the caller takes one of the worst.)
pub(super) fn shape_quality_squared(t: [DVec3; 3]) -> f64 {
    let l2 = larger(
        larger(
            (t[1] - t[0]).length_squared(),
            (t[2] - t[1]).length_squared(),
        ),
        (t[0] - t[2]).length_squared(),
    );
    if l2 > 0.0 {
        4.0 * cross(t).length_squared() / (3.0 * l2 * l2)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate::test_rng::Lcg;

    #[test]
    fn the_minimiser_solves_the_quadric_system() {
        let mut rng = Lcg(11);
        for _ in 0..200 {
            // A sum of a few planes through random points, as a vertex's quadric is.
            let mut q = Quadric::default();
            for _ in 0..4 {
                let n =
                    DVec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5).normalize();
                let p = DVec3::new(rng.unit(), rng.unit(), rng.unit());
                q.add(&Quadric::plane(n, -n.dot(p), 0.1 + rng.unit()));
            }
            let Some(x) = q.minimiser() else {
                continue;
            };
            // The gradient 2(Ax + b) vanishes at the minimiser ...
            let residual = q.matrix() * x + q.b;
            assert!(
                residual.length() <= 1e-9 * (1.0 + q.b.length()),
                "{residual}"
            );
            // ... and the minimum is no larger than nearby values.
            for d in [DVec3::X, DVec3::Y, DVec3::Z] {
                assert!(q.eval(x) <= q.eval(x + 1e-3 * d) + 1e-12);
                assert!(q.eval(x) <= q.eval(x - 1e-3 * d) + 1e-12);
            }
        }
        // A single plane leaves the system singular: no minimiser.
        assert!(Quadric::plane(DVec3::Z, 0.0, 1.0).minimiser().is_none());
    }
}
