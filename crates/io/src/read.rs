//! Reading entry points.

use std::io::{BufRead, BufReader, Cursor, Seek, SeekFrom};
use std::path::Path;

use crate::error::IoError;
use crate::format::MeshFormat;
use crate::height_map::{HeightMap, sdf, x3p};
use crate::read_options::HeightMapReport;
use crate::read_options::{ReadOptions, ReadReport};
use crate::text::is_blank_stream;
use crate::{obj, off, ply, stl};
use beltrami_halfedge::MeshData;

/// Reads a mesh file, choosing the format by the extension (`.ply`, `.stl`, `.obj`,
/// `.off`, and the height maps `.x3p` and `.sdf`, triangulated by
/// [`HeightMap::to_mesh`] in metres; [`read_mesh_with`] reports the grid and its
/// invalid points).
///
/// The file is streamed: it is read through a buffer of 256 KiB, element by element,
/// and only the mesh itself (24 bytes per vertex, about 20 per triangle) is held, so
/// a 2 GB file needs no 2 GB buffer. Checks that need the whole file (counts against
/// the size, an ascii PLY's line count) make a separate pass over it. Coordinates are
/// returned as stored, in the file's units (no scaling). STL triangle soups are welded
/// with the default of [`ReadOptions`]: corners within [`Weld::DEFAULT_RELATIVE`] of
/// the bounding-box diagonal become one vertex (the rule: [`Weld`]; ids in order of
/// first appearance), and triangles that collapse are left out. [`read_mesh_with`]
/// chooses the tolerance and reports what welding did.
///
/// [`Weld`]: crate::Weld
/// [`Weld::DEFAULT_RELATIVE`]: crate::Weld::DEFAULT_RELATIVE
///
/// # Examples
/// ```
/// use beltrami_io::{read_mesh, write_mesh, MeshData, WriteOptions};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("tetrahedron.obj");
/// let mesh = MeshData::from(beltrami_halfedge::primitives::tetrahedron());
/// write_mesh(&path, &mesh, &WriteOptions::default())?;
/// assert_eq!(read_mesh(&path)?, mesh);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`IoError::Io`] when the file cannot be read; an unsupported extension; and the
/// errors of [`read_mesh_from`] for malformed content.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<MeshData, IoError> {
    let path = path.as_ref();
    read_mesh_with(path, &ReadOptions::default()).map(|(mesh, _)| mesh)
}

/// Reads a mesh file as [`read_mesh`] does, with `options`, and reports what the read
/// did beyond decoding (STL welding: the distance used, the vertices merged, the
/// triangles dropped).
///
/// # Examples
/// ```
/// use beltrami_io::{read_mesh_with, write_mesh, MeshData, ReadOptions, Weld, WriteOptions};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("cube.stl");
/// write_mesh(&path, &MeshData::from(beltrami_halfedge::primitives::cube()), &WriteOptions::default())?;
/// let exact = ReadOptions::new().weld(Weld::Exact);
/// let (mesh, report) = read_mesh_with(&path, &exact)?;
/// assert_eq!(mesh.positions.len(), 8);
/// assert_eq!((report.weld_distance, report.welded_vertices), (Some(0.0), 0));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`IoError::WeldTolerance`] for a negative, NaN or infinite tolerance (whatever the
/// format); otherwise those of [`read_mesh`].
pub fn read_mesh_with(
    path: impl AsRef<Path>,
    options: &ReadOptions,
) -> Result<(MeshData, ReadReport), IoError> {
    let path = path.as_ref();
    options.weld.check()?;
    let format = MeshFormat::from_path(path)?;
    let file = std::fs::File::open(path).map_err(IoError::io("read the file"))?;
    read_stream(BufReader::with_capacity(READ_BUFFER, file), format, options)
}

/// The read buffer of [`read_mesh`], in bytes.
const READ_BUFFER: usize = 256 << 10;

