//! File formats and write options ([`MeshFormat::from_path`] is in `extension.rs`).

use std::fmt;

/// A mesh file format.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Stanford PLY (ascii, binary little-endian or binary big-endian).
    Ply,
    /// STL (binary or ascii): a triangle soup, welded on read.
    Stl,
    /// Wavefront OBJ (text): positions and polygon faces only.
    Obj,
    /// Geomview OFF (text): positions and polygon faces; colours, normals and texture
    /// coordinates ignored.
    Off,
    /// X3P (ISO 25178-72): a height map in a zip archive, read as a triangulated grid
    /// ([`HeightMap::to_mesh`](crate::HeightMap::to_mesh)).
    X3p,
    /// SDF (ISO 25178-71, ascii or binary): a height map, read as a triangulated grid.
    Sdf,
}

impl MeshFormat {
    /// The format's name in capitals, as `beltrami info` prints it: `PLY`, `STL`, `OBJ`,
    /// `OFF`, `X3P` or `SDF`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Ply => "PLY",
            Self::Stl => "STL",
            Self::Obj => "OBJ",
            Self::Off => "OFF",
            Self::X3p => "X3P",
            Self::Sdf => "SDF",
        }
    }

    /// Whether the format stores a height map (X3P, SDF) rather than a mesh.
    #[must_use]
    pub fn is_height_map(self) -> bool {
        matches!(self, Self::X3p | Self::Sdf)
    }

    /// Why a mesh whose repair split `split_vertices` vertices off (cut non-manifold
    /// edges, pinched vertices, opened edges) cannot be written in this format, or
    /// `None` when it can: STL keeps no vertex indices, so a copy split off, still at its
    /// original's position, is joined to it again when the file is read, undoing the
    /// repair. The one message of the commands and the Python package.
    ///
    /// # Examples
    /// ```
    /// use beltrami_io::MeshFormat;
    /// assert!(MeshFormat::Stl.loses_split_vertices(2).unwrap().contains("the 2 vertices"));
    /// assert_eq!(MeshFormat::Stl.loses_split_vertices(0), None);
    /// assert_eq!(MeshFormat::Ply.loses_split_vertices(2), None);
    /// ```
    #[must_use]
    pub fn loses_split_vertices(self, split_vertices: usize) -> Option<String> {
        (self == Self::Stl && split_vertices > 0).then(|| {
            format!(
                "an STL file keeps no vertex indices, so the {split_vertices} {} the repair split off would be joined again when it is read; write .ply, .obj or .off",
                if split_vertices == 1 { "vertex" } else { "vertices" }
            )
        })
    }

    /// What writing a mesh with `vertices_in_no_face` vertices that no face uses in this
    /// format leaves out, or `None` when nothing is left out: an STL file stores
    /// triangles only, so such vertices are not written (PLY, OBJ and OFF keep them).
    /// The one note of the commands and the Python package.
    ///
    /// # Examples
    /// ```
    /// use beltrami_io::MeshFormat;
    /// let note = MeshFormat::Stl.drops_vertices_in_no_face(1).unwrap();
    /// assert!(note.contains("the 1 vertex in no face is not written"));
    /// assert_eq!(MeshFormat::Stl.drops_vertices_in_no_face(0), None);
    /// assert_eq!(MeshFormat::Ply.drops_vertices_in_no_face(3), None);
    /// ```
    #[must_use]
    pub fn drops_vertices_in_no_face(self, vertices_in_no_face: usize) -> Option<String> {
        (self == Self::Stl && vertices_in_no_face > 0).then(|| {
            let (noun, verb) = if vertices_in_no_face == 1 {
                ("vertex", "is")
            } else {
                ("vertices", "are")
            };
            format!(
                "an STL file stores triangles only: the {vertices_in_no_face} {noun} in no face {verb} not written (.ply, .obj and .off keep them)"
            )
        })
    }
}

impl fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Ply => "ply",
            Self::Stl => "stl",
            Self::Obj => "obj",
            Self::Off => "off",
            Self::X3p => "x3p",
            Self::Sdf => "sdf",
        })
    }
}

/// How a file is encoded when written.
///
/// PLY supports all three. STL supports [`Ascii`](Self::Ascii) and
/// [`BinaryLittleEndian`](Self::BinaryLittleEndian) (binary STL is little-endian by
/// definition). OBJ, OFF and SDF are always text, X3P always binary; they ignore the
/// encoding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Human-readable text; numbers in their shortest exact decimal form.
    Ascii,
    /// Binary, least significant byte first (the default: compact and exact).
    #[default]
    BinaryLittleEndian,
    /// Binary, most significant byte first.
    BinaryBigEndian,
}

impl fmt::Display for Encoding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Ascii => "ascii",
            Self::BinaryLittleEndian => "binary little-endian",
            Self::BinaryBigEndian => "binary big-endian",
        })
    }
}

/// The floating-point precision of written coordinates.
///
/// STL always stores 32-bit floats and ignores this setting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Precision {
    /// 64-bit floats: coordinates are written exactly (the default).
    #[default]
    Double,
    /// 32-bit floats: half the size, coordinates rounded to the nearest `f32`. OBJ and OFF
    /// write the shortest decimal that identifies that `f32` (at most 9 significant
    /// digits); read back as `f64` it is not the `f32` itself but rounds to it.
    Single,
}

/// Options for the writers.
///
/// The default writes binary little-endian with double precision, which round-trips
/// every coordinate bit for bit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct WriteOptions {
    /// Text or binary (see [`Encoding`] for what each format supports).
    pub encoding: Encoding,
    /// Coordinate precision (PLY, OBJ and OFF).
    pub precision: Precision,
}

impl WriteOptions {
    /// Sets [`encoding`](Self::encoding): text or binary.
    #[must_use]
    pub fn encoding(mut self, encoding: Encoding) -> Self {
        self.encoding = encoding;
        self
    }

    /// Sets [`precision`](Self::precision): the coordinate precision.
    #[must_use]
    pub fn precision(mut self, precision: Precision) -> Self {
        self.precision = precision;
        self
    }
}

/// Per-vertex data written beside the positions by [`write_ply`](crate::write_ply).
///
/// Every attribute must hold exactly one value per vertex.
///
/// # Examples
/// ```
/// use beltrami_io::VertexAttributes;
/// let attributes = VertexAttributes {
///     scalars: vec![("deviation".to_owned(), vec![0.0, 0.01, -0.02])],
///     colors: Some(vec![[255, 0, 0], [0, 255, 0], [0, 0, 255]]),
/// };
/// assert_eq!(attributes.scalars.len(), 1);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexAttributes {
    /// Named scalar fields, each written as `property double <name>`. Names must be
    /// PLY identifiers (a letter or `_`, then letters, digits, `_` or `-`).
    pub scalars: Vec<(String, Vec<f64>)>,
    /// Vertex colours, written as `red green blue` (`uchar`).
    pub colors: Option<Vec<[u8; 3]>>,
}
