//! Height maps: heights on a regular grid, as areal surface instruments (confocal and
//! white-light interference microscopes, stylus profilers) store them, and the
//! triangle meshes they become.

mod mesh;
pub(crate) mod sdf;
pub(crate) mod x3p;

use std::fmt;

use crate::error::IoError;

/// The unit of a height map's spacings and heights.
///
/// X3P and SDF files store metres; the readers return [`LengthUnit::Metre`], and the
/// writers convert other units to metres.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LengthUnit {
    /// Metres (the unit of X3P and SDF files).
    #[default]
    Metre,
    /// Millimetres.
    Millimetre,
    /// Micrometres.
    Micrometre,
    /// Nanometres.
    Nanometre,
}

impl LengthUnit {
    /// The length of one unit in metres (`1e-6` for a micrometre).
    #[must_use]
    pub fn metres(self) -> f64 {
        match self {
            Self::Metre => 1.0,
            Self::Millimetre => 1e-3,
            Self::Micrometre => 1e-6,
            Self::Nanometre => 1e-9,
        }
    }

    /// The unit's symbol: `m`, `mm`, `µm` or `nm`.
    #[must_use]
    pub fn symbol(self) -> &'static str {
        match self {
            Self::Metre => "m",
            Self::Millimetre => "mm",
            Self::Micrometre => "µm",
            Self::Nanometre => "nm",
        }
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// Heights on a regular grid: point `(i, j)`, with `0 <= i < nx` along x and
/// `0 <= j < ny` along y, lies at `x = i·dx`, `y = j·dy` and has the height
/// `z[i + nx·j]` (row-major, x running fastest, as X3P and SDF store it). A NaN
/// height marks an invalid point (not measured, or flagged by the instrument).
///
/// [`HeightMap::to_mesh`] triangulates it; [`HeightMap::from_mesh`] recovers it from
/// a mesh whose vertices lie on a regular grid.
///
/// # Examples
/// ```
/// use beltrami_io::{HeightMap, LengthUnit};
/// // 3 × 2 points 1 µm apart, the last one not measured.
/// let z = vec![0.0, 1e-9, 2e-9, 1e-9, 0.0, f64::NAN];
/// let map = HeightMap::new(3, 2, 1e-6, 1e-6, z, LengthUnit::Metre)?;
/// assert_eq!(map.invalid_points(), 1);
/// assert_eq!(map.height(2, 0), Some(2e-9));
/// let (mesh, stats) = map.to_mesh();
/// // Only the cell whose four corners are valid becomes two triangles.
/// assert_eq!((mesh.faces.len(), stats.invalid_points), (2, 1));
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
#[non_exhaustive]
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Points along x (per row).
    pub nx: usize,
    /// Points along y (rows).
    pub ny: usize,
    /// The spacing along x, in [`unit`](Self::unit).
    pub dx: f64,
    /// The spacing along y, in [`unit`](Self::unit).
    pub dy: f64,
    /// The heights, `nx·ny` of them, row by row (`z[i + nx·j]`), in
    /// [`unit`](Self::unit); NaN marks an invalid point.
    pub z: Vec<f64>,
    /// The unit of `dx`, `dy` and `z`.
    pub unit: LengthUnit,
}

impl HeightMap {
    /// A height map of `nx × ny` points (see [`HeightMap`] for the layout).
    ///
    /// # Errors
    /// [`IoError::InvalidHeightMap`] when `z` does not hold `nx·ny` values, a spacing
    /// is not finite and positive, the grid's extent (`(nx − 1)·dx` or `(ny − 1)·dy`)
    /// is not finite, or a height is infinite (NaN is allowed: an invalid point).
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        z: Vec<f64>,
        unit: LengthUnit,
    ) -> Result<Self, IoError> {
        let map = Self {
            nx,
            ny,
            dx,
            dy,
            z,
            unit,
        };
        map.check()?;
        Ok(map)
    }

    /// Checks what [`HeightMap::new`] checks (the fields are public and may have
    /// changed since).
    ///
    /// # Errors
    /// [`IoError::InvalidHeightMap`], as for [`HeightMap::new`].
    pub fn check(&self) -> Result<(), IoError> {
        let invalid = |reason: String| Err(IoError::InvalidHeightMap { reason });
        if self.nx.checked_mul(self.ny) != Some(self.z.len()) {
            return invalid(format!(
                "{} heights for {} × {} points",
                self.z.len(),
                self.nx,
                self.ny
            ));
        }
        for (name, value) in [("dx", self.dx), ("dy", self.dy)] {
            if !(value.is_finite() && value > 0.0) {
                return invalid(format!(
                    "the spacing {name} is {value}, expected a finite positive number"
                ));
            }
        }
        // The points' coordinates are `i·dx` and `j·dy`: the largest must be finite.
        for (name, n, d) in [("x", self.nx, self.dx), ("y", self.ny, self.dy)] {
            let extent = n.saturating_sub(1) as f64 * d;
            if !extent.is_finite() {
                return invalid(format!(
                    "the grid's extent along {name}, ({n} − 1) × {d:e}, is not a finite number"
                ));
            }
        }
        if let Some(k) = self.z.iter().position(|z| z.is_infinite()) {
            return invalid(format!(
                "the height of point ({}, {}) is {}",
                k % self.nx,
                k / self.nx,
                self.z[k]
            ));
        }
        Ok(())
    }

    /// The height at point `(i, j)`: `None` outside the grid or at an invalid point.
    #[must_use]
    pub fn height(&self, i: usize, j: usize) -> Option<f64> {
        if i >= self.nx || j >= self.ny {
            return None;
        }
        self.z.get(i + self.nx * j).copied().filter(|z| !z.is_nan())
    }

    /// The number of invalid (NaN) points.
    #[must_use]
    pub fn invalid_points(&self) -> usize {
        self.z.iter().filter(|z| z.is_nan()).count()
    }

    /// This height map in `unit`: spacings and heights multiplied by the ratio of the
    /// units (exact only when it is 1).
    ///
    /// # Errors
    /// [`IoError::InvalidHeightMap`] when the converted map is not valid (see
    /// [`HeightMap::check`]): a conversion to a smaller unit can take a spacing, the
    /// grid's extent or a height beyond the largest `f64`, one to a larger unit can
    /// take a spacing to zero.
    pub fn to_unit(&self, unit: LengthUnit) -> Result<Self, IoError> {
        if unit == self.unit {
            return Ok(self.clone());
        }
        let scale = self.unit.metres() / unit.metres();
        let map = Self {
            dx: self.dx * scale,
            dy: self.dy * scale,
            z: self.z.iter().map(|z| z * scale).collect(),
            unit,
            ..*self
        };
        map.check().map_err(|e| match e {
            IoError::InvalidHeightMap { reason } => IoError::InvalidHeightMap {
                reason: format!("in {}: {reason}", unit.symbol()),
            },
            other => other,
        })?;
        Ok(map)
    }
}

pub use mesh::GridStats;
