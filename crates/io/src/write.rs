//! Writing entry points.

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomic;
use crate::error::IoError;
use crate::format::{Encoding, MeshFormat, VertexAttributes, WriteOptions};
use crate::height_map::{HeightMap, LengthUnit, sdf, x3p};
use crate::{obj, off, ply, stl};
use beltrami_halfedge::MeshData;

/// Writes a mesh file, choosing the format by the extension (`.ply`, `.stl`, `.obj`,
/// `.off`, and the height maps `.x3p` and `.sdf` for a mesh on a regular grid).
///
/// The file is replaced atomically: the data goes to a temporary file in the same
/// directory, which is flushed to disk and then renamed over `path`. On any error
/// nothing is left behind and an existing file is untouched.
///
/// Per format:
/// - PLY: see [`write_ply`] (no attributes).
/// - STL: binary unless [`Encoding::Ascii`]. STL stores `f32` coordinates, so writing
///   is lossy for `f64` values that are not exactly representable. Polygons are
///   fan-triangulated around their first vertex (faces with fewer than three
///   vertices produce no triangle), facet normals are computed from the triangles.
///   The precision option is ignored.
/// - OBJ: always text; `v` lines with the shortest decimal that reads back to the
///   same `f64` (or `f32` with [`Precision::Single`](crate::Precision::Single)),
///   1-based `f` lines. The encoding option is ignored.
/// - OFF: always text; `OFF`, the counts `vertices faces 0`, `x y z` lines with the
///   shortest decimal as for OBJ, 0-based `n i0 … i(n-1)` face lines. The encoding
///   option is ignored.
/// - X3P and SDF: the height map whose grid the vertices lie on, in metres
///   ([`HeightMap::from_mesh`]: a mesh read from such a file, or one whose vertices
///   moved along z only), written as [`write_height_map`] does; grid points without
///   a vertex are invalid. The options are ignored.
///
/// # Examples
/// ```
/// use beltrami_io::{read_mesh, write_mesh, Encoding, MeshData, WriteOptions};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("cube.stl");
/// let cube = MeshData::from(beltrami_halfedge::primitives::cube());
/// let ascii = WriteOptions::default().encoding(Encoding::Ascii);
/// write_mesh(&path, &cube, &ascii)?;
/// // The cube's coordinates are exact in f32, and welding restores the 8 corners.
/// assert_eq!(read_mesh(&path)?.positions.len(), 8);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// An unsupported extension; [`IoError::UnsupportedEncoding`] for big-endian STL;
/// [`IoError::NonFiniteCoordinate`] and [`IoError::FaceIndexOutOfRange`] for a mesh
/// no reader would accept; [`IoError::CoordinateOutOfRange`] when a coordinate
/// exceeds `f32` (STL, single precision); [`IoError::TooManyTriangles`] for a binary
/// STL; [`IoError::NotAGrid`] for X3P and SDF when the vertices are not on a regular
/// grid; [`IoError::Io`] when the file cannot be created, written or renamed.
pub fn write_mesh(
    path: impl AsRef<Path>,
    mesh: &MeshData,
    options: &WriteOptions,
) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    check_encoding(format, options.encoding)?;
    write_atomic(path, |file| write_mesh_to(file, mesh, format, options))
}

/// Writes a mesh in the given format to any writer (see [`write_mesh`] for what each
/// format stores). The writer is buffered internally.
///
/// # Examples
/// ```
/// use beltrami_io::{write_mesh_to, MeshData, MeshFormat, WriteOptions};
/// let mesh = MeshData::from(beltrami_halfedge::primitives::triangle());
/// let mut obj = Vec::new();
/// write_mesh_to(&mut obj, &mesh, MeshFormat::Obj, &WriteOptions::default())?;
/// assert!(String::from_utf8_lossy(&obj).ends_with("v 0 1 0\nf 1 2 3\n"));
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
///
/// # Errors
/// As [`write_mesh`], except that nothing is atomic here: on an error the writer
/// may have received part of the data.
pub fn write_mesh_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    format: MeshFormat,
    options: &WriteOptions,
) -> Result<(), IoError> {
    check_encoding(format, options.encoding)?;
    match format {
        MeshFormat::Ply => ply::write_ply_to(writer, mesh, &VertexAttributes::default(), options),
        MeshFormat::Stl => stl::write_stl_to(writer, mesh, options.encoding),
        MeshFormat::Obj => obj::write_obj_to(writer, mesh, options.precision),
        MeshFormat::Off => off::write_off_to(writer, mesh, options.precision),
        MeshFormat::X3p | MeshFormat::Sdf => {
            let map = HeightMap::from_mesh(mesh, LengthUnit::Metre)?;
            write_height_map_to(writer, &map, format)
        }
    }
}

