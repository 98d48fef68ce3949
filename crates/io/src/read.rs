//! Reading entry points.

use std::io::BufRead;
use std::path::Path;

use crate::error::IoError;
use crate::format::MeshFormat;
use crate::mesh::MeshData;
use crate::{obj, ply, stl};

/// Reads a mesh file, choosing the format by the extension (`.ply`, `.stl`, `.obj`).
///
/// The whole file is read into memory first. Coordinates are returned as stored, in
/// the file's units (no scaling). STL triangle soups are welded exactly (identical
/// `f32` coordinates become one vertex, `-0.0` equal to `0.0`; ids in order of first
/// appearance).
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
pub fn read_mesh(path: &Path) -> Result<MeshData, IoError> {
    let format = MeshFormat::from_path(path)?;
    let bytes = std::fs::read(path).map_err(IoError::io("read the file"))?;
    read_bytes(&bytes, format)
}

/// Reads a mesh in the given format from any buffered reader (a file, a byte slice,
/// a fuzzer's input).
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
/// Every malformed input gives an error, never a panic: [`IoError::Empty`];
/// syntax and header errors ([`IoError::Syntax`], [`IoError::PlyHeader`], …);
/// counts that the input cannot hold ([`IoError::CountExceedsFile`],
/// [`IoError::StlTriangleCount`], [`IoError::Truncated`]); non-finite coordinates
/// ([`IoError::NonFiniteCoordinate`], [`IoError::NonFiniteFacet`]); face indices that
/// name no vertex ([`IoError::FaceIndexOutOfRange`], [`IoError::NegativeIndex`],
/// [`IoError::ZeroIndex`]). Faces with fewer than three vertices or repeated
/// vertices are passed through, for the half-edge builder to report.
pub fn read_mesh_from<R: BufRead>(mut reader: R, format: MeshFormat) -> Result<MeshData, IoError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(IoError::io("read the input"))?;
    read_bytes(&bytes, format)
}

fn read_bytes(bytes: &[u8], format: MeshFormat) -> Result<MeshData, IoError> {
    match format {
        MeshFormat::Ply => ply::read_ply(bytes),
        MeshFormat::Stl => stl::read_stl(bytes),
        MeshFormat::Obj => obj::read_obj(bytes),
    }
}