/// Reads a mesh in the given format from any buffered reader (a file, a byte slice,
/// a fuzzer's input).
///
/// A reader that cannot seek is read into memory first; [`read_mesh`] streams a file
/// instead. Both give the same mesh and the same errors for the same bytes.
///
/// # Examples
/// ```
/// use beltrami_io::{read_mesh_from, MeshFormat};
/// let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
/// let mesh = read_mesh_from(obj.as_bytes(), MeshFormat::Obj)?;
/// assert_eq!((mesh.positions.len(), mesh.faces.len()), (3, 1));
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
///
/// # Errors
/// Every malformed input gives an error, never a panic: [`IoError::Empty`] (also
/// for nothing but whitespace); syntax and header errors ([`IoError::Syntax`],
/// [`IoError::PlyHeader`], [`IoError::OffHeader`], …); a text file read as OBJ that
/// is none ([`IoError::NotObj`]); counts that the input cannot hold
/// ([`IoError::CountExceedsFile`], [`IoError::StlTriangleCount`],
/// [`IoError::Truncated`]) or more than the header declares
/// ([`IoError::TrailingData`]); non-finite coordinates
/// ([`IoError::NonFiniteCoordinate`], [`IoError::NonFiniteFacet`]); face indices that
/// name no vertex ([`IoError::FaceIndexOutOfRange`], [`IoError::NegativeIndex`],
/// [`IoError::ZeroIndex`]). Faces with fewer than three vertices or repeated
/// vertices are passed through, for the half-edge builder to report.
pub fn read_mesh_from<R: BufRead>(reader: R, format: MeshFormat) -> Result<MeshData, IoError> {
    read_mesh_from_with(reader, format, &ReadOptions::default()).map(|(mesh, _)| mesh)
}

/// Reads a mesh as [`read_mesh_from`] does, with `options`, and reports what the read
/// did beyond decoding (see [`read_mesh_with`]).
///
/// # Examples
/// ```
/// use beltrami_io::{read_mesh_from_with, MeshFormat, ReadOptions, Weld};
/// // Two triangles of an STL soup whose shared corners differ by round-off.
/// let stl = "solid s\n\
///     facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n\
///     facet normal 0 0 1\nouter loop\nvertex 1 2.7e-16 0\nvertex 1 1 0\nvertex 0 1.0000001 0\nendloop\nendfacet\n\
///     endsolid s\n";
/// let exact = ReadOptions::new().weld(Weld::Exact);
/// let (cracked, _) = read_mesh_from_with(stl.as_bytes(), MeshFormat::Stl, &exact)?;
/// assert_eq!(cracked.positions.len(), 6);
/// let (mesh, report) = read_mesh_from_with(stl.as_bytes(), MeshFormat::Stl, &ReadOptions::default())?;
/// assert_eq!((mesh.positions.len(), report.welded_vertices), (4, 2));
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
///
/// # Errors
/// [`IoError::WeldTolerance`] for a negative, NaN or infinite tolerance (whatever the
/// format); otherwise those of [`read_mesh_from`].
pub fn read_mesh_from_with<R: BufRead>(
    mut reader: R,
    format: MeshFormat,
    options: &ReadOptions,
) -> Result<(MeshData, ReadReport), IoError> {
    options.weld.check()?;
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(IoError::io("read the input"))?;
    read_stream(Cursor::new(&bytes[..]), format, options)
}

fn read_stream<R: BufRead + Seek>(
    reader: R,
    format: MeshFormat,
    options: &ReadOptions,
) -> Result<(MeshData, ReadReport), IoError> {
    let unwelded = |mesh| (mesh, ReadReport::default());
    match format {
        MeshFormat::Ply => ply::read_ply(reader, options.lenient),
        MeshFormat::Stl => stl::read_stl(reader, &options.weld),
        MeshFormat::Obj => obj::read_obj(reader).map(unwelded),
        MeshFormat::Off => off::read_off(reader).map(unwelded),
        MeshFormat::X3p | MeshFormat::Sdf => {
            let (map, checksum_mismatches) = read_height_map_stream(reader, format, options)?;
            let (mesh, stats) = map.to_mesh();
            let report = ReadReport {
                checksum_mismatches,
                height_map: Some(HeightMapReport {
                    nx: map.nx,
                    ny: map.ny,
                    dx: map.dx,
                    dy: map.dy,
                    unit: map.unit,
                    stats,
                }),
                ..ReadReport::default()
            };
            Ok((mesh, report))
        }
    }
}

