//! STL writer, binary or ascii.

use std::io::{BufWriter, Write};

use glam::DVec3;

use super::{BINARY_HEADER, BINARY_TRIANGLE};
use crate::error::IoError;
use crate::format::{Encoding, MeshFormat};
use crate::validate::{check_faces, check_positions};
use beltrami_halfedge::MeshData;

/// The 80-byte binary header; it must not start with `solid`.
const HEADER_TEXT: &[u8] = b"binary STL written by beltrami";

/// Writes an STL file: faces fan-triangulated, facet normals from the geometry,
/// coordinates rounded to `f32`.
pub(crate) fn write_stl_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    encoding: Encoding,
) -> Result<(), IoError> {
    check_positions(&mesh.positions, true)?;
    check_faces(mesh, None)?;
    check_corners_apart(mesh)?;
    let count: usize = mesh.faces.iter().map(|f| f.len().saturating_sub(2)).sum();
    let mut out = BufWriter::new(writer);
    match encoding {
        Encoding::BinaryLittleEndian => {
            let count = u32::try_from(count).map_err(|_| IoError::TooManyTriangles {
                count,
                max: u32::MAX as usize,
            })?;
            write_binary(&mut out, mesh, count)
        }
        Encoding::Ascii => write_ascii(&mut out, mesh),
        Encoding::BinaryBigEndian => {
            return Err(IoError::UnsupportedEncoding {
                format: MeshFormat::Stl,
                encoding,
            });
        }
    }
    .and_then(|()| out.flush())
    .map_err(IoError::io("write the file"))
}

/// Every face's distinct corners stay apart in 32-bit floats: a reader joins corners
/// of equal coordinates, so two that round to one point (closer together than `f32`
/// resolves, or both below its smallest value) would come back as one vertex, and the
/// face would name it twice.
fn check_corners_apart(mesh: &MeshData) -> Result<(), IoError> {
    #[allow(
        clippy::cast_possible_truncation,
        reason = "the rounding is what is checked"
    )]
    // (`+ 0.0` makes −0 the reader's 0, as its welding does.)
    let single = |i: u32| {
        mesh.positions[i as usize]
            .as_vec3()
            .to_array()
            .map(|c| (c + 0.0).to_bits())
    };
    for (face, corners) in mesh.faces.iter().enumerate() {
        for (k, &a) in corners.iter().enumerate() {
            for &b in &corners[k + 1..] {
                if a != b && single(a) == single(b) {
                    return Err(IoError::CornersCoincide { face, a, b });
                }
            }
        }
    }
    Ok(())
}

/// The triangles of the fan around each face's first vertex, as corner positions.
fn triangles(mesh: &MeshData) -> impl Iterator<Item = [DVec3; 3]> + '_ {
    let p = |i: u32| mesh.positions[i as usize];
    mesh.faces.iter().flat_map(move |face| {
        face.windows(2)
            .skip(1)
            .map(move |w| [p(face[0]), p(w[0]), p(w[1])])
    })
}

/// The unit normal of a counter-clockwise triangle, zero when degenerate (and `0`
/// rather than `-0` in every component).
fn normal([a, b, c]: &[DVec3; 3]) -> DVec3 {
    (*b - *a).cross(*c - *a).normalize_or_zero() + DVec3::ZERO
}

#[allow(
    clippy::cast_possible_truncation,
    reason = "stl stores f32 by definition"
)]
fn to_f32(p: DVec3) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

fn write_binary<W: Write>(out: &mut W, mesh: &MeshData, count: u32) -> std::io::Result<()> {
    let mut header = [b' '; BINARY_HEADER];
    header[..HEADER_TEXT.len()].copy_from_slice(HEADER_TEXT);
    header[80..].copy_from_slice(&count.to_le_bytes());
    out.write_all(&header)?;
    let mut record = [0u8; BINARY_TRIANGLE];
    for triangle in triangles(mesh) {
        let vectors = [normal(&triangle), triangle[0], triangle[1], triangle[2]];
        for (k, value) in vectors.into_iter().flat_map(to_f32).enumerate() {
            record[4 * k..4 * k + 4].copy_from_slice(&value.to_le_bytes());
        }
        out.write_all(&record)?;
    }
    Ok(())
}

fn write_ascii<W: Write>(out: &mut W, mesh: &MeshData) -> std::io::Result<()> {
    writeln!(out, "solid beltrami")?;
    for triangle in triangles(mesh) {
        let [nx, ny, nz] = to_f32(normal(&triangle));
        writeln!(out, "  facet normal {nx} {ny} {nz}")?;
        writeln!(out, "    outer loop")?;
        for p in triangle {
            let [x, y, z] = to_f32(p);
            writeln!(out, "      vertex {x} {y} {z}")?;
        }
        writeln!(out, "    endloop")?;
        writeln!(out, "  endfacet")?;
    }
    writeln!(out, "endsolid beltrami")
}
