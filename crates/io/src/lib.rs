//! # beltrami-io
//!
//! Readers and writers for the mesh files of surface metrology: Stanford PLY (ascii,
//! binary little- and big-endian), STL (binary and ascii), Wavefront OBJ and Geomview
//! OFF; and for the height maps of areal instruments, X3P (ISO 25178-72) and SDF (ISO
//! 25178-71), as a [`HeightMap`] or as its triangulated grid.
//!
//! A file is read into a [`MeshData`]: `f64` positions and a [`PolygonList`] of faces,
//! ready for [`HalfedgeMesh::from_polygons`]. Coordinates are whatever the file
//! holds — typically millimetres for scans — and are never scaled.
//!
//! ## Quick start
//!
//! ```
//! use beltrami_io::{read_mesh, write_mesh, MeshData, WriteOptions};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("torus.ply");
//!
//! let torus = MeshData::from(beltrami_halfedge::primitives::torus(2.0, 0.5, 12, 8));
//! // Binary little-endian, double precision: exact to the last bit.
//! write_mesh(&path, &torus, &WriteOptions::default())?;
//!
//! let back = read_mesh(&path)?;
//! assert_eq!(back, torus);
//! let mesh = beltrami_halfedge::HalfedgeMesh::from_polygons(back.positions.len(), back.faces.iter())?;
//! assert_eq!(mesh.n_faces(), 12 * 8 * 2);
//! # Ok(())
//! # }
//! ```
//!
//! ## Formats
//!
//! | format | read | written by [`write_mesh`] |
//! |---|---|---|
//! | PLY | ascii, binary little- and big-endian; `x y z` of any numeric type; faces from the `vertex_indices` or `vertex_index` lists of the `face` element and of triangle strips (`tristrips`, `-1` between strips); other elements and properties ignored; exactly what the header declares (after the last element, only whitespace) | `x y z` as `double` (or `float`), faces as `list uchar int vertex_indices`; [`write_ply`] adds scalar attributes and colours |
//! | STL | binary or ascii, told apart by content; the triangle soup is welded, by default within `1e-6` of the bounding-box diagonal ([`Weld`]; [`read_mesh_with`] chooses and reports) | binary (or ascii); `f32` coordinates, polygons fan-triangulated |
//! | OBJ | `v` and `f` (all corner forms, negative indices), `\` line continuations; the other statements of the specification (`vt`, `vn`, `l`, `p`, `g`, …) ignored; a file without `v` lines that holds a word that is no OBJ statement is refused (another format under the wrong name) | `v` and `f` lines |
//! | OFF | ascii, keyword `OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`, … or none; counts on the keyword line or the next; values after `x y z` and after a face's indices (normals, colours, texture coordinates) ignored; `#` comments; exactly the declared vertices and faces; binary OFF refused | `OFF`, the counts, `x y z` lines and 0-based `n i0 … i(n-1)` face lines |
//! | X3P | a zip archive: `main.xml` (a `SUR` feature on incremental x and y axes, one layer), the point data in `bindata/data.bin` (or the entry linked; `D`, `F`, `I`, `L`) or inline, the mask of valid points, MD5 checksums verified; as a mesh by [`HeightMap::to_mesh`], in metres, invalid points left out as holes ([`read_height_map`] for the grid) | from a mesh that is a height map — its vertices on a regular grid, its faces tiling the grid's whole cells, facing up ([`HeightMap::from_mesh`]) — or from a [`HeightMap`] by [`write_height_map`]: doubles, the mask when a point is invalid, every checksum |
//! | SDF | ascii (`aISO-1.0`, `aBCR-1.0`) and binary (`bISO-1.0`, `bBCR-1.0`), `BAD` and NaN invalid points; as X3P | ascii, doubles in metres |
//!
//! Text may end its lines with `\n`, `\r\n` or a lone `\r` (a PLY header needs one of
//! the first two), and may start with a UTF-8 byte order mark. A file of nothing but
//! whitespace is [`IoError::Empty`]; a file with a valid header and no vertices is an
//! empty mesh.
//!
//! ## Guarantees
//!
//! - **Exact round trips.** Binary PLY in double precision keeps every bit; ascii PLY,
//!   OBJ and OFF write the shortest decimal that reads back to the same `f64`. STL holds
//!   `f32` by definition, so it is exact only for coordinates that are.
//! - **Validation.** Every reader rejects non-finite coordinates and face indices that
//!   name no vertex, with the vertex or face (and the line in text formats). Faces
//!   with fewer than three vertices or repeated vertices pass through for the
//!   half-edge builder to report.
//! - **No panics, no runaway allocation.** Malformed input gives an [`IoError`].
//!   Element counts in headers are checked against the size of the file before
//!   anything is allocated, so a header claiming billions of vertices in a small file
//!   fails at once.
//! - **Streaming.** [`read_mesh`] reads a file through a fixed buffer and holds only
//!   the mesh (and one text line), never the whole file (X3P holds its decompressed
//!   `main.xml` and point data, whose sizes are checked against the grid first); [`declared_counts`] reads a
//!   file's declared counts without reading its elements.
//! - **Atomic writes.** [`write_mesh`], [`write_ply`], [`write_height_map`] and
//!   [`write_bytes_atomic`] write a temporary file beside the target, flush it to
//!   disk, rename it over the target and flush the directory (the flushes unless
//!   [`set_flush_to_disk`]`(false)`); on any error the target is untouched and the temporary
//!   file removed, and a killed process leaves the old file or the new one, whole.
//!   [`stage_mesh`], [`stage_ply`] and [`stage_bytes`] stop before the rename, so that
//!   a command with several outputs replaces all of them or none
//!   ([`StagedFile::commit`]); [`remove_staged_files`] lets a signal handler remove
//!   the temporary files before the process exits. A symbolic link is written
//!   through to its target.
//!
//! [`HalfedgeMesh::from_polygons`]: beltrami_halfedge::HalfedgeMesh::from_polygons

mod atomic;
mod error;
mod extension;
mod format;
mod height_map;
mod memory;
mod obj;
mod off;
mod ply;
mod read;
mod read_options;
mod stl;
mod text;
mod validate;
mod write;

pub use atomic::{
    StagedDir, StagedFile, check_writable, commit_staged, flushes_to_disk, remove_staged_files,
    resolve_target, set_flush_to_disk, stage_bytes, stage_dir, stage_mesh, stage_ply, stage_with,
    with_flush_to_disk, write_bytes_atomic,
};
pub use beltrami_halfedge::MeshData;
pub use beltrami_halfedge::PolygonList;
pub use error::IoError;
pub use format::{Encoding, MeshFormat, Precision, VertexAttributes, WriteOptions};
pub use height_map::{GridStats, HeightMap, LengthUnit};
pub use memory::{address_space_left, available_in_meminfo, available_memory};
pub use read::{
    DeclaredCounts, declared_counts, read_height_map, read_height_map_from, read_mesh,
    read_mesh_from, read_mesh_from_with, read_mesh_with,
};
pub use read_options::{HeightMapReport, ReadOptions, ReadReport, Weld};
pub use write::{
    write_height_map, write_height_map_to, write_mesh, write_mesh_to, write_ply, write_ply_to,
};