fn read_height_map_stream<R: BufRead + Seek>(
    reader: R,
    format: MeshFormat,
    options: &ReadOptions,
) -> Result<(HeightMap, Vec<String>), IoError> {
    match format {
        MeshFormat::X3p => x3p::read_x3p(reader, options.lenient),
        MeshFormat::Sdf => sdf::read_sdf(reader).map(|map| (map, Vec::new())),
        _ => Err(IoError::NotHeightMapFormat { format }),
    }
}

/// Reads a height map file (`.x3p` or `.sdf`, by the extension) as its grid, in
/// metres as the files store it; NaN marks the invalid points.
///
/// X3P: `main.xml` must describe a surface (`FeatureType` `SUR`) of one layer
/// (`SizeZ` 1) on incremental x and y axes (`AxisType` `I`, the spacing in
/// `Increment`; their `Offset` is not applied: point `(0, 0)` is at the origin); the
/// heights are the point data (`bindata/data.bin` or the entry `PointDataLink` names,
/// little-endian `D` double, `F` float, `I` 16-bit or `L` 32-bit signed integers,
/// or an inline `DataList`) scaled by the z axis' `Increment` and shifted by its
/// `Offset` when given. Invalid points are NaN values, empty inline values, and the
/// points whose bit in the valid-point mask (`ValidPointsLink`, or
/// `bindata/valid.bin`; least significant bit first) is 0. The MD5 checksums of
/// `main.xml` (`md5checksum.hex`), of the point data and of the mask are verified
/// where the archive holds them.
///
/// SDF: the ascii (`aISO-1.0`, `aBCR-1.0`) and binary (`bISO-1.0`, `bBCR-1.0`)
/// variants; `NumPoints` values per profile along x, `NumProfiles` profiles, the
/// spacings `Xscale` and `Yscale` and the height unit `Zscale` in metres. Invalid
/// points are `BAD` in ascii; in binary NaN and `±MAX` floats (some writers mark
/// invalid points with `-f64::MAX`) and the most negative value of signed integer
/// types. The header fields that do not change the data
/// (`ManufacID`, the dates, `Zresolution`, `CheckType`) are not checked, and the
/// trailer after the data is not read.
///
/// # Examples
/// ```
/// use beltrami_io::{read_height_map, write_height_map, HeightMap, LengthUnit};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("scan.x3p");
/// let map = HeightMap::new(2, 2, 1e-6, 1e-6, vec![0.0, 1e-9, f64::NAN, 3e-9], LengthUnit::Metre)?;
/// write_height_map(&path, &map)?;
/// let back = read_height_map(&path)?;
/// assert_eq!((back.nx, back.ny, back.dx, back.invalid_points()), (2, 2, 1e-6, 1));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`IoError::NotHeightMapFormat`] for a mesh format, an unsupported extension;
/// [`IoError::Io`] when the file cannot be read; for X3P [`IoError::X3pArchive`]
/// (not a zip archive, truncated, no `main.xml`), [`IoError::X3pXml`] naming the
/// field and line of `main.xml` (missing or malformed fields, unknown `DataType`,
/// non-finite or non-positive increments, other feature types, absolute x or y axes,
/// several layers), [`IoError::X3pData`] (point data or mask of the wrong size,
/// missing entries, infinite heights) and [`IoError::Checksum`] (unless
/// [`ReadOptions::lenient`]); for SDF [`IoError::SdfHeader`] (no version line,
/// missing or malformed fields, counts the file cannot hold, compression),
/// [`IoError::SdfData`] (values that do not parse, more or fewer than
/// `NumPoints·NumProfiles`) and [`IoError::Truncated`] (binary). Counts are checked
/// against the size of the file (or of the archive's entries) before anything is
/// allocated for them.
pub fn read_height_map(path: impl AsRef<Path>) -> Result<HeightMap, IoError> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    if !format.is_height_map() {
        return Err(IoError::NotHeightMapFormat { format });
    }
    let file = std::fs::File::open(path).map_err(IoError::io("read the file"))?;
    let reader = BufReader::with_capacity(READ_BUFFER, file);
    read_height_map_stream(reader, format, &ReadOptions::default()).map(|(map, _)| map)
}

