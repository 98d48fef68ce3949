//! Vectors of lanes for the batched geometry queries: `N` three-dimensional vectors in
//! structure-of-arrays form, each coordinate a [`wide`] lane type (packed SSE2 on the
//! x86-64 baseline, plain arrays elsewhere). Lane by lane the operations are glam's,
//! operation by operation: IEEE add, subtract, multiply, divide and square root are
//! correctly rounded per lane, there is no fused multiply-add (Rust never contracts) and
//! no reassociation, so every lane has the bits of the scalar expression.

use std::ops::{Add, Mul, Sub};

/// Three coordinates, each a lane type `T`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct V3<T> {
    pub(crate) x: T,
    pub(crate) y: T,
    pub(crate) z: T,
}

impl<T: Copy + Sub<Output = T>> Sub for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, rhs: Self) -> Self {
        Self {
            x: self.x - rhs.x,
            y: self.y - rhs.y,
            z: self.z - rhs.z,
        }
    }
}

impl<T> V3<T>
where
    T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>,
{
    /// `(x·x') + (y·y') + (z·z')`, in that order (glam's `DVec3::dot`).
    #[inline(always)]
    pub(crate) fn dot(self, rhs: Self) -> T {
        self.x * rhs.x + self.y * rhs.y + self.z * rhs.z
    }

    /// glam's `DVec3::cross`, operation by operation.
    #[inline(always)]
    pub(crate) fn cross(self, rhs: Self) -> Self {
        Self {
            x: self.y * rhs.z - rhs.y * self.z,
            y: self.z * rhs.x - rhs.z * self.x,
            z: self.x * rhs.y - rhs.x * self.y,
        }
    }
}
