//! Options for the readers, and what a read did beyond decoding.

use crate::error::IoError;
use crate::height_map::{GridStats, LengthUnit};

/// How the corners of an STL triangle soup become shared vertices.
///
/// STL stores each triangle with its own three corners; a reader must decide which
/// corners are the same vertex. Exact welding merges identical coordinates only. CAD
/// exporters often write the same point with different round-off (`2.7e-16` where
/// another triangle has `0`, or one `f32` step apart), and exact welding then opens a
/// crack along every such edge: welding within a tolerance closes them.
///
/// The rule within a tolerance `t` (a distance in the file's units): corners are
/// first welded exactly, which numbers the vertices in order of first appearance in
/// the file. Then, in that order, each vertex joins the earliest vertex kept so far
/// whose Euclidean distance to it is at most `t`, or is kept itself when there is
/// none. A kept vertex keeps its position (no averaging) and the kept vertices are
/// renumbered in their order; the result depends on the file alone, never on hashing
/// or threads. Chains do not merge through: with `|ab| ≤ t`, `|bc| ≤ t` and
/// `|ac| > t`, `b` joins `a` and `c` stays. `t = 0` is exact welding.
///
/// Only STL is welded; PLY, OBJ and OFF store shared vertices and are read as stored.
///
/// # Examples
/// ```
/// use beltrami_io::{ReadOptions, Weld};
/// let exact = ReadOptions::new().weld(Weld::Exact);
/// assert_eq!(ReadOptions::default().weld, Weld::Relative(1e-6));
/// assert_ne!(exact, ReadOptions::default());
/// ```
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Weld {
    /// Identical coordinates only: the same `f32` bit patterns, `-0.0` equal to `0.0`.
    Exact,
    /// Within this fraction of the diagonal of the bounding box of the corners (after
    /// exact welding). Scale-free: the right choice when the units are unknown.
    Relative(f64),
    /// Within this distance, in the file's units (e.g. millimetres).
    Absolute(f64),
}

impl Weld {
    /// The default relative tolerance, `1e-6` of the bounding-box diagonal.
    ///
    /// An STL coordinate is an `f32`, whose spacing is `2^-23` (about `1.2e-7`) of its
    /// magnitude: round-off that moves a corner by a few such steps on a part whose
    /// coordinates are of the size of its diagonal stays within `1e-6` of the
    /// diagonal, and coordinates such as `2.7e-16` for `0` are far within. Real
    /// features are far larger: a mesh of a million even triangles has edges of about
    /// `1e-3` of its diagonal, a thousand times the tolerance (it takes 10¹² triangles
    /// for edges to shrink to `1e-6`). On a 100 mm part the tolerance is 0.1 µm,
    /// below what any STL exporter resolves on purpose.
    pub const DEFAULT_RELATIVE: f64 = 1e-6;

    /// The weld distance for corners whose bounding box has the diagonal `diagonal`
    /// (in the file's units): 0 for [`Weld::Exact`].
    ///
    /// # Errors
    /// [`IoError::WeldTolerance`] when the tolerance is negative, NaN or infinite.
    pub fn distance(&self, diagonal: f64) -> Result<f64, IoError> {
        self.check()?;
        Ok(match *self {
            Self::Exact => 0.0,
            Self::Relative(fraction) => fraction * diagonal,
            Self::Absolute(distance) => distance,
        })
    }

    /// Checks that the tolerance is finite and not negative.
    ///
    /// # Errors
    /// [`IoError::WeldTolerance`] otherwise.
    pub fn check(&self) -> Result<(), IoError> {
        match *self {
            Self::Exact => Ok(()),
            Self::Relative(value) | Self::Absolute(value) => {
                if value.is_finite() && value >= 0.0 {
                    Ok(())
                } else {
                    Err(IoError::WeldTolerance { value })
                }
            }
        }
    }
}

impl Default for Weld {
    /// [`Weld::Relative`] with [`Weld::DEFAULT_RELATIVE`].
    fn default() -> Self {
        Self::Relative(Self::DEFAULT_RELATIVE)
    }
}