/// Reads a height map in `format` (X3P or SDF) from any reader, as
/// [`read_height_map`] reads a file.
///
/// # Examples
/// ```
/// use beltrami_io::{read_height_map_from, MeshFormat};
/// let sdf = "aISO-1.0\nNumPoints = 2\nNumProfiles = 1\nXscale = 1e-6\nYscale = 1e-6\n\
///     Zscale = 1e-9\nDataType = 7\n*\n2 BAD\n*\n";
/// let map = read_height_map_from(sdf.as_bytes(), MeshFormat::Sdf)?;
/// assert_eq!(map.height(0, 0), Some(2e-9));
/// assert_eq!(map.height(1, 0), None);
/// # Ok::<(), beltrami_io::IoError>(())
/// ```
///
/// # Errors
/// Those of [`read_height_map`].
pub fn read_height_map_from<R: BufRead>(
    mut reader: R,
    format: MeshFormat,
) -> Result<HeightMap, IoError> {
    if !format.is_height_map() {
        return Err(IoError::NotHeightMapFormat { format });
    }
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(IoError::io("read the input"))?;
    read_height_map_stream(Cursor::new(&bytes[..]), format, &ReadOptions::default())
        .map(|(map, _)| map)
}

/// Element counts a file declares before its elements (see [`declared_counts`]).
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeclaredCounts {
    /// The vertex count of a PLY or OFF header; `None` for an STL, whose vertices are
    /// known only after welding.
    pub vertices: Option<usize>,
    /// The face count of a PLY header (0 without a `face` element: the triangles of
    /// strips are known only once read) or an OFF header, or the triangle count of a
    /// binary STL.
    pub faces: usize,
}

/// The element counts a mesh file declares up front, read without decoding any
/// element: the header of a PLY or OFF file, the triangle count of a binary STL. `None` for
/// formats that declare nothing (OBJ, ascii STL, X3P and SDF), whose counts are known only after
/// a full pass. Meant for checks before a large read (memory limits); the counts
/// are what the file claims, which [`read_mesh`] verifies.
///
/// # Examples
/// ```
/// use beltrami_io::{declared_counts, write_mesh, MeshData, WriteOptions};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("cube.ply");
/// write_mesh(&path, &MeshData::from(beltrami_halfedge::primitives::cube()), &WriteOptions::default())?;
/// let counts = declared_counts(&path)?.expect("a ply header declares its counts");
/// assert_eq!((counts.vertices, counts.faces), (Some(8), 12));
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// An unsupported extension; [`IoError::Io`] when the file cannot be opened or read;
/// [`IoError::Empty`] for a file of nothing but whitespace; for PLY and OFF the
/// header errors of [`read_mesh`].
pub fn declared_counts(path: impl AsRef<Path>) -> Result<Option<DeclaredCounts>, IoError> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    let file = std::fs::File::open(path).map_err(IoError::io("open the file"))?;
    let length = file
        .metadata()
        .map_err(IoError::io("read the file's metadata"))?
        .len();
    if length == 0 {
        return Err(IoError::Empty);
    }
    let mut reader = BufReader::new(file);
    // Nothing but whitespace: empty, as the readers say (stops at the first other byte).
    if is_blank_stream(&mut reader)? {
        return Err(IoError::Empty);
    }
    reader
        .seek(SeekFrom::Start(0))
        .map_err(IoError::io("read the file"))?;
    match format {
        MeshFormat::Ply => ply::declared_counts(&mut reader).map(Some),
        MeshFormat::Stl => stl::declared_triangles(&mut reader, length).map(|triangles| {
            triangles.map(|faces| DeclaredCounts {
                vertices: None,
                faces,
            })
        }),
        MeshFormat::Off => off::declared_counts(&mut reader).map(Some),
        MeshFormat::Obj | MeshFormat::X3p | MeshFormat::Sdf => Ok(None),
    }
}
