//! The orthographic camera: a viewing direction and an up vector.

use glam::DVec3;

use crate::VizError;

/// An orthographic view: the direction from the camera towards the object, and the
/// world direction that appears upwards in the image (its component across the viewing
/// direction).
///
/// # Examples
/// ```
/// use beltrami_viz::render::View;
/// use beltrami_halfedge::DVec3;
/// let side = View::from_side();
/// assert_eq!(side.direction, DVec3::Y);
/// assert_eq!(side.up, DVec3::Z);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// From the camera towards the object (need not be unit length).
    pub direction: DVec3,
    /// The world direction shown upwards; must not be parallel to `direction`.
    pub up: DVec3,
}

/// The camera's orthonormal frame: image right, image up, and forward (into the image).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Basis {
    pub(crate) right: DVec3,
    pub(crate) up: DVec3,
    pub(crate) forward: DVec3,
}

impl View {
    /// A view along `direction` with `up` upwards.
    #[must_use]
    pub fn new(direction: DVec3, up: DVec3) -> Self {
        Self { direction, up }
    }

    /// Looking down the −z axis, +y upwards, +x to the right.
    #[must_use]
    pub fn from_above() -> Self {
        Self::new(DVec3::NEG_Z, DVec3::Y)
    }

    /// Looking along +y (from the −y side), +z upwards, +x to the right.
    #[must_use]
    pub fn from_side() -> Self {
        Self::new(DVec3::Y, DVec3::Z)
    }

    /// A three-quarter view from the front right and above (about 33° elevation),
    /// with the thinnest axis of the bounding box of `positions` upwards: +z for a
    /// height field over the xy-plane and for shapes about as thick in every direction.
    /// Non-finite positions are ignored.
    #[must_use]
    pub fn default_for(positions: &[DVec3]) -> Self {
        let mut bounds: Option<(DVec3, DVec3)> = None;
        for p in positions.iter().filter(|p| p.is_finite()) {
            let (lo, hi) = bounds.get_or_insert((*p, *p));
            *lo = lo.min(*p);
            *hi = hi.max(*p);
        }
        let extent = bounds.map_or(DVec3::ONE, |(lo, hi)| hi - lo).to_array();
        // The thinnest axis goes up only when it is clearly the thinnest.
        let mut up_axis = 2;
        for k in 0..3 {
            let others = (0..3)
                .filter(|&j| j != k)
                .map(|j| extent[j])
                .fold(0f64, f64::max);
            if extent[k] < 0.5 * others && extent[k] < extent[up_axis] {
                up_axis = k;
            }
        }
        let axis = |k: usize| {
            let mut a = [0.0; 3];
            a[k % 3] = 1.0;
            DVec3::from_array(a)
        };
        let (x, y, z) = (axis(up_axis + 1), axis(up_axis + 2), axis(up_axis));
        let camera = 0.55 * x - 1.0 * y + 0.75 * z;
        Self::new(-camera, z)
    }

    /// The camera frame.
    ///
    /// # Errors
    /// [`VizError::Invalid`] when a vector is zero or not finite, or they are parallel.
    pub(crate) fn basis(&self) -> Result<Basis, VizError> {
        let invalid = |reason: &str| VizError::Invalid {
            what: "view",
            reason: format!("{reason} (direction {}, up {})", self.direction, self.up),
        };
        if !self.direction.is_finite() || !self.up.is_finite() {
            return Err(invalid("vectors must be finite"));
        }
        let forward = self
            .direction
            .try_normalize()
            .ok_or_else(|| invalid("direction must not be zero"))?;
        let up = self
            .up
            .try_normalize()
            .ok_or_else(|| invalid("up must not be zero"))?;
        let right = forward.cross(up);
        if right.length() < 1e-9 {
            return Err(invalid("up must not be parallel to the direction"));
        }
        let right = right.normalize();
        Ok(Basis {
            right,
            up: right.cross(forward),
            forward,
        })
    }
}

impl Default for View {
    /// [`View::from_side`].
    fn default() -> Self {
        Self::from_side()
    }
}