/// Writes a height map file, choosing the format by the extension (`.x3p` or `.sdf`),
/// replacing the file atomically as [`write_mesh`] does. Spacings and heights are
/// written in metres (converted from [`HeightMap::unit`]).
///
/// - X3P: `main.xml` (a surface on incremental x and y axes, heights as doubles),
///   `bindata/data.bin` (little-endian `f64`, NaN at invalid points), the mask
///   `bindata/valid.bin` when a point is invalid, MD5 checksums of all three in
///   `main.xml` and `md5checksum.hex`; deflated, without time stamps, so the same
///   map gives the same bytes.
/// - SDF: ascii (`aISO-1.0`), `DataType = 7`, `Zscale = 1`, the heights as the
///   shortest decimals that read back to the same `f64`, `BAD` at invalid points;
///   the header's dates are the current time.
///
/// Both read back bit for bit (heights and spacings) when the map is in metres.
///
/// # Examples
/// ```
/// use beltrami_io::{read_height_map, write_height_map, HeightMap, LengthUnit};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let map = HeightMap::new(3, 1, 2.5e-6, 2.5e-6, vec![1e-9, f64::NAN, -0.1e-9], LengthUnit::Metre)?;
/// for name in ["scan.x3p", "scan.sdf"] {
///     write_height_map(dir.path().join(name), &map)?;
///     let back = read_height_map(dir.path().join(name))?;
///     assert_eq!(back.height(2, 0), Some(-0.1e-9));
///     assert_eq!(back.height(1, 0), None);
/// }
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// An unsupported extension; [`IoError::NotHeightMapFormat`] for a mesh format;
/// [`IoError::InvalidHeightMap`] for a map that breaks the invariants of
/// [`HeightMap::new`]; [`IoError::Io`] when the file cannot be created, written or
/// renamed.
pub fn write_height_map(path: impl AsRef<Path>, map: &HeightMap) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    if !format.is_height_map() {
        return Err(IoError::NotHeightMapFormat { format });
    }
    write_atomic(path, |file| write_height_map_to(file, map, format))
}

/// Writes a height map in `format` (X3P or SDF) to any writer, as
/// [`write_height_map`] writes a file.
///
/// # Errors
/// As [`write_height_map`], except that nothing is atomic here.
pub fn write_height_map_to<W: Write>(
    writer: W,
    map: &HeightMap,
    format: MeshFormat,
) -> Result<(), IoError> {
    match format {
        MeshFormat::X3p => x3p::write_x3p_to(writer, map),
        MeshFormat::Sdf => sdf::write_sdf_to(writer, map),
        _ => Err(IoError::NotHeightMapFormat { format }),
    }
}

/// Writes a PLY file with per-vertex attributes, whatever the extension of `path`,
/// replacing the file atomically as [`write_mesh`] does.
///
/// The vertex element holds `x y z` (`double`, or `float` with
/// [`Precision::Single`](crate::Precision::Single)), then one `double` property per
/// scalar attribute, then `red green blue` (`uchar`) when colours are given. Faces
/// are `list uchar int vertex_indices` (`list uint …` when a face has more than 255
/// vertices). Binary double precision round-trips every bit; ascii writes the
/// shortest decimal that reads back to the same value, so it round-trips too.
///
/// # Examples
/// ```
/// use beltrami_io::{write_ply, MeshData, VertexAttributes, WriteOptions};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let mesh = MeshData::from(beltrami_halfedge::primitives::triangle());
/// let attributes = VertexAttributes {
///     scalars: vec![("deviation".to_owned(), vec![0.0, 0.25, -0.5])],
///     colors: None,
/// };
/// write_ply(&dir.path().join("deviation.ply"), &mesh, &attributes, &WriteOptions::default())?;
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`IoError::AttributeLength`] when an attribute does not have one value per
/// vertex; [`IoError::AttributeName`] for a name that is not a PLY identifier, is
/// used twice or is one of `x y z red green blue`; [`IoError::NonFiniteAttribute`]
/// for NaN or infinite attribute values in ascii; the mesh errors and
/// [`IoError::Io`] of [`write_mesh`].
pub fn write_ply(
    path: impl AsRef<Path>,
    mesh: &MeshData,
    attributes: &VertexAttributes,
    options: &WriteOptions,
) -> Result<(), IoError> {
    let path = path.as_ref();
    write_atomic(path, |file| write_ply_to(file, mesh, attributes, options))
}

/// Writes a PLY file with per-vertex attributes to any writer (see [`write_ply`]).
///
/// # Examples
/// ```
/// use beltrami_io::{write_ply_to, Encoding, MeshData, VertexAttributes, WriteOptions};
/// let mesh = MeshData::from(beltrami_halfedge::primitives::triangle());
/// let ascii = WriteOptions::default().encoding(Encoding::Ascii);
/// let mut ply = Vec::new();
/// write_ply_to(&mut ply, &mesh, &VertexAttributes::default(), &ascii)?;
/// assert!(String::from_utf8_lossy(&ply).ends_with("end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
///
/// # Errors
/// As [`write_ply`], except that nothing is atomic here.
pub fn write_ply_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    attributes: &VertexAttributes,
    options: &WriteOptions,
) -> Result<(), IoError> {
    ply::write_ply_to(writer, mesh, attributes, options)
}

fn check_encoding(format: MeshFormat, encoding: Encoding) -> Result<(), IoError> {
    if format == MeshFormat::Stl && encoding == Encoding::BinaryBigEndian {
        return Err(IoError::UnsupportedEncoding { format, encoding });
    }
    Ok(())
}