/// Options for [`read_mesh_with`](crate::read_mesh_with) and
/// [`read_mesh_from_with`](crate::read_mesh_from_with).
///
/// # Examples
/// ```
/// use beltrami_io::{ReadOptions, Weld};
/// // A command-line `--weld-tolerance 0.01` in millimetres:
/// let options = ReadOptions::new().weld(Weld::Absolute(0.01));
/// assert_eq!(options.weld, Weld::Absolute(0.01));
/// ```
#[non_exhaustive]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// How STL corners are welded (the default: [`Weld::Relative`] with
    /// [`Weld::DEFAULT_RELATIVE`]).
    pub weld: Weld,
    /// Read a PLY file that holds more than its header declares (values beyond an
    /// element's properties on an ascii line, lines or bytes after the last element)
    /// for what the header declares, ignore the rest and count it in the
    /// [`ReadReport`], instead of failing (the default `false`). Some exporters write
    /// such files; the declared data are read as declared, nothing is guessed. Also
    /// reads an X3P archive whose MD5 checksums do not match, and lists the
    /// mismatches in the report.
    pub lenient: bool,
}

impl ReadOptions {
    /// The defaults: [`Weld::Relative`] with [`Weld::DEFAULT_RELATIVE`], not lenient.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// These options with [`weld`](Self::weld) set to `weld`.
    #[must_use]
    pub fn weld(mut self, weld: Weld) -> Self {
        self.weld = weld;
        self
    }

    /// These options with [`lenient`](Self::lenient) set to `yes`.
    #[must_use]
    pub fn lenient(mut self, yes: bool) -> Self {
        self.lenient = yes;
        self
    }

    /// The old name of [`weld`](Self::weld).
    #[deprecated(note = "renamed to `weld`, like the other options types' setters")]
    #[must_use]
    pub fn with_weld(self, weld: Weld) -> Self {
        self.weld(weld)
    }

    /// The old name of [`lenient`](Self::lenient).
    #[deprecated(note = "renamed to `lenient`, like the other options types' setters")]
    #[must_use]
    pub fn with_lenient(self, yes: bool) -> Self {
        self.lenient(yes)
    }
}

/// What a read did to the file's content beyond decoding it.
///
/// # Examples
/// ```
/// use beltrami_io::{read_mesh_from_with, MeshFormat, ReadOptions};
/// let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
/// let (_, report) = read_mesh_from_with(obj.as_bytes(), MeshFormat::Obj, &ReadOptions::default())?;
/// assert_eq!(report.weld_distance, None); // OBJ is not welded
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
#[non_exhaustive]
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadReport {
    /// The weld distance used, in the file's units: `Some(0.0)` for exact welding,
    /// `None` for formats that are not welded (all but STL).
    pub weld_distance: Option<f64>,
    /// The number of vertices merged into others by welding within the tolerance,
    /// beyond exact welding (0 for exact welding).
    pub welded_vertices: usize,
    /// The triangles, as 0-based facet numbers in file order, that welding within the
    /// tolerance collapsed (two of their corners became one vertex): they are left
    /// out of the mesh. A triangle with repeated corners in the file itself is kept,
    /// for the half-edge builder to report.
    pub dropped_faces: Vec<usize>,
    /// With [`ReadOptions::lenient`]: the ascii PLY lines whose values beyond the
    /// element's properties were ignored, as 1-based line numbers.
    pub lines_with_extra_values: Vec<usize>,
    /// With [`ReadOptions::lenient`]: the non-blank ascii lines after the last element
    /// that were ignored.
    pub ignored_trailing_lines: usize,
    /// With [`ReadOptions::lenient`]: the bytes after the last element of a binary PLY
    /// that were ignored.
    pub ignored_trailing_bytes: u64,
    /// With [`ReadOptions::lenient`]: the MD5 checksums of an X3P archive that did not
    /// match their entries (one message each), which otherwise fail the read with
    /// [`IoError::Checksum`].
    pub checksum_mismatches: Vec<String>,
    /// For a height map (X3P, SDF): its grid and what became of its points; `None`
    /// for mesh formats.
    pub height_map: Option<HeightMapReport>,
}

/// The grid of a height map read as a mesh, and what became of its points.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightMapReport {
    /// Points along x.
    pub nx: usize,
    /// Points along y.
    pub ny: usize,
    /// The spacing along x, in [`unit`](Self::unit).
    pub dx: f64,
    /// The spacing along y, in [`unit`](Self::unit).
    pub dy: f64,
    /// The unit of the mesh's coordinates (metres for X3P and SDF).
    pub unit: LengthUnit,
    /// What the triangulation left out: invalid points, and valid points in no
    /// whole cell.
    pub stats: GridStats,
}

impl ReadReport {
    /// Whether anything in the file was ignored by a lenient read.
    #[must_use]
    pub fn ignored_anything(&self) -> bool {
        !self.lines_with_extra_values.is_empty()
            || self.ignored_trailing_lines > 0
            || self.ignored_trailing_bytes > 0
            || !self.checksum_mismatches.is_empty()
    }
}
